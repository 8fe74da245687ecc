/* Memory a render needs, against what it may use (polarcam/sim.h), so that a scene too large for
 * the machine is refused with a message before hours of work end in an allocation failure or
 * the kernel's OOM killer. */
#include "polarcam/sim.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "polarcam/error.h"
#include "polarcam/limits.h"
#include "sim_impl.h"

uint64_t pc_sim_memory_bytes(const pc_sim *sim, bool truth)
{
	const uint64_t W = sim->info.width, H = sim->info.height, npix = W * H;
	const uint64_t C = sim->nch;
	uint64_t b = (uint64_t)sim->n_states * npix * sizeof(float); /* rate caches */
	if (sim->fx & PC_FX_PRNU_DSNU)
		b += npix * sizeof(float);
	if (sim->fx & PC_FX_CROSSTALK) /* halos while a state is prepared */
		b += (uint64_t)sim->n_psa * (W + 2) * (H + 2) * sizeof(float);
	/* row buffers of the render threads: Stokes (4) and Mueller (16) doubles per column and
	 * channel, deviates */
	long cpus = sim->opt.threads > 0 ? sim->opt.threads : sysconf(_SC_NPROCESSORS_ONLN);
	if (cpus < 1)
		cpus = 1;
	b += (uint64_t)cpus * W * (C * 20 + 4) * sizeof(double);
	b += npix * 2; /* one frame (at most 16 bits per pixel) */
	if (sim->fx & PC_FX_BLUR) {
		/* the lens blur's row pass (blur.c): (H + 2 + 2R) × (W + 2) Stokes vectors per
		 * channel, Mueller matrices with Mueller truth; its render rows (W + 2 + 2R wide)
		 */
		const uint64_t R = (uint64_t)pc_blur_radius(sim->scene->blur_sigma);
		const uint64_t per = C * ((truth && (sim->fx & PC_FX_MUELLER)) ? 20 : 4);
		b += (H + 2 + 2 * R) * (W + 2) * per * sizeof(double);
		b += (uint64_t)cpus * (W + 2 + 2 * R) * per * sizeof(double);
	}
	if (truth) {
		b += npix * C * 4 * sizeof(float);
		if (sim->fx & PC_FX_MUELLER)
			b += npix * C * 16 * sizeof(float);
	}
	return b;
}

/* "Key:   12345 kB" from /proc/meminfo, in bytes; 0 when absent. */
static uint64_t meminfo(const char *key)
{
	FILE *fp = fopen("/proc/meminfo", "r");
	if (!fp)
		return 0;
	char line[256];
	uint64_t v = 0;
	size_t kl = strlen(key);
	while (fgets(line, sizeof line, fp))
		if (!strncmp(line, key, kl) && line[kl] == ':') {
			unsigned long long kb = 0;
			if (sscanf(line + kl + 1, "%llu", &kb) == 1)
				v = (uint64_t)kb * 1024;
			break;
		}
	fclose(fp);
	return v;
}

/* A cgroup v2 file holding one number ("max" or unreadable: 0). */
static uint64_t cgroup_value(const char *name)
{
	char path[128];
	snprintf(path, sizeof path, "/sys/fs/cgroup/%s", name);
	FILE *fp = fopen(path, "r");
	if (!fp)
		return 0;
	unsigned long long v = 0;
	if (fscanf(fp, "%llu", &v) != 1)
		v = 0;
	fclose(fp);
	return (uint64_t)v;
}

uint64_t pc_sim_memory_available(const char **source)
{
	const char *src = "unknown";
	uint64_t lim = pc_limit_get(PC_LIMIT_MEMORY);
	if (lim) {
		if (source)
			*source = "POLARCAM_MAX_MEMORY";
		return lim;
	}
	uint64_t avail = UINT64_MAX;
	uint64_t m = meminfo("MemAvailable");
	if (m) {
		avail = m;
		src = "MemAvailable in /proc/meminfo";
	}
	uint64_t cmax = cgroup_value("memory.max"), ccur = cgroup_value("memory.current");
	if (cmax && cmax > ccur && cmax - ccur < avail) {
		avail = cmax - ccur;
		src = "the cgroup's memory.max";
	}
	struct rlimit rl;
	if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
	    (uint64_t)rl.rlim_cur < avail) {
		avail = (uint64_t)rl.rlim_cur;
		src = "RLIMIT_AS (ulimit -v)";
	}
	if (getrlimit(RLIMIT_DATA, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
	    (uint64_t)rl.rlim_cur < avail) {
		avail = (uint64_t)rl.rlim_cur;
		src = "RLIMIT_DATA (ulimit -d)";
	}
	if (source)
		*source = src;
	return avail;
}

int pc_sim_check_memory(const pc_sim *sim, bool truth)
{
	int rc = pc_limit_check(PC_LIMIT_MEMORY, 0, "render"); /* a malformed variable */
	if (rc)
		return rc;
	const char *src = NULL;
	const uint64_t need = pc_sim_memory_bytes(sim, truth), have = pc_sim_memory_available(&src);
	if (need <= have)
		return 0;
	return pc_error(PC_ENOMEM,
	                "a %ux%u render with %u polarization state%s needs about %.3g GiB, "
	                "%.3g GiB available (%s): render a region (--roi), lower "
	                "sensor.resolution, or set POLARCAM_MAX_MEMORY if more is available",
	                sim->info.width, sim->info.height, sim->n_states,
	                sim->n_states == 1 ? "" : "s", (double)need / (1 << 30),
	                (double)have / (1 << 30), src);
}
