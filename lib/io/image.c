#include "io/image.h"

#include "core/color.h"
#include "core/err.h"
#include "core/fileio.h"

#include <png.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int cs_png_write_to(struct cs_outfile *of, const char *name, int width,
		    int height, int channels, const uint8_t *pixels)
{
	static const png_uint_32 formats[5] = {0, PNG_FORMAT_GRAY, 0,
					       PNG_FORMAT_RGB, PNG_FORMAT_RGBA};
	if (width < 1 || height < 1 || channels < 1 || channels > 4 ||
	    channels == 2)
		return cs_error(CS_EINVAL, "cannot write a %dx%d PNG with %d channels",
				width, height, channels);
	int fd = dup(of->fd);
	FILE *fp = fd >= 0 ? fdopen(fd, "wb") : NULL;
	if (fp == NULL) {
		if (fd >= 0)
			close(fd);
		return cs_error(CS_EIO, "%s: cannot open stream", name);
	}
	png_image img;
	memset(&img, 0, sizeof img);
	img.version = PNG_IMAGE_VERSION;
	img.width = (png_uint_32)width;
	img.height = (png_uint_32)height;
	img.format = formats[channels];
	int ok = png_image_write_to_stdio(&img, fp, 0, pixels,
					  width * channels, NULL);
	int closed = fclose(fp) == 0;
	if (!ok || !closed) {
		int rc = cs_error(CS_EIO, "%s: cannot write PNG: %s", name,
				  ok ? "write failed" : img.message);
		png_image_free(&img);
		return rc;
	}
	return CS_OK;
}

int cs_png_write(const char *path, int width, int height, int channels,
		 const uint8_t *pixels)
{
	struct cs_outfile of;
	int rc = cs_outfile_open(&of, path);
	if (rc != CS_OK)
		return rc;
	const char *name = strcmp(path, "-") == 0 ? "standard output" : path;
	rc = cs_png_write_to(&of, name, width, height, channels, pixels);
	if (rc != CS_OK) {
		cs_outfile_abort(&of);
		return rc;
	}
	return cs_outfile_commit(&of);
}

/* libpng's error callback: the message kept, then back to the setjmp. */
static void png16_error(png_structp png, png_const_charp msg)
{
	char *buf = png_get_error_ptr(png);
	snprintf(buf, 200, "%s", msg);
	png_longjmp(png, 1);
}

static void png16_warning(png_structp png, png_const_charp msg)
{
	(void)png;
	(void)msg;
}

/* The body of cs_png16_write_to() and cs_png_write_text_to(), on a
 * stream: 8 or 16 bits a sample, text chunks (iTXt where flagged); 0 or a
 * message in why. */
static int png_stream(FILE *fp, int width, int height, int channels, int bits,
		      const void *pixels, const struct cs_png_text *text, int ntext,
		      char why[200])
{
	static const int types[5] = {0, PNG_COLOR_TYPE_GRAY, 0, PNG_COLOR_TYPE_RGB,
				     PNG_COLOR_TYPE_RGB_ALPHA};
	png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, why,
						  png16_error, png16_warning);
	png_infop info = png ? png_create_info_struct(png) : NULL;
	size_t rowlen = (size_t)width * channels * (size_t)(bits / 8);
	unsigned char *volatile row = malloc(rowlen);
	png_text *volatile chunks = ntext > 0 ? calloc((size_t)ntext, sizeof *chunks) : NULL;
	if (png == NULL || info == NULL || row == NULL || (ntext > 0 && chunks == NULL)) {
		snprintf(why, 200, "out of memory");
		png_destroy_write_struct(&png, &info);
		free(row);
		free(chunks);
		return -1;
	}
	if (setjmp(png_jmpbuf(png))) {
		png_destroy_write_struct(&png, &info);
		free(row);
		free(chunks);
		return -1;
	}
	png_init_io(png, fp);
	png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, bits, types[channels],
		     PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
	png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
	/* deflate level 3 and every row the Sub filter (libpng's default:
	 * level 6, each row's best of five filters): a 1280x720 render of the
	 * default sky in 0.034 s instead of 0.129 s, 411 kB instead of 373 kB
	 * (level 6 with Sub: 0.106 s, 348 kB; level 1: 0.018 s, 455 kB) */
	png_set_compression_level(png, 3);
	png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
	for (int i = 0; i < ntext; i++) {
		chunks[i].compression = text[i].itxt ? PNG_ITXT_COMPRESSION_NONE
						     : PNG_TEXT_COMPRESSION_NONE;
		chunks[i].key = (png_charp)text[i].key;
		chunks[i].text = (png_charp)text[i].text;
		chunks[i].text_length = strlen(text[i].text);
	}
	if (ntext > 0)
		png_set_text(png, info, chunks, ntext);
	png_write_info(png, info);
	for (int y = 0; y < height; y++) {
		if (bits == 8) {
			png_write_row(png, (png_const_bytep)pixels + (size_t)y * rowlen);
			continue;
		}
		const uint16_t *src = (const uint16_t *)pixels + (size_t)y * width * channels;
		for (size_t i = 0; i < (size_t)width * channels; i++) { /* big-endian */
			row[2 * i] = (unsigned char)(src[i] >> 8);
			row[2 * i + 1] = (unsigned char)(src[i] & 0xff);
		}
		png_write_row(png, row);
	}
	png_write_end(png, NULL);
	png_destroy_write_struct(&png, &info);
	free(row);
	free(chunks);
	return 0;
}

/* cs_png16_write_to() and cs_png_write_text_to(): checks, the stream. */
static int png_write_any(struct cs_outfile *of, const char *name, int width, int height,
			 int channels, int bits, const void *pixels,
			 const struct cs_png_text *text, int ntext)
{
	if (width < 1 || height < 1 || channels < 1 || channels > 4 || channels == 2 ||
	    (bits != 8 && bits != 16))
		return cs_error(CS_EINVAL, "cannot write a %dx%d PNG with %d channels of %d bits",
				width, height, channels, bits);
	int fd = dup(of->fd);
	FILE *fp = fd >= 0 ? fdopen(fd, "wb") : NULL;
	if (fp == NULL) {
		if (fd >= 0)
			close(fd);
		return cs_error(CS_EIO, "%s: cannot open stream", name);
	}
	char why[200] = "";
	int bad = png_stream(fp, width, height, channels, bits, pixels, text, ntext, why);
	int closed = fclose(fp) == 0;
	if (bad || !closed)
		return cs_error(CS_EIO, "%s: cannot write PNG: %s", name,
				bad ? why : "write failed");
	return CS_OK;
}

int cs_png_write_text_to(struct cs_outfile *of, const char *name, int width, int height,
			 int channels, int bits, const void *pixels,
			 const struct cs_png_text *text, int ntext)
{
	return png_write_any(of, name, width, height, channels, bits, pixels, text, ntext);
}

int cs_png16_write_to(struct cs_outfile *of, const char *name, int width,
		      int height, int channels, const uint16_t *pixels)
{
	return png_write_any(of, name, width, height, channels, 16, pixels, NULL, 0);
}

/* The most bytes of an image's pixel data a PNG of len bytes can hold:
 * zlib's best ratio, 1032:1 (RFC 1951). */
#define PNG_MAX_RATIO 1032
#define PNG_MAX_FILE_BYTES ((size_t)1 << 30)

int cs_png_read_rgb8_mem(const void *data, size_t len, const char *name,
			 uint8_t **rgb, int *width, int *height)
{
	png_image img;
	memset(&img, 0, sizeof img);
	img.version = PNG_IMAGE_VERSION;
	*rgb = NULL;
	if (!png_image_begin_read_from_memory(&img, data, len))
		return cs_error(CS_EDATA, "%s: not a readable PNG: %s", name, img.message);
	if (img.width < 1 || img.height < 1 ||
	    (double)img.width * img.height > CS_PNG_MAX_PIXELS) {
		png_image_free(&img);
		return cs_error(CS_EDATA, "%s: a %ux%u image is too large (at most %.0f pixels)",
				name, img.width, img.height, (double)CS_PNG_MAX_PIXELS);
	}
	/* every row is a filter byte and at least one bit a pixel */
	double least = (double)img.height * (1.0 + ceil(img.width / 8.0));
	if (least > (double)PNG_MAX_RATIO * (double)len) {
		png_image_free(&img);
		return cs_error(CS_EDATA, "%s: the header claims %ux%u pixels, more than a "
				"file of %zu bytes can hold (corrupt or hostile header)",
				name, img.width, img.height, len);
	}
	img.format = PNG_FORMAT_RGB;
	uint8_t *buf = malloc(PNG_IMAGE_SIZE(img));
	if (buf == NULL) {
		png_image_free(&img);
		return cs_error(CS_ENOMEM, "%s: out of memory for %ux%u pixels", name,
				img.width, img.height);
	}
	if (!png_image_finish_read(&img, NULL, buf, 0, NULL)) {
		free(buf);
		return cs_error(CS_EDATA, "%s: %s", name, img.message);
	}
	*rgb = buf;
	*width = (int)img.width;
	*height = (int)img.height;
	return CS_OK;
}

int cs_png_read_rgb8(const char *path, uint8_t **rgb, int *width, int *height)
{
	unsigned char *data = NULL;
	size_t len = 0;
	*rgb = NULL;
	int rc = cs_read_all(path, PNG_MAX_FILE_BYTES, &data, &len);
	if (rc != CS_OK) /* an unreadable PNG is bad data to the caller, as before */
		return cs_error(CS_EDATA, "%s", cs_errmsg());
	rc = cs_png_read_rgb8_mem(data, len, strcmp(path, "-") == 0 ? "standard input" : path,
				  rgb, width, height);
	free(data);
	return rc;
}

double cs_tonemap_aces(double x)
{
	double y = (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14);
	return y < 0.0 ? 0.0 : y > 1.0 ? 1.0 : y;
}

double cs_srgb_oetf(double v)
{
	return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

double cs_auto_exposure_ev(const float *px, size_t stride, size_t n)
{
	double sum = 0.0;
	for (size_t i = 0; i < n; i++) {
		const float *p = px + i * stride;
		double y = cs_luminance(p[0], p[1], p[2]);
		sum += log(isfinite(y) && y > 1e-9 ? y : 1e-9);
	}
	double avg = n ? exp(sum / (double)n) : 1.0;
	/* x = L 2^ev / 16 = 0.25 at L = avg; within the range --exposure
	 * accepts, which a black frame (32 EV) or the sun's disk would leave */
	double ev = log2(0.25 * 16.0 / avg);
	return ev < CS_EXPOSURE_MIN_EV ? CS_EXPOSURE_MIN_EV :
	       ev > CS_EXPOSURE_MAX_EV ? CS_EXPOSURE_MAX_EV : ev;
}

/* A linear value on the display, 0..1: scaled by k, finite and positive,
 * tone-mapped, sRGB-encoded. */
static double display(float v, double k)
{
	double x = v * k;
	x = isfinite(x) && x > 0.0 ? x : 0.0;
	return cs_srgb_oetf(cs_tonemap_aces(x));
}

void cs_tonemap_srgb8(const float *px, size_t stride, size_t n,
		      double exposure_ev, uint8_t *rgb)
{
	double k = pow(2.0, exposure_ev) / 16.0;
	for (size_t i = 0; i < n; i++)
		for (int c = 0; c < 3; c++)
			rgb[i * 3 + c] = (uint8_t)lrint(255.0 * display(px[i * stride + c], k));
}

void cs_tonemap_srgb16(const float *px, size_t stride, size_t n,
		       double exposure_ev, uint16_t *rgb)
{
	double k = pow(2.0, exposure_ev) / 16.0;
	for (size_t i = 0; i < n; i++)
		for (int c = 0; c < 3; c++)
			rgb[i * 3 + c] = (uint16_t)lrint(65535.0 * display(px[i * stride + c], k));
}
