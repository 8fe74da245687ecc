/* libFuzzer harness: source URIs "SCHEME:ARG?k=v&k2=v2". The option parser and its typed getters
 * run through pc_source_open_ops with a backend that reads options of every type (no device);
 * inputs starting with "sim:" or "file:" then go to the real backends through pc_source_open
 * (the simulator's default scene opens in a few ms; file: paths name missing or scratch
 * directories). Network and device schemes are not opened here: they would probe hardware. */
#include "fuzz.h"
#include "polarcam/error.h"
#include "polarcam/source.h"

static const char *const fz_options[] = {"a", "b", "c", "seed", "fps", "roi", NULL};

static int fz_open(pc_source *s, const char *arg)
{
	(void)arg;
	double d = 0;
	uint64_t u = 0;
	bool b = false;
	int rc = pc_source_option_double(s, "a", -1e9, 1e9, &d);
	if (!rc)
		rc = pc_source_option_u64(s, "b", 0, UINT64_MAX, &u);
	if (!rc)
		rc = pc_source_option_bool(s, "c", &b);
	if (!rc)
		rc = pc_source_option_u64(s, "seed", 1, 1000, &u);
	if (!rc)
		rc = pc_source_option_double(s, "fps", 0, 1e5, &d);
	const char *roi = pc_source_option(s, "roi");
	if (roi)
		(void)strlen(roi);
	return rc;
}

static void fz_close(pc_source *s)
{
	(void)s;
}

static const pc_source_ops fz_ops = {.open = fz_open, .close = fz_close, .options = fz_options};

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	fuzz_dir();
	char *t = fuzz_text(data, size);
	pc_source *s = NULL;
	if (pc_source_open_ops(&s, &fz_ops, "fz", t) == 0)
		pc_source_close(s);
	else
		FUZZ_ASSERT(s == NULL, "source set on failure");
	if ((!strncmp(t, "sim:", 4) && size < 256) || !strncmp(t, "file:", 5)) {
		s = NULL;
		if (pc_source_open(&s, t) == 0)
			pc_source_close(s);
		else
			FUZZ_ASSERT(s == NULL && *pc_error_detail(), "%s", t);
	}
	free(t);
	return 0;
}
