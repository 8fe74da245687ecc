/* tests/out_peek.h - where a command writes an output folder before it puts it in place: the
 * temporary sibling ".NAME.tmp-HOST-PID-XXXXXX" (pc_outdir, polarcam/io.h). Tests that watch a
 * command's progress on disk look there. */
#ifndef POLARCAM_TESTS_OUT_PEEK_H
#define POLARCAM_TESTS_OUT_PEEK_H

#include <dirent.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

/* The temporary siblings of output folder dir (".NAME.tmp-HOST-PID-XXXXXX", pc_outdir): their
 * number; the path of the first one found in first (may be NULL). */
static inline unsigned sf_work_dirs(const char *dir, char *first, size_t size)
{
	char parent[1024], prefix[300];
	const char *slash = strrchr(dir, '/');
	const char *name = slash ? slash + 1 : dir;
	snprintf(parent, sizeof parent, "%.*s", slash ? (int)(slash - dir) : 1, slash ? dir : ".");
	snprintf(prefix, sizeof prefix, ".%s.tmp-", name);
	unsigned n = 0;
	DIR *d = opendir(parent);
	struct dirent *de;
	while (d && (de = readdir(d))) {
		if (strncmp(de->d_name, prefix, strlen(prefix)))
			continue;
		if (!n++ && first) {
			int w = snprintf(first, size, "%s/%s", parent, de->d_name);
			if (w < 0 || (size_t)w >= size)
				first[0] = '\0'; /* too long for the caller: not found */
		}
	}
	if (d)
		closedir(d);
	return n;
}

/* Whether file name exists in output folder dir or in the temporary sibling a command is
 * writing it in. */
static inline bool sf_out_file_exists(const char *dir, const char *name)
{
	char p[1400], w[1100];
	snprintf(p, sizeof p, "%s/%s", dir, name);
	if (access(p, F_OK) == 0)
		return true;
	if (!sf_work_dirs(dir, w, sizeof w))
		return false;
	snprintf(p, sizeof p, "%s/%s", w, name);
	return access(p, F_OK) == 0;
}

#endif
