/* dem.h - operations on a north-up grid of heights (row 0 north, float
 * metres, NaN = void): void filling and hillshading. */
#ifndef CS_DEM_H
#define CS_DEM_H

/* Fills every NaN with the height of the nearest valid sample (exact
 * Euclidean distance on the grid; ties broken deterministically).  Returns CS_EDATA if no sample is valid. */
int cs_dem_fill_nearest(float *h, int width, int height);

struct cs_hillshade {
	double azimuth_deg;   /* sun direction, clockwise from north (315) */
	double altitude_deg;  /* sun above the horizon (45) */
	double z_factor;      /* vertical exaggeration (1) */
	double scale;         /* horizontal units per vertical unit (1) */
};

/* Hillshade as gdaldem computes it (Horn 1981 gradients, Lambert light):
 * per sample 1 + 254 cos(incidence) rounded, 1 in self-shadow, 0 where the
 * 3x3 window holds a void.  Edges replicate the border samples (gdaldem
 * leaves them 0 without -compute_edges).  dx, dy: pixel size (> 0). */
void cs_dem_hillshade(const float *h, int width, int height, double dx,
		      double dy, const struct cs_hillshade *s,
		      unsigned char *out);

#endif
