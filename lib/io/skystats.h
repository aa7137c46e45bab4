/* skystats.h - what a sky picture holds, and how two differ: the sky mask,
 * the cloud fraction (io/skyclass.h's red/blue ratio), luminance, colour,
 * per-channel histograms and their distances.  Over a cs_picture
 * (io/picture.h) and its sky mask. */
#ifndef CS_SKYSTATS_H
#define CS_SKYSTATS_H

#include "io/picture.h"
#include "io/skyclass.h"

#define CS_SKY_BINS 256 /* histogram bins: one per 8-bit display level */

/* The auto mask's rule (cs_sky_mask_auto): a pixel looks like ground when
 * its display luminance is under CS_SKY_AUTO_DARK of the top rows' median,
 * or its linear blue under CS_SKY_AUTO_BLUE of its green (vegetation, earth:
 * the sky, clear or cloudy, is at least as blue as it is green). */
#define CS_SKY_AUTO_DARK 0.5
#define CS_SKY_AUTO_BLUE 0.8

struct cs_sky_stats {
	long pixels, sky_pixels;
	struct cs_sky_class cls;  /* cloud fraction of the sky */
	/* relative luminance (BT.709 Y of the decoded display sRGB), 0..1 */
	double mean_lum, median_lum;
	double mean_lum_kcd_m2;   /* OpenEXR only: of the linear radiance; else -1 */
	double mean_rgb[3];       /* display sRGB levels, 0..255 */
	double median_rgb[3];     /* the lower median of each channel's levels */
	long hist[3][CS_SKY_BINS];/* display levels of the sky, per channel */
};

/* How a differs from b (a - b, same grid). */
struct cs_sky_diff {
	long common_pixels;       /* sky in both */
	double d_cloud_fraction;  /* a's minus b's */
	double lum_ratio;         /* a's mean luminance over b's (NAN if b's is 0) */
	double d_mean_lum;        /* a's minus b's */
	double emd[3], chi2[3];   /* histogram distances per channel R, G, B */
	double emd_mean, chi2_mean; /* over the three channels */
	/* per pixel, on the common sky: */
	double mean_d_level[3];   /* mean of a - b, display levels */
	double mean_abs_d_level;  /* mean |a - b| over pixels and channels */
	double cloud_disagree;    /* fraction classified differently */
};

/* Sky masks, written to p->sky (allocated here).
 * _all: every pixel.  _depth: from an EXR's A and Z (cloudrender's): a
 * pixel is sky unless it is clear (A <= 0) and its depth is under half
 * sky_depth_m (ground or terrain); CS_EINVAL without A and Z.
 * _horizon: rows 0..row-1 (row counted in p's rows, clamped).
 * _image: the pixels of mask (a picture of p's size, else CS_EDATA) whose display
 * luminance is at least half white.
 * _auto: an estimate for a photograph: see cs_sky_mask_auto. */
int cs_sky_mask_all(struct cs_picture *p);
int cs_sky_mask_depth(struct cs_picture *p, double sky_depth_m);
int cs_sky_mask_horizon(struct cs_picture *p, int row);
int cs_sky_mask_image(struct cs_picture *p, const struct cs_picture *mask, const char *mask_name);

/* The automatic estimate, for daylight pictures whose top rows are sky and
 * whose ground is darker or greener than the sky: the reference is the
 * median display luminance of the top tenth of the rows; each column's sky
 * runs from the top down to the first run of max(2, height/50) rows that
 * look like ground (CS_SKY_AUTO_DARK, CS_SKY_AUTO_BLUE); the column
 * horizons are then the median over width/32 neighbouring columns (a pole,
 * a dark cloud).  It fails on night pictures, sunset skies (less blue than
 * green), grey rock or snow in sunlight, dark storm cloud under a bright
 * top, and a top edge that is not sky (a caption bar): give a mask then. */
int cs_sky_mask_auto(struct cs_picture *p);

/* The statistics of p's sky (p->sky, or every pixel when NULL), classified
 * with the R/B threshold on p->lin; cls, when not NULL, receives each
 * pixel's class (CS_SKY_NONE, _CLEAR, _CLOUD). */
int cs_sky_stats(const struct cs_picture *p, double rb_threshold, unsigned char *cls,
		 struct cs_sky_stats *s);

/* Earth mover's distance between two histograms of n bins, each normalised
 * to sum 1, in bins (the mean shift of a translated histogram):
 * sum over k of |CDF_a(k) - CDF_b(k)|.  NAN when either is empty. */
double cs_hist_emd(const long *a, const long *b, int n);

/* The chi-squared histogram distance 0.5 sum (p - q)^2 / (p + q) of the
 * normalised histograms: 0 for equal, 1 for disjoint ones.  NAN when
 * either is empty. */
double cs_hist_chi2(const long *a, const long *b, int n);

/* Compares a and b (the same size; their statistics sa, sb, their class
 * maps ca, cb from cs_sky_stats). */
int cs_sky_diff(const struct cs_picture *a, const struct cs_picture *b,
		const struct cs_sky_stats *sa, const struct cs_sky_stats *sb,
		const unsigned char *ca, const unsigned char *cb, struct cs_sky_diff *d);

/* The display luminance (BT.709 Y of decoded sRGB, 0..1) of 8-bit levels. */
double cs_srgb8_luminance(const unsigned char *rgb);

#endif
