/* picture.h - any picture as pixels to compare: PNG (libpng), OpenEXR
 * (cloudrender's linear RGBA + Z) or anything else GDAL reads (JPEG webcam
 * frames, TIFF, ...); cropping and resampling onto another grid. */
#ifndef CS_PICTURE_H
#define CS_PICTURE_H

#include <stddef.h>
#include <stdint.h>

struct cs_picture {
	int width, height;
	uint8_t *srgb; /* 3 bytes per pixel, display sRGB, rows top to bottom */
	float *lin;    /* 3 floats per pixel, linear: kcd/m^2 for EXR, else the
			* decoded display values, 0..1 */
	float *alpha;  /* EXR only (A: 1 - cloud transmittance), else NULL */
	float *depth;  /* EXR only (Z, metres), else NULL */
	uint8_t *sky;  /* 1 where the pixel is sky, or NULL (not decided yet) */
	int hdr;       /* 1: read from OpenEXR (lin is absolute radiance) */
	char format[16]; /* "PNG", "OpenEXR" or GDAL's driver name */
};

/* Reads path: PNG and OpenEXR by their magic numbers, anything else through
 * GDAL (1 band: grey; 3 or more: the first three are R, G, B; 8 or 16 bits;
 * palettes expanded).  An EXR needs R, G and B (A and Z are read when
 * present) and is shown through cloudrender's display transform at
 * exposure_ev stops.  Errors name the file (CS_EDATA, CS_EIO, CS_ENOMEM).
 * Free with cs_picture_free(), whatever it returned. */
int cs_picture_read(const char *path, double exposure_ev, struct cs_picture *p);

/* Allocates a width x height picture (srgb and lin; alpha and depth when
 * with_ad), zeroed. */
int cs_picture_alloc(struct cs_picture *p, int width, int height, int with_ad);
void cs_picture_free(struct cs_picture *p);

/* Replaces p by its window x, y, w, h (pixels; it must lie inside), with
 * its sky mask; alpha and depth are dropped (decide the mask first). */
int cs_picture_crop(struct cs_picture *p, int x, int y, int w, int h);

/* Replaces p by p resampled to width x height by area averaging (a box
 * filter over the source pixels each target pixel covers: a picture
 * resampled onto its own size is unchanged), its sky mask as
 * cs_mask_resample() does; alpha and depth are dropped. */
int cs_picture_resample(struct cs_picture *p, int width, int height);

/* Resamples an 8-bit mask (0 or 1) the same way: a target pixel is 1 when
 * at least half of what it covers is; *out is malloc'ed for the caller. */
int cs_mask_resample(const uint8_t *m, int w, int h, int width, int height, uint8_t **out);

/* For a PNG of cloudrender's (not an EXR): replaces lin by the radiance the
 * display transform came from (kcd/m^2), inverting the sRGB encoding, the
 * ACES curve (cs_aces_inverse) and the exposure (x = L 2^ev / 16); p->hdr
 * becomes 1.  Levels 255 (the curve's clipped top) stay at the curve's
 * value for 1.  A no-op for an EXR. */
void cs_picture_undo_display(struct cs_picture *p, double exposure_ev);

/* The x >= 0 with cs_tonemap_aces(x) = y, y in 0..1: the positive root of
 * (2.43 y - 2.51) x^2 + (0.59 y - 0.03) x + 0.14 y = 0. */
double cs_aces_inverse(double y);

/* The sRGB decoding (IEC 61966-2-1 EOTF) of an 8-bit level, 0..1. */
double cs_srgb8_to_linear(int level);

#endif
