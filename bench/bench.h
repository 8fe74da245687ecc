/* bench/bench.h - benchmarks behind `polarcam bench NAME`. Each prints a table (and JSON with
 * --json) of ratios against a baseline measured in the same run. */
#ifndef POLARCAM_BENCH_H
#define POLARCAM_BENCH_H

int pc_bench_physics(int argc, char **argv);
int pc_bench_demosaic(int argc, char **argv);
int pc_bench_render(int argc, char **argv);
int pc_bench_devices(int argc, char **argv);
int pc_bench_calib(int argc, char **argv);
int pc_bench_dataset(int argc, char **argv);

#endif
