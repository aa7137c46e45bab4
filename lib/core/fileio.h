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
	int no_clobber;     /* CS_OUT_NO_CLOBBER: never replace an existing file */
};

/* Flags of an output.  CS_OUT_NO_CLOBBER: an existing regular file (or a
 * link) at the destination is an error, never replaced; devices and pipes
 * (/dev/stdout, a FIFO) are still written. */
#define CS_OUT_NO_CLOBBER 1

/* Creates the temporary for dst ("-" means standard output; an existing
 * destination that is not a regular file, such as /dev/stdout or a FIFO,
 * is written in place at commit, never renamed over).  The file is
 * created with mode 0666 & ~umask, like an ordinary output. */
int cs_outfile_open(struct cs_outfile *of, const char *dst);

/* cs_outfile_open() with flags (CS_OUT_NO_CLOBBER). */
int cs_outfile_open_flags(struct cs_outfile *of, const char *dst, int flags);

/* Checks, before any long work and without creating anything, that dst
 * could be written: it is not a directory, its directory exists and is
 * writable (or, for an existing device or pipe, it is writable), and with
 * CS_OUT_NO_CLOBBER that no file is there.  "-" always passes. */
int cs_outfile_check(const char *dst, int flags);

/* Writes n bytes to the temporary. */
int cs_outfile_write(struct cs_outfile *of, const void *buf, size_t n);

/* Flushes, closes and renames the temporary over the destination (or copies
 * it to standard output and removes it). */
int cs_outfile_commit(struct cs_outfile *of);

/* Closes and removes the temporary.  Safe to call after a failed open or
 * after commit. */
void cs_outfile_abort(struct cs_outfile *of);

/* Several outputs of one run that appear all together or not at all:
 * every temporary is written first, then all are renamed at the end.  A
 * failure before the renames leaves nothing; a rename that fails after
 * others succeeded (a disk removed between two renames in the same
 * directory) removes the outputs already placed when they were new
 * (CS_OUT_NO_CLOBBER), and can only report the others. */
#define CS_OUTSET_MAX 8
struct cs_outset {
	struct cs_outfile of[CS_OUTSET_MAX];
	int n;
	int flags;
};

/* Checks a run's outputs before its work: each with cs_outfile_check(),
 * and no two naming the same file ("-" twice included). */
int cs_outset_check(const char *const *paths, int n, int flags);

void cs_outset_init(struct cs_outset *s, int flags);

/* Opens the temporary of one more output; *of stays valid until
 * cs_outset_commit() or cs_outset_abort(). */
int cs_outset_open(struct cs_outset *s, const char *dst, struct cs_outfile **of);

/* Copies the standard-stream outputs out, then renames every temporary
 * over its destination.  On failure nothing of the set is left behind
 * (see above for the one exception). */
int cs_outset_commit(struct cs_outset *s);

/* Removes every temporary.  Safe after a failed open or a commit. */
void cs_outset_abort(struct cs_outset *s);

/* Writes n bytes to path ("-": standard output) whole or not at all:
 * cs_outfile_open, _write, _commit, and _abort on a failure. */
int cs_write_file(const char *path, const void *buf, size_t n);

/* cs_write_file() with flags (CS_OUT_NO_CLOBBER). */
int cs_write_file_flags(const char *path, const void *buf, size_t n, int flags);

/* Writes all n bytes to fd, retrying interrupted and short writes.
 * Returns 0, or -1 with errno set (no message: the caller names the file). */
int cs_write_all(int fd, const void *buf, size_t n);

/* Reads a whole file ("-" = standard input) into a new buffer the caller
 * frees.  Fails with CS_EDATA if it is larger than max_bytes. */
int cs_read_all(const char *path, size_t max_bytes, unsigned char **data,
		size_t *len);

#endif
