#define _POSIX_C_SOURCE 200809L
#include "polarcam/io.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "polarcam/error.h"

int pc_atomic_open(pc_atomic_file *af, const char *path)
{
	memset(af, 0, sizeof *af);
	if (!path || !*path)
		return pc_error(PC_EINVAL, "output path is empty");
	size_t n = strlen(path);
	af->path = malloc(n + 1);
	af->tmp_path = calloc(1, n + 32); /* zeroed: pc_atomic_abort may see it before mkstemp */
	if (!af->path || !af->tmp_path) {
		pc_atomic_abort(af);
		return pc_error(PC_ENOMEM, "%s: out of memory", path);
	}
	memcpy(af->path, path, n + 1);
	/* The temporary file lives in the destination's directory so that rename() is atomic. */
	const char *slash = strrchr(path, '/');
	size_t dir = slash ? (size_t)(slash - path + 1) : 0;
	memcpy(af->tmp_path, path, dir);
	/* ".NAME.tmpXXXXXX" must itself be a legal name: NAME is cut (at a UTF-8 character
	 * boundary) so that the temporary name stays within NAME_MAX bytes even when NAME, legal
	 * itself, is up to NAME_MAX long; mkstemp's XXXXXX keep it unique. */
	size_t base = n - dir, keep = base;
	if (base > NAME_MAX) {
		free(af->tmp_path); /* not a file yet: nothing to unlink */
		af->tmp_path = NULL;
		pc_atomic_abort(af);
		return pc_error(PC_EINVAL, "%s: file name of %zu bytes: too long (at most %d)", path,
				base, NAME_MAX);
	}
	const size_t decor = strlen("..tmpXXXXXX");
	if (keep + decor > NAME_MAX) {
		keep = NAME_MAX - decor;
		while (keep > 0 && ((unsigned char)path[dir + keep] & 0xc0) == 0x80)
			keep--;
	}
	snprintf(af->tmp_path + dir, n + 32 - dir, ".%.*s.tmpXXXXXX", (int)keep, path + dir);
	int fd = mkstemp(af->tmp_path);
	if (fd < 0) {
		int e = errno;
		free(af->tmp_path);
		af->tmp_path = NULL;
		pc_atomic_abort(af);
		/* a name the file system cannot hold is a bad argument, not an I/O failure */
		return pc_error(e == ENOENT ? PC_ENOENT : e == EACCES ? PC_EPERM
						: e == ENAMETOOLONG ? PC_EINVAL : PC_EIO,
				"%s: cannot create a file there: %s", path, strerror(e));
	}
	af->fp = fdopen(fd, "wb");
	if (!af->fp) {
		int e = errno;
		close(fd);
		pc_atomic_abort(af);
		return pc_error(PC_EIO, "%s: %s", path, strerror(e));
	}
	return 0;
}

int pc_atomic_commit(pc_atomic_file *af)
{
	if (!af->fp)
		return pc_error(PC_ESTATE, "atomic file not open");
	int bad = ferror(af->fp);
	if (fflush(af->fp) != 0)
		bad = 1;
	int e = errno;
	if (!bad && fsync(fileno(af->fp)) != 0) {
		bad = 1;
		e = errno;
	}
	if (fclose(af->fp) != 0 && !bad) {
		bad = 1;
		e = errno;
	}
	af->fp = NULL;
	if (bad) {
		int rc = pc_error(PC_EIO, "%s: write failed: %s", af->path, strerror(e));
		pc_atomic_abort(af);
		return rc;
	}
	/* mkstemp creates 0600; give the file the usual permissions (umask applies). */
	mode_t um = umask(0);
	umask(um);
	chmod(af->tmp_path, 0666 & ~um);
	if (rename(af->tmp_path, af->path) != 0) {
		e = errno;
		int rc = pc_error(PC_EIO, "%s: cannot rename into place: %s", af->path, strerror(e));
		pc_atomic_abort(af);
		return rc;
	}
	free(af->tmp_path);
	af->tmp_path = NULL;
	free(af->path);
	af->path = NULL;
	return 0;
}

void pc_atomic_abort(pc_atomic_file *af)
{
	if (af->fp) {
		fclose(af->fp);
		af->fp = NULL;
	}
	if (af->tmp_path) {
		unlink(af->tmp_path);
		free(af->tmp_path);
		af->tmp_path = NULL;
	}
	free(af->path);
	af->path = NULL;
}

int pc_write_file_atomic(const char *path, const void *data, size_t size)
{
	pc_atomic_file af;
	int rc = pc_atomic_open(&af, path);
	if (rc)
		return rc;
	if (size && fwrite(data, 1, size, af.fp) != size) {
		int e = errno;
		pc_atomic_abort(&af);
		return pc_error(PC_EIO, "%s: write failed: %s", path, strerror(e));
	}
	return pc_atomic_commit(&af);
}

int pc_mkdir_p(const char *path)
{
	if (!path || !*path)
		return pc_error(PC_EINVAL, "directory path is empty");
	char *p = strdup(path);
	if (!p)
		return pc_error(PC_ENOMEM, "%s", path);
	for (char *s = p + 1;; s++) {
		if (*s == '/' || *s == '\0') {
			char c = *s;
			*s = '\0';
			if (mkdir(p, 0777) != 0 && errno != EEXIST) {
				int e = errno;
				int rc = pc_error(PC_EIO, "%s: cannot create directory: %s", p, strerror(e));
				free(p);
				return rc;
			}
			*s = c;
			if (c == '\0')
				break;
		}
	}
	struct stat st;
	int ok = stat(path, &st) == 0 && S_ISDIR(st.st_mode);
	free(p);
	if (!ok)
		return pc_error(PC_EIO, "%s: exists and is not a directory", path);
	return 0;
}
