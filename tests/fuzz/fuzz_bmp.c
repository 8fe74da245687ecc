/* libFuzzer harness: BMP files through pc_image_read, pc_image_read_mosaic (bit depth
 * from the last input byte: 0 = declared, else 1..16 or 32) and the format's own reader. */
#include "fuzz_image.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const char *p = fuzz_file("in.bmp", data, size);
	unsigned bits = size ? data[size - 1] % 18 : 0;
	fuzz_read_image(p, NULL, bits == 17 ? 32 : bits);
	pc_view v;
	if (pc_bmp_read(p, &v) == 0) {
		fuzz_check_view(&v, p);
		pc_view_free(&v);
	}
	return 0;
}
