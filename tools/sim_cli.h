/* tools/sim_cli.h - what the simulator commands (render, demo, mueller, bench render) share:
 * the simulator's description as JSON, the states file, progress adapters. */
#ifndef CLI_TOOLS_SIM_CLI_H
#define CLI_TOOLS_SIM_CLI_H

#include <jansson.h>

#include "cli.h"
#include "polarcam/demosaic.h"
#include "polarcam/mueller_imaging.h"
#include "polarcam/sim.h"

/* {"scene": <document>, "scene_name", "seed", "effects": [names], "sensor": {figures},
 *  "supersampling", "states": {...}} */
json_t *pc_sim_describe(const pc_sim *sim, const pc_scene *scene);

/* The effect names of a PC_FX_* set as a JSON array. */
json_t *pc_sim_effects_json(unsigned effects);

/* states.json for `polarcam mueller --states`: frame order, PSG Stokes vectors, PSA Mueller
 * matrices, the mosaic and the analyser rows (docs/scene-format.md, "Frame sequences"). */
json_t *pc_sim_states_json(const pc_sim *sim);

/* A pc_sim_progress_fn drawing a cli_progress (user = cli_progress*) with an offset. */
typedef struct pc_sim_progress_adapter {
	cli_progress *bar;
	uint64_t base;
} pc_sim_progress_adapter;
void pc_sim_progress_cb(void *user, uint64_t done, uint64_t total);



/* sizeof-checked path join: DIR/NAME into buf (PC_EINVAL when too long). */
int pc_path_join(char *buf, size_t size, const char *dir, const char *name);

#endif
