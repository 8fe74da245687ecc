/* tools/commands.h - the polarcam commands, one file per command (cmd_<name>.c defines
 * cli_cmd_<name>). */
#ifndef CLI_TOOLS_COMMANDS_H
#define CLI_TOOLS_COMMANDS_H

typedef int (*cli_command_fn)(int argc, char **argv);

typedef struct cli_command {
	const char *name;
	const char *summary;
	cli_command_fn run;
} cli_command;

#define CLI_COMMANDS(X)                                                                            \
	X(demo, "render the default scene, run the pipeline, write pictures and a report")         \
	X(pbrdf, "evaluate the polarized BRDF Mueller matrix (JSON lines)")                        \
	X(decompose, "Lu-Chipman decomposition of Mueller matrices (JSON lines)")                  \
	X(figures, "reproduce the seed paper's figures 2-11 as CSV and PNG")                       \
	X(render, "render a scene to raw mosaic frames and ground truth")                          \
	X(dataset, "scene-family datasets: sharded, resumable, verified (SHA-256)")                \
	X(demosaic, "demosaic a raw polarizer mosaic to four analyser channels")                   \
	X(process, "raw mosaic -> Stokes, DoLP, AoLP and pictures")                                \
	X(eval, "score demosaicking methods against ground truth")                                 \
	X(mueller, "per-pixel Mueller matrices from frame sequences, D/R/Delta maps")              \
	X(calibrate, "calibrate a camera: dark, flat, analyser matrices, ECM (one file)")          \
	X(devices, "list cameras: Aravis, V4L2, libcamera, USB3 Vision")                           \
	X(capture, "record frames from a source URI")                                              \
	X(view, "live window of S0, DoLP and AoLP")                                                \
	X(serve, "serve the simulator as a GigE Vision camera")                                    \
	X(bench, "benchmarks: physics, demosaic, render, devices, calib, dataset")

#define CLI_COMMAND_DECL(name, summary) int cli_cmd_##name(int argc, char **argv);
CLI_COMMANDS(CLI_COMMAND_DECL)
#undef CLI_COMMAND_DECL

#endif
