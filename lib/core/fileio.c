#include "core/fileio.h"

#include "core/err.h"

#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int cs_write_all(int fd, const void *buf, size_t n)
{
	const char *p = buf;
	while (n > 0) {
		ssize_t w = write(fd, p, n);
		if (w < 0) {
			if (errno == EINTR)
				continue;
			return -1;
		}
		p += w;
		n -= (size_t)w;
	}
	return 0;
}

/* The process's umask, read once: reading it sets it, so two threads
 * reading it at once (a series writes frames on several) could leave it 0. */
static pthread_once_t umask_once = PTHREAD_ONCE_INIT;
static mode_t process_umask;

static void read_umask(void)
{
	process_umask = umask(0);
	umask(process_umask);
}

/* The message of an existing destination under CS_OUT_NO_CLOBBER. */
static int exists_error(const char *dst)
{
	return cs_error(CS_EIO, "%s exists: not overwritten (--no-clobber)", dst);
}

/* dst's directory ("." for a bare name), into dir. */
static int dir_of(const char *dst, char *dir, size_t size)
{
	const char *slash = strrchr(dst, '/');
	int n = slash ? snprintf(dir, size, "%.*s", (int)(slash - dst + 1), dst)
		      : snprintf(dir, size, ".");
	if (n < 0 || (size_t)n >= size)
		return cs_error(CS_EINVAL, "output file name too long");
	return CS_OK;
}

int cs_outfile_check(const char *dst, int flags)
{
	if (dst == NULL || dst[0] == '\0')
		return cs_error(CS_EINVAL, "empty output file name");
	if (strcmp(dst, "-") == 0)
		return CS_OK;
	struct stat st;
	if (stat(dst, &st) == 0) {
		if (S_ISDIR(st.st_mode))
			return cs_error(CS_EIO, "cannot write %s: Is a directory", dst);
		if (!S_ISREG(st.st_mode))
			return access(dst, W_OK) == 0
				       ? CS_OK
				       : cs_error(CS_EIO, "cannot write %s: %s", dst, strerror(errno));
	}
	if ((flags & CS_OUT_NO_CLOBBER) && lstat(dst, &st) == 0)
		return exists_error(dst);
	char dir[4096];
	int rc = dir_of(dst, dir, sizeof dir);
	if (rc != CS_OK)
		return rc;
	if (stat(dir, &st) < 0)
		return cs_error(CS_EIO, "cannot create %s: %s", dst, strerror(errno));
	if (!S_ISDIR(st.st_mode))
		return cs_error(CS_EIO, "cannot create %s: %s is not a directory", dst, dir);
	if (access(dir, W_OK | X_OK) < 0)
		return cs_error(CS_EIO, "cannot create %s: %s", dst, strerror(errno));
	return CS_OK;
}

int cs_outfile_open(struct cs_outfile *of, const char *dst)
{
	return cs_outfile_open_flags(of, dst, 0);
}

int cs_outfile_open_flags(struct cs_outfile *of, const char *dst, int flags)
{
	memset(of, 0, sizeof *of);
	of->fd = -1;
	of->no_clobber = (flags & CS_OUT_NO_CLOBBER) != 0;
	if (dst == NULL || dst[0] == '\0')
		return cs_error(CS_EINVAL, "empty output file name");
	of->to_stdout = strcmp(dst, "-") == 0;
	/* An existing destination that is not a regular file (/dev/stdout, a
	 * FIFO, a device) is written in place, never renamed over. */
	struct stat st;
	if (!of->to_stdout && stat(dst, &st) == 0 && !S_ISREG(st.st_mode)) {
		if (S_ISDIR(st.st_mode))
			return cs_error(CS_EIO, "cannot write %s: Is a directory", dst);
		of->to_stream = 1;
	}
	if (!of->to_stdout && !of->to_stream && of->no_clobber && lstat(dst, &st) == 0)
		return exists_error(dst);
	if (strlen(dst) >= sizeof of->dst_path)
		return cs_error(CS_EINVAL, "output file name too long");
	strcpy(of->dst_path, dst);
	int n;
	if (of->to_stdout || of->to_stream) {
		const char *tmpdir = getenv("TMPDIR");
		if (tmpdir == NULL || tmpdir[0] == '\0')
			tmpdir = "/tmp";
		n = snprintf(of->tmp_path, sizeof of->tmp_path,
			     "%s/cloudscape-stdout.XXXXXX", tmpdir);
	} else {
		const char *slash = strrchr(dst, '/');
		int dirlen = slash ? (int)(slash - dst) + 1 : 0;
		n = snprintf(of->tmp_path, sizeof of->tmp_path, "%.*s.%s.XXXXXX",
			     dirlen, dst, slash ? slash + 1 : dst);
	}
	if (n < 0 || (size_t)n >= sizeof of->tmp_path)
		return cs_error(CS_EINVAL, "output file name too long");
	of->fd = mkstemp(of->tmp_path);
	if (of->fd < 0) {
		int e = errno;
		of->tmp_path[0] = '\0';
		return cs_error(CS_EIO, "cannot create %s: %s",
				of->to_stdout || of->to_stream ? "temporary file" : dst,
				strerror(e));
	}
	/* mkstemp makes the file 0600; give it the mode a plain open() would */
	pthread_once(&umask_once, read_umask);
	if (!of->to_stdout && !of->to_stream)
		fchmod(of->fd, 0666 & ~process_umask);
	return CS_OK;
}

int cs_outfile_write(struct cs_outfile *of, const void *buf, size_t n)
{
	if (cs_write_all(of->fd, buf, n) < 0)
		return cs_error(CS_EIO, "cannot write %s: %s",
				of->to_stdout ? "standard output" : of->dst_path,
				strerror(errno));
	return CS_OK;
}

int cs_write_file(const char *path, const void *buf, size_t n)
{
	return cs_write_file_flags(path, buf, n, 0);
}

int cs_write_file_flags(const char *path, const void *buf, size_t n, int flags)
{
	struct cs_outfile of;
	int rc = cs_outfile_open_flags(&of, path, flags);
	if (rc == CS_OK)
		rc = cs_outfile_write(&of, buf, n);
	if (rc == CS_OK)
		return cs_outfile_commit(&of);
	cs_outfile_abort(&of);
	return rc;
}

/* Copies the finished temporary to standard output or to the stream
 * destination. */
static int copy_out(struct cs_outfile *of)
{
	const char *name = of->to_stdout ? "standard output" : of->dst_path;
	int out = of->to_stdout ? STDOUT_FILENO : open(of->dst_path, O_WRONLY);
	if (out < 0)
		return cs_error(CS_EIO, "cannot open %s: %s", name, strerror(errno));
	char buf[65536];
	int rc = CS_OK;
	if (lseek(of->fd, 0, SEEK_SET) < 0)
		rc = cs_error(CS_EIO, "cannot rewind temporary: %s", strerror(errno));
	while (rc == CS_OK) {
		ssize_t r = read(of->fd, buf, sizeof buf);
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0)
			rc = cs_error(CS_EIO, "cannot read temporary: %s",
				      strerror(errno));
		else if (r == 0)
			break;
		else if (cs_write_all(out, buf, (size_t)r) < 0)
			rc = cs_error(CS_EIO, "cannot write %s: %s", name,
				      strerror(errno));
	}
	if (out != STDOUT_FILENO && close(out) < 0 && rc == CS_OK)
		rc = cs_error(CS_EIO, "cannot write %s: %s", name, strerror(errno));
	return rc;
}

/* The first half of a commit: the data on disk (or copied out to a
 * stream) and the temporary closed. */
static int finish(struct cs_outfile *of)
{
	if (of->fd < 0)
		return cs_error(CS_EINVAL, "output is not open");
	int rc = CS_OK;
	if (of->to_stdout || of->to_stream) {
		rc = copy_out(of);
	} else if (fsync(of->fd) < 0 && errno != EINVAL && errno != EROFS) {
		rc = cs_error(CS_EIO, "cannot write %s: %s", of->dst_path,
			      strerror(errno));
	}
	if (close(of->fd) < 0 && rc == CS_OK)
		rc = cs_error(CS_EIO, "cannot write %s: %s", of->dst_path,
			      strerror(errno));
	of->fd = -1;
	return rc;
}

/* The second half: the finished temporary renamed over the destination
 * (under CS_OUT_NO_CLOBBER linked, which fails if something appeared there
 * meanwhile), or removed after a stream's copy. */
static int place(struct cs_outfile *of)
{
	int rc = CS_OK;
	if (of->to_stdout || of->to_stream) {
		/* copied out by finish() */
	} else if (of->no_clobber) {
		if (link(of->tmp_path, of->dst_path) < 0) {
			int e = errno;
			struct stat st;
			if (e == EEXIST)
				rc = exists_error(of->dst_path);
			else if (lstat(of->dst_path, &st) == 0) /* no hard links here */
				rc = exists_error(of->dst_path);
			else if (rename(of->tmp_path, of->dst_path) < 0)
				rc = cs_error(CS_EIO, "cannot rename temporary to %s: %s",
					      of->dst_path, strerror(errno));
			else
				of->tmp_path[0] = '\0';
		}
	} else if (rename(of->tmp_path, of->dst_path) < 0) {
		rc = cs_error(CS_EIO, "cannot rename temporary to %s: %s",
			      of->dst_path, strerror(errno));
	} else {
		of->tmp_path[0] = '\0';
	}
	if (of->tmp_path[0] != '\0')
		unlink(of->tmp_path);
	of->tmp_path[0] = '\0';
	return rc;
}

int cs_outfile_commit(struct cs_outfile *of)
{
	int rc = finish(of);
	if (rc != CS_OK) {
		cs_outfile_abort(of);
		return rc;
	}
	return place(of);
}

void cs_outfile_abort(struct cs_outfile *of)
{
	if (of->fd >= 0)
		close(of->fd);
	of->fd = -1;
	if (of->tmp_path[0] != '\0')
		unlink(of->tmp_path);
	of->tmp_path[0] = '\0';
}

/* ---- sets of outputs -------------------------------------------------- */

/* Whether a and b name one file: the same existing file, or the same name
 * in the same directory. */
static int same_file(const char *a, const char *b)
{
	if (strcmp(a, b) == 0)
		return 1;
	if (strcmp(a, "-") == 0 || strcmp(b, "-") == 0)
		return 0;
	struct stat sa, sb;
	if (stat(a, &sa) == 0 && stat(b, &sb) == 0)
		return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
	const char *ba = strrchr(a, '/'), *bb = strrchr(b, '/');
	ba = ba ? ba + 1 : a;
	bb = bb ? bb + 1 : b;
	if (strcmp(ba, bb) != 0)
		return 0;
	char da[4096], db[4096];
	if (dir_of(a, da, sizeof da) != CS_OK || dir_of(b, db, sizeof db) != CS_OK)
		return 0;
	return stat(da, &sa) == 0 && stat(db, &sb) == 0 && sa.st_dev == sb.st_dev &&
	       sa.st_ino == sb.st_ino;
}

int cs_outset_check(const char *const *paths, int n, int flags)
{
	if (n > CS_OUTSET_MAX)
		return cs_error(CS_EINVAL, "at most %d outputs", CS_OUTSET_MAX);
	for (int i = 0; i < n; i++)
		for (int j = 0; j < i; j++)
			if (same_file(paths[i], paths[j]))
				return cs_error(CS_EINVAL, "%s is named twice as an output%s",
						strcmp(paths[i], "-") == 0 ? "'-' (standard output)"
									   : paths[i],
						strcmp(paths[i], paths[j]) == 0 ? "" : " (as the same file)");
	for (int i = 0; i < n; i++) {
		int rc = cs_outfile_check(paths[i], flags);
		if (rc != CS_OK)
			return rc;
	}
	return CS_OK;
}

void cs_outset_init(struct cs_outset *s, int flags)
{
	memset(s, 0, sizeof *s);
	s->flags = flags;
	for (int i = 0; i < CS_OUTSET_MAX; i++)
		s->of[i].fd = -1;
}

int cs_outset_open(struct cs_outset *s, const char *dst, struct cs_outfile **of)
{
	if (s->n == CS_OUTSET_MAX)
		return cs_error(CS_EINVAL, "at most %d outputs", CS_OUTSET_MAX);
	int rc = cs_outfile_open_flags(&s->of[s->n], dst, s->flags);
	if (rc != CS_OK)
		return rc;
	*of = &s->of[s->n++];
	return CS_OK;
}

int cs_outset_commit(struct cs_outset *s)
{
	int rc = CS_OK;
	/* streams first: once a file is renamed it cannot be taken back,
	 * while standard output is the likelier to fail (a closed pipe) */
	for (int pass = 0; pass < 2 && rc == CS_OK; pass++)
		for (int i = 0; i < s->n && rc == CS_OK; i++) {
			struct cs_outfile *of = &s->of[i];
			int streamed = of->to_stdout || of->to_stream;
			if (streamed == (pass == 0))
				rc = finish(of);
		}
	int placed = 0;
	while (rc == CS_OK && placed < s->n)
		if ((rc = place(&s->of[placed])) == CS_OK)
			placed++;
	if (rc != CS_OK) {
		/* the outputs this set created are taken back; the ones that
		 * replaced a file cannot be */
		for (int i = 0; i < placed; i++) {
			struct cs_outfile *of = &s->of[i];
			if (of->no_clobber && !of->to_stdout && !of->to_stream)
				unlink(of->dst_path);
		}
	}
	cs_outset_abort(s);
	return rc;
}

void cs_outset_abort(struct cs_outset *s)
{
	for (int i = 0; i < s->n; i++)
		cs_outfile_abort(&s->of[i]);
	s->n = 0;
}

int cs_read_all(const char *path, size_t max_bytes, unsigned char **data,
		size_t *len)
{
	int fd = strcmp(path, "-") == 0 ? STDIN_FILENO : open(path, O_RDONLY);
	if (fd < 0)
		return cs_error(CS_EIO, "cannot open %s: %s", path,
				strerror(errno));
	size_t cap = 65536, n = 0;
	unsigned char *buf = malloc(cap);
	int rc = CS_OK;
	if (buf == NULL) {
		rc = cs_error(CS_ENOMEM, "out of memory reading %s", path);
		goto done;
	}
	for (;;) {
		if (n == cap) {
			if (cap > max_bytes) {
				rc = cs_error(CS_EDATA, "%s is larger than %zu bytes",
					      path, max_bytes);
				goto done;
			}
			unsigned char *nb = realloc(buf, cap * 2);
			if (nb == NULL) {
				rc = cs_error(CS_ENOMEM, "out of memory reading %s",
					      path);
				goto done;
			}
			buf = nb;
			cap *= 2;
		}
		ssize_t r = read(fd, buf + n, cap - n);
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0) {
			rc = cs_error(CS_EIO, "cannot read %s: %s", path,
				      strerror(errno));
			goto done;
		}
		if (r == 0)
			break;
		n += (size_t)r;
	}
	if (n > max_bytes) {
		rc = cs_error(CS_EDATA, "%s is larger than %zu bytes", path,
			      max_bytes);
		goto done;
	}
	*data = buf;
	*len = n;
	buf = NULL;
done:
	free(buf);
	if (fd != STDIN_FILENO)
		close(fd);
	return rc;
}
