/* Size limits for untrusted input (polarcam/limits.h). */
#include "polarcam/limits.h"

#include <stdatomic.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"

static const struct {
	const char *env, *unit;
	uint64_t def;
} pc_limits[PC_LIMIT_COUNT] = {
    [PC_LIMIT_PIXELS] = {"POLARCAM_MAX_PIXELS", "pixels", PC_LIMIT_PIXELS_DEFAULT},
    [PC_LIMIT_BYTES] = {"POLARCAM_MAX_BYTES", "bytes", PC_LIMIT_BYTES_DEFAULT},
    [PC_LIMIT_TRIANGLES] = {"POLARCAM_MAX_TRIANGLES", "triangles", PC_LIMIT_TRIANGLES_DEFAULT},
    [PC_LIMIT_MEMORY] = {"POLARCAM_MAX_MEMORY", "bytes", PC_LIMIT_MEMORY_DEFAULT},
    [PC_LIMIT_FRAMES] = {"POLARCAM_MAX_FRAMES", "frames", PC_LIMIT_FRAMES_DEFAULT},
};

/* pc_limit_set's values (0: none) */
static _Atomic uint64_t pc_limit_override[PC_LIMIT_COUNT];

int pc_limit_parse(const char *text, uint64_t *out)
{
	if (!text || *text < '0' || *text > '9')
		return PC_EINVAL;
	uint64_t v = 0;
	const char *p = text;
	for (; *p >= '0' && *p <= '9'; p++) {
		unsigned d = (unsigned)(*p - '0');
		if (v > (UINT64_MAX - d) / 10)
			return PC_EINVAL;
		v = v * 10 + d;
	}
	uint64_t mul = 1;
	if (*p) {
		static const char units[] = "kMGT";
		const char *u = *p == 'K' ? units : strchr(units, *p); /* k or K */
		if (!u || !*p)
			return PC_EINVAL;
		unsigned e = (unsigned)(u - units) + 1;
		bool binary = p[1] == 'i';
		if (p[binary ? 2 : 1] != '\0')
			return PC_EINVAL;
		for (unsigned i = 0; i < e; i++)
			mul *= binary ? 1024 : 1000;
	}
	if (v == 0 || v > UINT64_MAX / mul)
		return PC_EINVAL;
	*out = v * mul;
	return 0;
}

static int pc_limit_env_value(pc_limit which, uint64_t *out)
{
	const char *t = getenv(pc_limits[which].env);
	if (!t || !*t)
		return 1;
	return pc_limit_parse(t, out);
}

uint64_t pc_limit_get(pc_limit which)
{
	if ((unsigned)which >= PC_LIMIT_COUNT)
		return 0;
	uint64_t v = atomic_load(&pc_limit_override[which]);
	if (v)
		return v;
	if (pc_limit_env_value(which, &v) == 0)
		return v;
	return pc_limits[which].def;
}

int pc_limit_set(pc_limit which, uint64_t value)
{
	if ((unsigned)which >= PC_LIMIT_COUNT)
		return pc_error(PC_EINVAL, "pc_limit_set: unknown limit %d", (int)which);
	atomic_store(&pc_limit_override[which], value);
	return 0;
}

const char *pc_limit_env(pc_limit which)
{
	return (unsigned)which < PC_LIMIT_COUNT ? pc_limits[which].env : NULL;
}

int pc_limit_check(pc_limit which, uint64_t value, const char *what)
{
	if ((unsigned)which >= PC_LIMIT_COUNT)
		return pc_error(PC_EINVAL, "pc_limit_check: unknown limit %d", (int)which);
	if (!what)
		what = "input";
	uint64_t lim = atomic_load(&pc_limit_override[which]);
	if (!lim) {
		int e = pc_limit_env_value(which, &lim);
		if (e == 1)
			lim = pc_limits[which].def;
		else if (e)
			return pc_error(PC_EINVAL,
			                "%s: %s='%s': expected a positive integer, "
			                "optionally with a suffix k, M, G, T or Ki, Mi, Gi, Ti",
			                what, pc_limits[which].env, getenv(pc_limits[which].env));
	}
	if (lim == 0 || value <= lim)
		return 0;
	return pc_error(PC_ERANGE, "%s: %llu %s exceed the limit of %llu (set %s to allow more)",
	                what, (unsigned long long)value, pc_limits[which].unit,
	                (unsigned long long)lim, pc_limits[which].env);
}
