/* Outputs: the one overwrite rule, and folders written as a set (polarcam/io.h). */
#define _GNU_SOURCE /* renameat2, RENAME_EXCHANGE */
#include "polarcam/io.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "io_internal.h"
#include "polarcam/error.h"

/* The description file every polarcam output folder carries: a folder holding one of them was
 * written by polarcam and may be replaced with PC_OUT_OVERWRITE. */
static const char *const own_markers[] = {"meta.json", "report.json", "mueller.json", "figures.md",
                                          "demosaic.json"};

static int errno_code(int e)
{
	return e == ENOENT                 ? PC_ENOENT
	       : e == EACCES || e == EPERM ? PC_EPERM
	       : e == ENAMETOOLONG         ? PC_EINVAL /* a bad name given, not a failure */
	                                   : PC_EIO;
}

/* 1 when dir holds no entry but . and .., 0 when it holds some, < 0 on error. */
static int dir_empty(const char *dir)
{
	DIR *d = opendir(dir);
	if (!d)
		return pc_error(errno_code(errno), "%s: %s", dir, strerror(errno));
	int empty = 1;
	for (struct dirent *e; (e = readdir(d));)
		if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
			empty = 0;
			break;
		}
	closedir(d);
	return empty;
}

static bool holds_marker(const char *dir)
{
	char p[PATH_MAX];
	struct stat st;
	for (size_t i = 0; i < sizeof own_markers / sizeof own_markers[0]; i++)
		if ((size_t)snprintf(p, sizeof p, "%s/%s", dir, own_markers[i]) < sizeof p &&
		    lstat(p, &st) == 0 && S_ISREG(st.st_mode))
			return true;
	return false;
}

/* True when dir is the current directory or contains it (its removal would pull the working
 * directory away). */
static bool holds_cwd(const char *dir)
{
	char rd[PATH_MAX], cwd[PATH_MAX];
	if (!realpath(dir, rd) || !getcwd(cwd, sizeof cwd))
		return false;
	size_t n = strlen(rd);
	if (n == 1) /* "/" */
		return true;
	return !strncmp(cwd, rd, n) && (cwd[n] == '\0' || cwd[n] == '/');
}

int pc_output_check(const char *path, unsigned flags, bool folder)
{
	if (!path || !*path)
		return pc_error(PC_EINVAL, "the output path is empty");
	struct stat st;
	if (lstat(path, &st) != 0) {
		if (errno == ENOENT)
			return 0;
		return pc_error(errno_code(errno), "%s: %s", path, strerror(errno));
	}
	const bool over = flags & PC_OUT_OVERWRITE;
	if (S_ISLNK(st.st_mode))
		return pc_error(PC_EEXIST,
		                "%s: is a symbolic link; give the %s it points to (a link "
		                "is never replaced)",
		                path, folder ? "folder" : "file");
	if (folder) {
		if (!S_ISDIR(st.st_mode))
			return pc_error(PC_EEXIST, "%s: exists and is not a folder", path);
		int empty = dir_empty(path);
		if (empty < 0)
			return empty;
		if (empty)
			return 0;
		if (!over)
			return pc_error(PC_EEXIST,
			                "%s: exists and is not empty (--overwrite replaces "
			                "it as a whole)",
			                path);
		if (holds_cwd(path))
			return pc_error(PC_EEXIST,
			                "%s: is the current directory or contains it; not "
			                "replaced, even with --overwrite",
			                path);
		if (!holds_marker(path))
			return pc_error(PC_EEXIST,
			                "%s: holds files polarcam did not write (none of "
			                "meta.json, report.json, mueller.json, figures.md, "
			                "demosaic.json); not replaced, even with --overwrite",
			                path);
		return 0;
	}
	if (!S_ISREG(st.st_mode))
		return pc_error(PC_EEXIST, "%s: exists and is not a regular file", path);
	if (st.st_size > 0 && !over)
		return pc_error(PC_EEXIST, "%s: exists (--overwrite replaces it)", path);
	return 0;
}

/* The parent folder of path ("." when none) and the last component, in parent/name buffers. */
static int split(const char *path, char *parent, char *name)
{
	size_t n = strlen(path);
	while (n > 1 && path[n - 1] == '/')
		n--;
	if (n >= PATH_MAX)
		return pc_error(PC_EINVAL, "%s: path too long", path);
	char buf[PATH_MAX];
	memcpy(buf, path, n);
	buf[n] = '\0';
	char *slash = strrchr(buf, '/');
	const char *base = slash ? slash + 1 : buf;
	if (!*base || !strcmp(base, ".") || !strcmp(base, ".."))
		return pc_error(PC_EINVAL,
		                "%s: name the output folder itself (not '.', '..' or '/')", path);
	size_t bl = strlen(base);
	if (bl > NAME_MAX)
		return pc_error(PC_EINVAL, "%s: name too long", path);
	memcpy(name, base, bl + 1);
	if (!slash)
		strcpy(parent, ".");
	else if (slash == buf)
		strcpy(parent, "/");
	else {
		*slash = '\0';
		strcpy(parent, buf);
	}
	return 0;
}

/* ".NAME.tmp-HOST-" (NAME cut to 100 bytes so that the whole name fits NAME_MAX) */
void pc_io_tmp_prefix(const char *name, char *out, size_t size)
{
	char host[64] = "host";
	if (gethostname(host, sizeof host) != 0)
		strcpy(host, "host");
	host[sizeof host - 1] = '\0';
	for (char *c = host; *c; c++)
		if (*c == '/' || *c == '-')
			*c = '_';
	snprintf(out, size, ".%.100s.tmp-%s-", name, host);
}

static int rm_entry(const char *p, const struct stat *sb, int flag, struct FTW *ftw)
{
	(void)sb, (void)flag, (void)ftw;
	remove(p);
	return 0;
}

/* Removes a folder and everything under it, never following symbolic links. */
static void rm_tree(const char *dir)
{
	nftw(dir, rm_entry, 16, FTW_DEPTH | FTW_PHYS);
}

/* Temporary folders of earlier runs for the same output on this host whose process is gone. */
void pc_io_remove_stale(const char *parent, const char *prefix)
{
	DIR *d = opendir(parent);
	if (!d)
		return;
	size_t pl = strlen(prefix);
	for (struct dirent *e; (e = readdir(d));) {
		if (strncmp(e->d_name, prefix, pl))
			continue;
		char *end;
		long pid = strtol(e->d_name + pl, &end, 10);
		if (end == e->d_name + pl || *end != '-' || strlen(end + 1) != 6 || pid <= 0 ||
		    pid == (long)getpid())
			continue;
		if (kill((pid_t)pid, 0) == 0 || errno != ESRCH)
			continue; /* alive, or not ours to judge */
		char p[PATH_MAX];
		if ((size_t)snprintf(p, sizeof p, "%s/%s", parent, e->d_name) < sizeof p)
			rm_tree(p);
	}
	closedir(d);
}

static void outdir_free(pc_outdir *od)
{
	free(od->path);
	free(od->tmp);
	od->path = od->tmp = NULL;
}

int pc_outdir_begin(pc_outdir *od, const char *path, unsigned flags)
{
	memset(od, 0, sizeof *od);
	int rc = pc_output_check(path, flags, true);
	if (rc)
		return rc;
	char parent[PATH_MAX], name[NAME_MAX + 1], prefix[256];
	if ((rc = split(path, parent, name)))
		return rc;
	if ((rc = pc_mkdir_p(parent)))
		return rc;
	pc_io_tmp_prefix(name, prefix, sizeof prefix);
	pc_io_remove_stale(parent, prefix);
	char tmp[PATH_MAX];
	if ((size_t)snprintf(tmp, sizeof tmp, "%s/%s%ld-XXXXXX", parent, prefix, (long)getpid()) >=
	    sizeof tmp)
		return pc_error(PC_EINVAL, "%s: path too long", path);
	if (!mkdtemp(tmp))
		return pc_error(errno_code(errno), "%s: cannot create a folder beside it: %s", path,
		                strerror(errno));
	od->path = strdup(path);
	od->tmp = strdup(tmp);
	od->flags = flags;
	if (!od->path || !od->tmp) {
		rmdir(tmp);
		outdir_free(od);
		return pc_error(PC_ENOMEM, "%s", path);
	}
	return 0;
}

static void sync_dir(const char *dir)
{
	int fd = open(dir, O_RDONLY | O_DIRECTORY);
	if (fd >= 0) {
		fsync(fd);
		close(fd);
	}
}

/* Swaps the folders at a and b; 0, or errno. */
static int exchange(const char *a, const char *b)
{
#ifdef RENAME_EXCHANGE
	if (renameat2(AT_FDCWD, a, AT_FDCWD, b, RENAME_EXCHANGE) == 0)
		return 0;
	if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP)
		return errno;
#endif
	/* without an atomic exchange: b moves aside, a into its place, the old one back to a */
	char aside[PATH_MAX];
	if ((size_t)snprintf(aside, sizeof aside, "%s.old", a) >= sizeof aside)
		return ENAMETOOLONG;
	if (rename(b, aside) != 0)
		return errno;
	if (rename(a, b) != 0) {
		int e = errno;
		rename(aside, b);
		return e;
	}
	return rename(aside, a) == 0 ? 0 : errno;
}

int pc_outdir_commit(pc_outdir *od)
{
	if (!od->tmp)
		return pc_error(PC_ESTATE, "output folder not begun");
	/* mkdtemp makes 0700; give the folder the usual permissions (umask applies) */
	mode_t um = umask(0);
	umask(um);
	chmod(od->tmp, 0777 & ~um);
	int rc = 0;
	struct stat st;
	if (lstat(od->path, &st) != 0 || (S_ISDIR(st.st_mode) && dir_empty(od->path) == 1)) {
		if (rename(od->tmp, od->path) != 0)
			rc = pc_error(errno == ENOTEMPTY || errno == EEXIST ? PC_EEXIST : PC_EIO,
			              "%s: cannot rename the new folder into place: %s", od->path,
			              strerror(errno));
	} else {
		/* the rule again: the folder may have appeared since pc_outdir_begin */
		rc = pc_output_check(od->path, od->flags, true);
		int e = rc ? 0 : exchange(od->tmp, od->path);
		if (e)
			rc = pc_error(PC_EIO, "%s: cannot swap the new folder into place: %s",
			              od->path, strerror(e));
		/* od->tmp now holds the old folder (or, on failure, still the new one) */
	}
	char parent[PATH_MAX], name[NAME_MAX + 1];
	if (!rc && !split(od->path, parent, name))
		sync_dir(parent);
	rm_tree(od->tmp);
	outdir_free(od);
	return rc;
}

/* The error detail names the folder the user asked for, not the temporary one. */
static void detail_names_path(const pc_outdir *od)
{
	const char *d = pc_error_detail();
	size_t tl = strlen(od->tmp);
	char buf[1024];
	size_t n = 0;
	bool changed = false;
	for (const char *p = d; *p && n + 1 < sizeof buf;) {
		if (!strncmp(p, od->tmp, tl)) {
			n += (size_t)snprintf(buf + n, sizeof buf - n, "%s", od->path);
			if (n >= sizeof buf)
				n = sizeof buf - 1;
			p += tl;
			changed = true;
		} else {
			buf[n++] = *p++;
		}
	}
	buf[n] = '\0';
	if (changed)
		pc_error(0, "%s", buf);
}

void pc_outdir_abort(pc_outdir *od)
{
	if (od->tmp) {
		detail_names_path(od);
		rm_tree(od->tmp);
	}
	outdir_free(od);
}
