/* fileio.h - outputs that appear whole or not at all.
 *
 * An output is written to a temporary file in the destination's directory
 * (so the final rename is atomic) and renamed over the destination only when
 * complete.  On any failure the temporary is removed and an existing file at
 * the destination is left untouched. */
#ifndef CS_FILEIO_H
#define CS_FILEIO_H

#include <stddef.h>

struct cs_outfile {
	int fd;             /* open for writing, or -1 */
	char tmp_path[4096];
	char dst_path[4096];
	int to_stdout;      /* destination "-": temp in $TMPDIR, copied out */
	int to_stream;      /* existing non-regular destination: same, copied in */
};

/* Creates the temporary for dst ("-" means standard output; an existing
 * destination that is not a regular file, such as /dev/stdout or a FIFO,
 * is written in place at commit, never renamed over).  The file is
 * created with mode 0666 & ~umask, like an ordinary output. */
int cs_outfile_open(struct cs_outfile *of, const char *dst);

/* Writes n bytes to the temporary. */
int cs_outfile_write(struct cs_outfile *of, const void *buf, size_t n);

/* Flushes, closes and renames the temporary over the destination (or copies
 * it to standard output and removes it). */
int cs_outfile_commit(struct cs_outfile *of);

/* Closes and removes the temporary.  Safe to call after a failed open or
 * after commit. */
void cs_outfile_abort(struct cs_outfile *of);

/* Writes n bytes to path ("-": standard output) whole or not at all:
 * cs_outfile_open, _write, _commit, and _abort on a failure. */
int cs_write_file(const char *path, const void *buf, size_t n);

/* Writes all n bytes to fd, retrying interrupted and short writes.
 * Returns 0, or -1 with errno set (no message: the caller names the file). */
int cs_write_all(int fd, const void *buf, size_t n);

/* Reads a whole file ("-" = standard input) into a new buffer the caller
 * frees.  Fails with CS_EDATA if it is larger than max_bytes. */
int cs_read_all(const char *path, size_t max_bytes, unsigned char **data,
		size_t *len);

#endif
