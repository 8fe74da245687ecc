/* tests/fuzz/fuzz_batch.h - the batch harnesses: the input is a --batch file, read with the
 * CLI's own line reader (cli_lines_*) and field parser (cli_parse_fields_n), as
 * `polarcam pbrdf|decompose --batch` do; each good line goes to fuzz_batch_line, each bad one
 * through the error object (cli_json_error_line, which must stay valid JSON). */
#ifndef POLARCAM_FUZZ_BATCH_H
#define POLARCAM_FUZZ_BATCH_H

#include "cli.h"
#include "fuzz.h"
#include "polarcam/error.h"

static void fuzz_batch_line(const double *v, const uint8_t *data, size_t size);

static inline void fuzz_batch(const uint8_t *data, size_t size, const char *const *names, int want)
{
	const char *p = fuzz_file("batch.txt", data, size);
	cli_lines in;
	if (cli_lines_open(&in, p) != 0)
		abort();
	char *line;
	int rc;
	while ((rc = cli_lines_next(&in, &line)) > 0) {
		double v[16];
		rc = cli_parse_fields_n(line, in.len, names, want, v);
		if (rc) {
			json_t *j = cli_json_error_line(in.lineno, rc);
			FUZZ_ASSERT(j != NULL, "error object for line %lu: %s", in.lineno,
			            pc_error_detail());
			char *s = json_dumps(j, JSON_COMPACT | JSON_ENSURE_ASCII);
			FUZZ_ASSERT(s != NULL, "json_dumps");
			for (const char *c = s; *c; c++) /* nothing for a terminal to interpret */
				FUZZ_ASSERT((unsigned char)*c >= 0x20 && (unsigned char)*c < 0x7f,
				            "byte %#x in %s", (unsigned char)*c, s);
			free(s);
			json_decref(j);
			continue;
		}
		fuzz_batch_line(v, data, size);
	}
	FUZZ_ASSERT(rc == 0, "read error: %s", pc_error_detail());
	cli_lines_close(&in);
}

#endif
