/* Ground-truth directories for the evaluation protocol. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "polarcam/error.h"
#include "polarcam/eval.h"
#include "polarcam/io.h"

static const char *const exts[] = { ".tif", ".tiff", ".png", ".bmp", ".npy",
				    ".TIF", ".TIFF", ".PNG", ".BMP" };

int pc_truth_load(const char *dir, pc_eval_truth *t)
{
	static const char *names[4] = { "0", "45", "90", "135" };
	memset(t, 0, sizeof *t);
	struct stat st;
	if (!dir || stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
		return pc_error(PC_ENOENT, "%s: not a directory", dir ? dir : "");
	pc_view v[4];
	memset(v, 0, sizeof v);
	int rc = 0;
	for (int c = 0; c < 4 && !rc; c++) {
		char path[4096];
		int found = 0;
		for (size_t e = 0; e < sizeof exts / sizeof exts[0] && !found; e++) {
			snprintf(path, sizeof path, "%s/%s%s", dir, names[c], exts[e]);
			found = stat(path, &st) == 0 && S_ISREG(st.st_mode);
		}
		if (!found) {
			rc = pc_error(PC_ENOENT, "%s: no analyser image '%s' (expected %s.tif, .png, "
						 ".bmp or .npy)", dir, names[c], names[c]);
			break;
		}
		rc = pc_image_read(path, NULL, &v[c], NULL);
	}
	if (!rc) {
		rc = pc_eval_truth_from_views(v, t);
		if (rc)
			pc_error_prefix(rc, "%s: ", dir);
	}
	for (int c = 0; c < 4; c++)
		pc_view_free(&v[c]);
	return rc;
}

void pc_truth_dataset(const char *dir, char *buf, size_t size)
{
	size_t n = strlen(dir);
	while (n > 1 && dir[n - 1] == '/')
		n--;
	size_t end = n;
	while (end > 0 && dir[end - 1] != '/')
		end--; /* end: start of the scene name */
	if (end == 0) {
		snprintf(buf, size, ".");
		return;
	}
	size_t pe = end - 1; /* the slash before the scene */
	while (pe > 0 && dir[pe - 1] == '/')
		pe--;
	size_t ps = pe;
	while (ps > 0 && dir[ps - 1] != '/')
		ps--;
	if (pe == ps)
		snprintf(buf, size, "%s", pe == 0 ? "/" : ".");
	else
		snprintf(buf, size, "%.*s", (int)(pe - ps), dir + ps);
}
