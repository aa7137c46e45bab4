#include "core/fileio.h"

#include "core/err.h"

#include <errno.h>
#include <fcntl.h>
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

int cs_outfile_open(struct cs_outfile *of, const char *dst)
{
	memset(of, 0, sizeof *of);
	of->fd = -1;
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
	mode_t mask = umask(0);
	umask(mask);
	if (!of->to_stdout && !of->to_stream)
		fchmod(of->fd, 0666 & ~mask);
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
	struct cs_outfile of;
	int rc = cs_outfile_open(&of, path);
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

int cs_outfile_commit(struct cs_outfile *of)
{
	if (of->fd < 0)
		return cs_error(CS_EINVAL, "output is not open");
	int rc = CS_OK;
	int streamed = of->to_stdout || of->to_stream;
	if (streamed) {
		rc = copy_out(of);
	} else if (fsync(of->fd) < 0 && errno != EINVAL && errno != EROFS) {
		rc = cs_error(CS_EIO, "cannot write %s: %s", of->dst_path,
			      strerror(errno));
	}
	if (close(of->fd) < 0 && rc == CS_OK)
		rc = cs_error(CS_EIO, "cannot write %s: %s", of->dst_path,
			      strerror(errno));
	of->fd = -1;
	if (rc == CS_OK && !streamed && rename(of->tmp_path, of->dst_path) < 0)
		rc = cs_error(CS_EIO, "cannot rename temporary to %s: %s",
			      of->dst_path, strerror(errno));
	if (rc != CS_OK || streamed)
		unlink(of->tmp_path);
	of->tmp_path[0] = '\0';
	return rc;
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
