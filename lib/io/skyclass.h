/* skyclass.h - cloud or clear, pixel by pixel, as ground-based sky imagers
 * decide it: by the red/blue ratio (Long et al. 2006, "Retrieving cloud
 * characteristics from ground-based daytime color all-sky images", J.
 * Atmos. Oceanic Technol. 23).  Clear sky scatters blue far more than red
 * (Rayleigh) and has a low ratio, about 0.5-0.6 on linear RGB; cloud
 * droplets scatter all colours alike and give 0.8-1. */
#ifndef CS_SKYCLASS_H
#define CS_SKYCLASS_H

#include <stddef.h>

/* The threshold of R/B on linear (not gamma-encoded) RGB at or above which
 * a pixel is cloud: chosen once for cloudrender's linear output, halfway
 * between clear sky (0.5-0.6) and grey cloud (0.9-1).  On sRGB-encoded
 * values (a JPEG's bytes) the same split is a ratio of about
 * 0.75^(1/2.4) = 0.89: decode to linear first (skycompare does). */
#define CS_SKY_RB_THRESHOLD 0.75
/* Imagers analyse the sky above this elevation (a zenith angle of 70 deg,
 * as Long et al. do): near the horizon haze whitens the clear sky and
 * obstructions hide it. */
#define CS_SKY_MIN_ELEVATION_DEG 20.0

struct cs_sky_class {
	long sky_pixels;       /* pixels classified */
	long cloud_pixels;     /* of those, cloud */
	double cloud_fraction; /* cloud / sky, 0 when there is no sky */
};

/* Classifies n pixels of linear RGB (stride floats apart, R, G, B first);
 * a pixel counts only where use is NULL or use[i] is nonzero.  A pixel
 * with B <= 0 (black) is not classified. */
void cs_sky_classify(const float *px, size_t stride, size_t n, const unsigned char *use,
		     double rb_threshold, struct cs_sky_class *out);

/* The classes of cs_sky_classify_map(), one byte per pixel. */
enum { CS_SKY_NONE = 0, CS_SKY_CLEAR = 1, CS_SKY_CLOUD = 2 };

/* cs_sky_classify(), and each pixel's class in cls[i] (n bytes): NONE where
 * it was not classified (not in use, or black), else CLEAR or CLOUD. */
void cs_sky_classify_map(const float *px, size_t stride, size_t n, const unsigned char *use,
			 double rb_threshold, unsigned char *cls, struct cs_sky_class *out);

#endif
