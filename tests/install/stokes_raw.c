/* stokes_raw RAW LAYOUT METHOD OUTDIR: demosaics a raw polarizer mosaic and writes Stokes, DoLP
 * and AoLP into OUTDIR/{stokes,dolp,aolp}.npy, the same files as `polarcam process`.
 * Build: cc stokes_raw.c $(pkg-config --cflags --libs polarcam)    (docs/api.md) */
#include <stdio.h>
#include <stdlib.h>

#include <polarcam/polarcam.h>

static void check(int rc)
{
	if (rc) {
		fprintf(stderr, "stokes_raw: %s: %s\n", pc_strerror(rc), pc_error_detail());
		exit(1);
	}
}

static void save(const char *dir, const char *name, const float *a, unsigned ndim,
                 const size_t *shape)
{
	char path[4096];
	if (snprintf(path, sizeof path, "%s/%s", dir, name) >= (int)sizeof path)
		check(pc_error(PC_EINVAL, "%s: path too long", dir));
	check(pc_npy_write(path, a, PC_DT_F32, ndim, shape));
}

int main(int argc, char **argv)
{
	if (argc != 5) {
		fprintf(stderr, "usage: stokes_raw RAW LAYOUT METHOD OUTDIR\n");
		return 2;
	}
	pc_mosaic mosaic;
	pc_demosaic_method method;
	pc_view raw;
	check(pc_mosaic_parse(argv[2], &mosaic));              /* "90,45,135,0": Sony IMX250MZR */
	check(pc_demosaic_method_from_name(argv[3], &method)); /* "bilinear", "eari", ... */
	check(pc_image_read_mosaic(argv[1], NULL, 0, &raw, NULL)); /* bit depth from the file */
	uint32_t w, h;
	pc_demosaic_out_size(method, raw.width, raw.height, &w, &h);
	size_t n = (size_t)w * h, row = 3 * (size_t)w;
	float *s = malloc(3 * n * sizeof *s), *dolp = malloc(n * sizeof *dolp),
	      *aolp = malloc(n * sizeof *aolp);
	if (!s || !dolp || !aolp)
		check(pc_error(PC_ENOMEM, "%ux%u Stokes images", w, h));
	/* S0, S1, S2 interleaved in one (H, W, 3) array; DoLP, AoLP planes. Strides in floats. */
	pc_stokes_out out = {
	    {s, row, 3}, {s + 1, row, 3}, {s + 2, row, 3}, {dolp, w, 1}, {aolp, w, 1}};
	check(pc_stokes_from_raw(&raw, &mosaic, method, NULL, &out));
	check(pc_mkdir_p(argv[4]));
	save(argv[4], "stokes.npy", s, 3, (size_t[]){h, w, 3});
	save(argv[4], "dolp.npy", dolp, 2, (size_t[]){h, w});
	save(argv[4], "aolp.npy", aolp, 2, (size_t[]){h, w});
	pc_view_free(&raw);
	free(s);
	free(dolp);
	free(aolp);
	return 0;
}
