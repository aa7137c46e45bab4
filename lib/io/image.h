/* image.h - 8-bit PNG (libpng's simplified API) and the display transform:
 * exposure, tone curve, sRGB encoding. */
#ifndef CS_IMAGE_H
#define CS_IMAGE_H

#include <stddef.h>
#include <stdint.h>

/* Writes width x height pixels of 1 (grey), 3 (RGB, sRGB) or 4 (RGBA)
 * interleaved 8-bit channels, rows top to bottom, to path ("-" = stdout).
 * Atomic: no partial file on failure. */
int cs_png_write(const char *path, int width, int height, int channels,
		 const uint8_t *pixels);

struct cs_outfile;

/* cs_png_write() into an open output (core/fileio.h), not committed; name
 * labels messages. */
int cs_png_write_to(struct cs_outfile *of, const char *name, int width,
		    int height, int channels, const uint8_t *pixels);

/* A 16-bit PNG of 1 (grey), 3 (RGB) or 4 (RGBA) channels whose samples are
 * sRGB-encoded (an sRGB chunk, as the 8-bit ones), into an open output. */
int cs_png16_write_to(struct cs_outfile *of, const char *name, int width,
		      int height, int channels, const uint16_t *pixels);

/* A text chunk: tEXt (Latin-1 text), or iTXt (UTF-8) when itxt; neither
 * compressed.  key: 1..79 printable Latin-1 bytes (PNG's keywords). */
struct cs_png_text {
	const char *key;
	const char *text;
	int itxt;
};

/* A PNG of 8 or 16 bits a sample (pixels: uint8_t or uint16_t), 1, 3 or 4
 * channels, sRGB-encoded, with ntext text chunks before the pixels, into
 * an open output. */
int cs_png_write_text_to(struct cs_outfile *of, const char *name, int width, int height,
			 int channels, int bits, const void *pixels,
			 const struct cs_png_text *text, int ntext);

/* Reads a PNG as 8-bit sRGB RGB (any PNG: grey, palette and alpha are
 * converted); *rgb is malloc'ed for the caller. */
int cs_png_read_rgb8(const char *path, uint8_t **rgb, int *width, int *height);
/* The same from len bytes in memory; name labels messages.  A header that
 * claims more than CS_PNG_MAX_PIXELS, or more pixels than len bytes can
 * hold at zlib's best ratio, is CS_EDATA before anything is allocated. */
int cs_png_read_rgb8_mem(const void *data, size_t len, const char *name,
			 uint8_t **rgb, int *width, int *height);
#define CS_PNG_MAX_PIXELS 100000000 /* 1e8: 300 MB of RGB */

/* The exposure (stops) that brings the log-average luminance of n pixels
 * (R G B first of each, stride floats apart) to 0.25 on the tone curve's
 * input, as a camera's automatic exposure does (Reinhard et al. 2002's
 * key); zero-radiance pixels count as 1e-9 kcd/m^2.  Clamped to
 * CS_EXPOSURE_MIN_EV..CS_EXPOSURE_MAX_EV (a black frame would ask 32). */
#define CS_EXPOSURE_MIN_EV (-20.0)
#define CS_EXPOSURE_MAX_EV 20.0
double cs_auto_exposure_ev(const float *px, size_t stride, size_t n);

/* The ACES filmic tone curve, Narkowicz 2015's fit
 * x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), clamped to 0..1. */
double cs_tonemap_aces(double x);

/* The sRGB transfer function (IEC 61966-2-1): linear 0..1 to encoded 0..1. */
double cs_srgb_oetf(double v);

/* Linear radiance (kcd/m^2, linear sRGB) to 8-bit sRGB for display: scaled
 * by 2^exposure_ev / 16 kcd/m^2, ACES filmic curve (Narkowicz 2015 fit),
 * sRGB transfer function.  px holds n pixels, stride floats apart, R G B
 * first; rgb receives 3 bytes per pixel. */
void cs_tonemap_srgb8(const float *px, size_t stride, size_t n,
		      double exposure_ev, uint8_t *rgb);

/* cs_tonemap_srgb8() to 16 bits: the same curve, 0..65535. */
void cs_tonemap_srgb16(const float *px, size_t stride, size_t n,
		       double exposure_ev, uint16_t *rgb);

#endif
