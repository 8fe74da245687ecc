/* libFuzzer harness: states.json (pc_states_read, what `polarcam mueller --states` reads).
 * Properties of a file that parses: 1..64 generator and analyser states, every entry finite,
 * the layout NUL-terminated within its buffer. */
#include <math.h>

#include "fuzz.h"
#include "polarcam/error.h"
#include "polarcam/states.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const char *p = fuzz_file("states.json", data, size);
	pc_sim_states st;
	char layout[64];
	memset(layout, 'x', sizeof layout);
	if (pc_states_read(p, &st, layout, sizeof layout) != 0) {
		FUZZ_ASSERT(strstr(pc_error_detail(), "states.json"), "%s", pc_error_detail());
		return 0;
	}
	FUZZ_ASSERT(st.n_psg >= 1 && st.n_psg <= 64 && st.n_psa >= 1 && st.n_psa <= 64, "%u %u",
	            st.n_psg, st.n_psa);
	FUZZ_ASSERT(memchr(layout, '\0', sizeof layout) != NULL, "layout not terminated");
	for (unsigned i = 0; i < st.n_psg; i++)
		for (int k = 0; k < 4; k++)
			FUZZ_ASSERT(isfinite(st.psg[i][k]), "psg[%u]", i);
	for (unsigned i = 0; i < st.n_psa; i++)
		for (int k = 0; k < 16; k++)
			FUZZ_ASSERT(isfinite(st.psa[i][k / 4][k % 4]), "psa[%u]", i);
	return 0;
}
