#include "polarcam/io.h"

#include "polarcam/error.h"

/* TIFF support (libtiff) is completed by the pipeline work (issue 3). */
int pc_tiff_read(const char *path, pc_view *out, unsigned *significant_bits);
int pc_tiff_read(const char *path, pc_view *out, unsigned *significant_bits)
{
	(void)out;
	(void)significant_bits;
	return pc_error(PC_ENOTSUP, "%s: TIFF reading not implemented yet", path);
}

int pc_tiff_write(const char *path, const pc_view *v)
{
	(void)v;
	return pc_error(PC_ENOTSUP, "%s: TIFF writing not implemented yet", path);
}
