/* libFuzzer harness: TIFF files through pc_image_read, pc_image_read_mosaic (bit depth
 * from the last input byte: 0 = declared, else 1..16 or 32) and the format's own reader. */
#include "fuzz_image.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const char *p = fuzz_file("in.tif", data, size);
	unsigned bits = size ? data[size - 1] % 18 : 0;
	fuzz_read_image(p, NULL, bits == 17 ? 32 : bits);
	pc_array a;
	if (pc_tiff_read_array(p, &a) == 0) {
		size_t n = pc_array_count(&a);
		FUZZ_ASSERT(a.data && n > 0, "%s", p);
		size_t es = a.dtype == PC_DT_U8 ? 1 : a.dtype == PC_DT_U16 ? 2 : 4;
		(void)fuzz_touch(a.data, n * es, 0, 1);
		pc_array_free(&a);
	}
	return 0;
}
