/* libFuzzer harness: a recording's meta.json (pc_recording_open, as capture file:, process and
 * the file: source read it). Properties of a recording that opens: its description is sane
 * (size > 0, a storage format, a mosaic when polarized), frames are named raw_NNNNNN.png and
 * listed in increasing sequence with non-decreasing timestamps, all below 2^63. */
#include "fuzz.h"
#include "polarcam/error.h"
#include "polarcam/format.h"
#include "polarcam/recording.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	fuzz_file("meta.json", data, size);
	pc_recording *r = NULL;
	if (pc_recording_open(&r, fuzz_dir()) != 0) {
		FUZZ_ASSERT(r == NULL, "recording set on failure");
		return 0;
	}
	const pc_recording_desc *d = pc_recording_get_desc(r);
	FUZZ_ASSERT(d->width > 0 && d->height > 0 && pc_format_info_get(d->format), "%ux%u",
	            d->width, d->height);
	FUZZ_ASSERT(!d->polarized || d->mosaic.period == 2 || d->mosaic.period == 4, "period %u",
	            d->mosaic.period);
	for (size_t i = 0; i < pc_recording_count(r); i++) {
		const pc_recording_frame *f = pc_recording_get_frame(r, i);
		FUZZ_ASSERT(f && strlen(f->file) == 14 && !strncmp(f->file, "raw_", 4), "frame %zu",
		            i);
		FUZZ_ASSERT(f->sequence <= (uint64_t)INT64_MAX &&
		                f->timestamp_ns <= (uint64_t)INT64_MAX,
		            "frame %zu", i);
		if (i) {
			const pc_recording_frame *p = pc_recording_get_frame(r, i - 1);
			FUZZ_ASSERT(f->sequence > p->sequence && f->timestamp_ns >= p->timestamp_ns,
			            "frame %zu order", i);
		}
	}
	pc_view v;
	if (pc_recording_count(r) && pc_recording_read(r, 0, &v) == 0) /* files are absent */
		pc_view_free(&v);
	pc_recording_free(r);
	return 0;
}
