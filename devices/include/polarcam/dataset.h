/* polarcam/dataset.h - datasets of rendered scene-family samples (docs/dataset.md): sharded,
 * resumable, verifiable.
 *
 * A dataset directory holds
 *   dataset.json                     the family spec as used, the seed and the sample count
 *   meshes/NAME                      the mesh files the spec draws (sample scenes refer to them)
 *   samples/NNNNNNNN/                one directory per sample, made in a temporary directory
 *                                    and renamed into place: it exists complete or not at all
 *       raw_000000.png ...           raw frames at the sensor's bit depth
 *       truth_stokes.npy             ground-truth Stokes radiance (float32 or float16)
 *       scene.json                   the sample's complete scene: re-renders alone with
 *                                    `polarcam render scene.json --seed SIM_SEED`
 *       meta.json                    what the sample is (index, seeds, sensor, exposure,
 *                                    statistics) and the scene
 *   manifests/shard-I-of-M.jsonl     one line per sample a shard made: SHA-256 and size of
 *                                    every file
 *   manifest.jsonl                   the merged manifest (pc_dataset_merge), sorted by index
 *
 * Sample i is a pure function of (spec, seed, i), so the dataset does not depend on the
 * sharding, the thread count or interruptions: a run skips the samples that exist and redoes
 * the partial ones. SHA-256 comes from nettle (Debian's nettle-dev).
 */
#ifndef POLARCAM_DATASET_H
#define POLARCAM_DATASET_H

#include <stdbool.h>
#include <stdint.h>

#include "polarcam/export.h"
#include "polarcam/progress.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pc_dataset_options {
	const char *spec;       /* family spec file */
	const char *dir;        /* dataset directory (created if missing) */
	uint64_t seed;          /* family seed */
	uint64_t count;         /* samples 0 .. count − 1 */
	uint32_t shard, shards; /* this run makes the samples i with i mod shards = shard */
	uint32_t width, height; /* resolution override (0, 0: the spec's) */
	int threads;            /* per sample (0 = all cores) */
	uint64_t stop_after;    /* stop after making this many samples (0 = no limit; tests) */
	pc_progress progress;   /* phase "samples": this shard's samples done (made or skipped)
	                         * out of its total; non-zero stops the run (PC_ECANCELED) after
	                         * the sample in hand, every finished sample kept */
} pc_dataset_options;

typedef struct pc_dataset_result {
	uint64_t total;           /* samples of this shard */
	uint64_t made, skipped;   /* made now, found complete */
	uint64_t repaired;        /* complete samples whose manifest line was missing */
	uint64_t bytes;           /* bytes written now */
	double render_s, write_s; /* wall time rendering and writing (hashing included) */
	uint64_t worst_index;     /* the sample with the most saturated pixels made now */
	double worst_saturated, min_median_dn;
} pc_dataset_result;

/* Makes (or completes) this shard of the dataset. */
PC_API int pc_dataset_run(const pc_dataset_options *o, pc_dataset_result *r);

/* The shard of this task from a scheduler's environment: SLURM_ARRAY_TASK_ID and
 * SLURM_ARRAY_TASK_COUNT (minus SLURM_ARRAY_TASK_MIN), or Kubernetes Indexed Jobs'
 * JOB_COMPLETION_INDEX with shards_hint (> 0) or POLARCAM_SHARDS as the count. Returns 1 and
 * sets *shard and *shards when found, 0 when none is set, < 0 on malformed values (the error
 * names the variable). *scheduler names it ("slurm", "kubernetes"). */
PC_API int pc_dataset_shard_from_env(uint32_t shards_hint, uint32_t *shard, uint32_t *shards,
                                     const char **scheduler);

/* Shard manifests → manifest.jsonl (sorted by index, every sample 0..count−1 exactly once,
 * lines of the same sample identical across shards). Nothing is written when incomplete. */
PC_API int pc_dataset_merge(const char *dir, uint64_t *count);

typedef struct pc_dataset_verify_result {
	uint64_t count;     /* samples the dataset declares */
	uint64_t ok;        /* complete with every hash right */
	uint64_t missing;   /* no manifest line or no directory */
	uint64_t corrupt;   /* a file missing, extra, of another size or hash */
	uint64_t first_bad; /* index of the first missing or corrupt sample */
	char first_problem[512];
	uint64_t bytes; /* bytes hashed */
} pc_dataset_verify_result;

/* Completeness and hashes against manifest.jsonl (or, before a merge, the shard manifests).
 * Returns 0 when the check ran (r says what it found), < 0 when it could not. */
PC_API int pc_dataset_verify(const char *dir, pc_dataset_verify_result *r);

/* SHA-256 of a file as 64 lowercase hex digits (+ NUL), and its size. */
PC_API int pc_sha256_file(const char *path, char hex[65], uint64_t *bytes);

#ifdef __cplusplus
}
#endif

#endif
