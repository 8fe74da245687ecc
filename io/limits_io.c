/* Limits and file lengths for the readers (io_internal.h). */
#include <stdint.h>
#include <sys/stat.h>

#include "io_internal.h"
#include "polarcam/error.h"
#include "polarcam/limits.h"

uint64_t pc_io_file_size(FILE *fp)
{
	struct stat st;
	if (fstat(fileno(fp), &st) != 0 || !S_ISREG(st.st_mode) || st.st_size < 0)
		return UINT64_MAX;
	return (uint64_t)st.st_size;
}

int pc_io_check_image(const char *path, uint64_t width, uint64_t height, uint64_t bytes)
{
	char what[512];
	snprintf(what, sizeof what, "%s: %llu x %llu image", path, (unsigned long long)width,
	         (unsigned long long)height);
	uint64_t pixels = width && height > UINT64_MAX / width ? UINT64_MAX : width * height;
	int rc = pc_limit_check(PC_LIMIT_PIXELS, pixels, what);
	if (!rc)
		rc = pc_limit_check(PC_LIMIT_BYTES, bytes, what);
	return rc;
}
