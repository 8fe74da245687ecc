/* Atomic files: a temporary file beside the destination, renamed into place when whole.
 *
 * A process killed before the rename (SIGKILL, a crash, a power cut) can leave only the
 * temporary file, never a partial file under the final name. Temporary files are named
 * ".NAME.tmpXXXXXX" (mkstemp) and their writer holds an exclusive flock() on them from creation
 * to the rename or removal, so that pc_atomic_sweep can tell a leftover (nobody holds its lock:
 * the kernel released it when the writer died) from a file being written now. */
#include "polarcam/io.h"

#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
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
		return pc_error(PC_EINVAL, "%s: file name of %zu bytes: too long (at most %d)",
		                path, base, NAME_MAX);
	}
	const size_t decor = strlen("..tmpXXXXXX");
	if (keep + decor > NAME_MAX) {
		keep = NAME_MAX - decor;
		while (keep > 0 && ((unsigned char)path[dir + keep] & 0xc0) == 0x80)
			keep--;
	}
	snprintf(af->tmp_path + dir, n + 32 - dir, ".%.*s.tmpXXXXXX", (int)keep, path + dir);
	/* The lock taken at once marks the file as being written. A sweeper that found it in the
	 * instant between mkstemp and flock, unlocked, may have removed it: then the name has no
	 * link any more (st_nlink == 0) and a new temporary file is made. */
	char *tmpl = af->tmp_path + strlen(af->tmp_path) - 6;
	int fd = -1;
	for (int attempt = 0; attempt < 8; attempt++) {
		memcpy(tmpl, "XXXXXX", 6);
		fd = mkstemp(af->tmp_path);
		if (fd < 0)
			break;
		struct stat st;
		if (flock(fd, LOCK_EX) == 0 && fstat(fd, &st) == 0 && st.st_nlink > 0)
			break;
		close(fd);
		fd = -1;
		errno = EAGAIN;
	}
	if (fd < 0) {
		int e = errno;
		free(af->tmp_path);
		af->tmp_path = NULL;
		pc_atomic_abort(af);
		/* a name the file system cannot hold is a bad argument, not an I/O failure */
		return pc_error(e == ENOENT         ? PC_ENOENT
		                : e == EACCES       ? PC_EPERM
		                : e == ENAMETOOLONG ? PC_EINVAL
		                                    : PC_EIO,
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
	int fd = fileno(af->fp);
	if (!bad && fsync(fd) != 0) {
		bad = 1;
		e = errno;
	}
	if (bad) {
		int rc = pc_error(PC_EIO, "%s: write failed: %s", af->path, strerror(e));
		pc_atomic_abort(af);
		return rc;
	}
	/* mkstemp creates 0600; give the file the usual permissions (umask applies). */
	mode_t um = umask(0);
	umask(um);
	fchmod(fd, 0666 & ~um);
	/* renamed while the lock is held: a sweeper never sees the whole file unlocked under its
	 * temporary name */
	if (rename(af->tmp_path, af->path) != 0) {
		e = errno;
		int rc =
		    pc_error(PC_EIO, "%s: cannot rename into place: %s", af->path, strerror(e));
		pc_atomic_abort(af);
		return rc;
	}
	free(af->tmp_path);
	af->tmp_path = NULL;
	if (fclose(af->fp) != 0) { /* the data was flushed and synced: nothing is lost here */
		e = errno;
		af->fp = NULL;
		int rc = pc_error(PC_EIO, "%s: closing: %s", af->path, strerror(e));
		pc_atomic_abort(af);
		return rc;
	}
	af->fp = NULL;
	free(af->path);
	af->path = NULL;
	return 0;
}

void pc_atomic_abort(pc_atomic_file *af)
{
	if (af->tmp_path) { /* removed before the lock goes with the close */
		unlink(af->tmp_path);
		free(af->tmp_path);
		af->tmp_path = NULL;
	}
	if (af->fp) {
		fclose(af->fp);
		af->fp = NULL;
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
				int rc = pc_error(PC_EIO, "%s: cannot create directory: %s", p,
				                  strerror(e));
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

/* ".NAME.tmpXXXXXX" as pc_atomic_open makes them (NAME possibly cut short). */
static int is_atomic_tmp_name(const char *n)
{
	size_t len = strlen(n);
	if (len < 1 + 4 + 6 + 1 || n[0] != '.' || memcmp(n + len - 10, ".tmp", 4) != 0)
		return 0;
	for (size_t i = len - 6; i < len; i++) {
		char c = n[i];
		if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9')))
			return 0;
	}
	return 1;
}

int pc_atomic_sweep(const char *dir, unsigned *removed)
{
	if (removed)
		*removed = 0;
	if (!dir || !*dir)
		return pc_error(PC_EINVAL, "sweep: directory path is empty");
	DIR *d = opendir(dir);
	if (!d) {
		int e = errno;
		if (e == ENOENT)
			return 0; /* nothing was ever written there */
		return pc_error(e == EACCES ? PC_EPERM : PC_EIO, "%s: %s", dir, strerror(e));
	}
	int dfd = dirfd(d);
	struct dirent *de;
	while ((de = readdir(d))) {
		if (!is_atomic_tmp_name(de->d_name))
			continue;
		int fd = openat(dfd, de->d_name, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
		if (fd < 0)
			continue;
		struct stat st;
		/* a regular file whose lock nobody holds: its writer is gone */
		if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode) &&
		    flock(fd, LOCK_EX | LOCK_NB) == 0 && unlinkat(dfd, de->d_name, 0) == 0 &&
		    removed)
			(*removed)++;
		close(fd);
	}
	closedir(d);
	return 0;
}
