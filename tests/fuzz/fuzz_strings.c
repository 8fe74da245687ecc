/* libFuzzer harness: the small text parsers — mosaic layouts ([BAYER:]A,B,C,D[@DX,DY]), pixel
 * format and GenICam names, limit sizes ("400M", "4Gi") and the CLI's numbers and ranges.
 * Properties: a layout that parses formats back to text that parses to the same mosaic; an
 * integer the CLI accepts is exactly its decimal digits; a size round-trips its digits. */
#include <math.h>

#include "cli.h"
#include "fuzz.h"
#include "polarcam/error.h"
#include "polarcam/format.h"
#include "polarcam/mosaic.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	fuzz_dir();
	char *t = fuzz_text(data, size);
	pc_mosaic m, m2;
	if (pc_mosaic_parse(t, &m) == 0) {
		char buf[128];
		pc_mosaic_format(&m, buf, sizeof buf);
		FUZZ_ASSERT(pc_mosaic_parse(buf, &m2) == 0, "'%s' formats to '%s', which fails", t,
		            buf);
		FUZZ_ASSERT(memcmp(&m, &m2, sizeof m) == 0, "'%s' -> '%s' differs", t, buf);
	}
	pc_pixfmt f = pc_format_from_name(t);
	if (f != PC_FMT_INVALID)
		FUZZ_ASSERT(pc_format_info_get(f) != NULL, "%s", t);
	bool pol, col;
	if (pc_format_from_genicam(t, &f, &pol, &col) == 0)
		FUZZ_ASSERT(pc_format_info_get(f) != NULL, "%s", t);
	uint64_t u;
	if (pc_limit_parse(t, &u) == 0)
		FUZZ_ASSERT(u > 0, "%s", t);
	if (cli_parse_u64("--x", t, &u) == 0) {
		char back[32];
		snprintf(back, sizeof back, "%llu", (unsigned long long)u);
		const char *digits = t;
		while (digits[0] == '0' && digits[1])
			digits++;
		FUZZ_ASSERT(!strcmp(back, digits), "'%s' read as %s", t, back);
	}
	long l;
	if (cli_parse_long("--x", t, -1000, 1000, &l) == 0)
		FUZZ_ASSERT(l >= -1000 && l <= 1000, "%ld", l);
	double d;
	if (cli_parse_double("--x", t, &d) == 0)
		FUZZ_ASSERT(isfinite(d), "%s", t);
	double *vals = NULL;
	size_t n = 0;
	if (cli_parse_range("--x", t, &vals, &n) == 0) {
		FUZZ_ASSERT(n >= 1 && n <= 10000000, "%zu values", n);
		for (size_t i = 0; i < n; i += 1 + n / 64)
			FUZZ_ASSERT(isfinite(vals[i]), "value %zu", i);
	}
	free(vals);
	char q[64];
	cli_quote(t, size, q, sizeof q);
	for (const char *c = q; *c; c++)
		FUZZ_ASSERT((unsigned char)*c >= 0x20 && *c != 0x7f, "control byte in quote");
	free(t);
	return 0;
}
