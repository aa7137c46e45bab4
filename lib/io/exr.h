/* exr.h - OpenEXR output through the OpenEXR C API (OpenEXRCore), and the
 * pieces the readers share.  All I/O goes through our callbacks: writes into
 * a cs_outfile temporary (atomic), reads from memory (a truncated file is a
 * short read), and the core's messages are kept, never printed. */
#ifndef CS_EXR_H
#define CS_EXR_H

#include "core/err.h"

#include <openexr.h>

#include <stddef.h>

struct cs_exr_channel {
	const char *name;
	int is_float;       /* 1: 32-bit float; 0: half */
	const float *data;  /* pixel (x, y) is data[(y * width + x) * stride] */
	size_t stride;      /* floats from one pixel to the next */
};

enum cs_exr_attr_type { CS_EXR_INT, CS_EXR_STRING, CS_EXR_V3I, CS_EXR_DOUBLE, CS_EXR_FLOAT };

struct cs_exr_attr {
	const char *name;
	enum cs_exr_attr_type type;
	int i[3];           /* CS_EXR_INT: i[0]; CS_EXR_V3I: all three */
	const char *s;      /* CS_EXR_STRING */
	double d;           /* CS_EXR_DOUBLE, CS_EXR_FLOAT (rounded to float) */
};

/* Writes a single-part scanline image, ZIP-compressed, with the given
 * channels (any order; the file sorts them) and extra attributes, to path
 * ("-" = stdout).  Atomic: no partial file on failure.  The chunks are
 * compressed, and read back to be checked, on nthreads threads (<= 0: one
 * per processor); the file is the same bytes for any number. */
int cs_exr_write(const char *path, int width, int height,
		 const struct cs_exr_channel *ch, int nch,
		 const struct cs_exr_attr *attrs, int nattrs, int nthreads);

struct cs_outfile;

/* cs_exr_write() into an open output (core/fileio.h), not committed; name
 * labels messages. */
int cs_exr_write_to(struct cs_outfile *of, const char *name, int width, int height,
		    const struct cs_exr_channel *ch, int nch,
		    const struct cs_exr_attr *attrs, int nattrs, int nthreads);

/* A memory source for exr_start_read(). */
struct cs_exr_mem {
	const unsigned char *data;
	size_t len;
};

/* Fills init to read from src and to keep error messages (no printing). */
void cs_exr_reader_init(exr_context_initializer_t *init, struct cs_exr_mem *src);

/* Reads channels (half or 32-bit float) of a single-part scanline image
 * held in memory, in one pass: *pixels (malloc'ed for the caller) holds
 * nch floats per pixel in the order asked, *width * *height pixels, row 0
 * first.  Other channels are ignored.  name labels messages (a file name).
 * Errors are CS_EDATA ("name: why"). */
int cs_exr_read_channels(const void *data, size_t len, const char *name,
			 const char *const *channels, int nch, int *width,
			 int *height, float **pixels);

/* cs_exr_read_channels with the chunks decoded on nthreads threads (<= 0:
 * one per processor); the same pixels for any number. */
int cs_exr_read_channels_threads(const void *data, size_t len, const char *name,
				 const char *const *channels, int nch, int nthreads,
				 int *width, int *height, float **pixels);

/* Reads one channel (half or 32-bit float) of a single-part scanline image
 * held in memory as floats: *pixels (malloc'ed for the caller) holds
 * *width * *height values, row 0 first.  Other channels are ignored.  name
 * labels messages (a file name).  Errors are CS_EDATA ("name: why"). */
int cs_exr_read_float_channel(const void *data, size_t len, const char *name,
			      const char *channel, int *width, int *height,
			      float **pixels);

/* The most bytes of pixel data a file of len bytes can hold under the
 * given compression (an exr_compression_t): what a header may claim. */
size_t cs_exr_max_pixel_bytes(size_t len, int compression);
/* The core's last message on this thread, or the default text of code. */
const char *cs_exr_message(exr_result_t code);

/* Checks a call of the OpenEXR core inside a function with an int rc and
 * a cleanup label: on failure sets rc = code with the message "name: what:
 * the core's message" (name: the file, a string) and jumps to label. */
#define CS_EXR_CHECK(call, code, name, what, label)                           \
	do {                                                                  \
		exr_result_t r_ = (call);                                     \
		if (r_ != EXR_ERR_SUCCESS) {                                  \
			rc = cs_error(code, "%s: %s: %s", name, what,          \
				      cs_exr_message(r_));                     \
			goto label;                                           \
		}                                                             \
	} while (0)

#endif
