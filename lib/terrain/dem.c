#include "terrain/dem.h"

#include "core/err.h"
#include "core/vec.h"

#include <math.h>
#include <stdlib.h>

/* Nearest valid sample by the exact Euclidean distance transform of
 * Felzenszwalb & Huttenlocher ("Distance Transforms of Sampled
 * Functions", Theory of Computing 8, 2012), keeping the argmin: a column
 * pass finds each sample's nearest valid row in its column, then a row pass
 * takes the lower envelope of the parabolas (x - q)^2 + dy(q)^2. */
int cs_dem_fill_nearest(float *h, int width, int height)
{
	size_t n = (size_t)width * height;
	int *row = malloc(n * sizeof *row);       /* nearest valid row, or -1 */
	int *v = malloc((size_t)width * sizeof *v);
	double *z = malloc(((size_t)width + 1) * sizeof *z);
	int *src = malloc((size_t)width * sizeof *src); /* chosen column per x */
	int rc = CS_OK;
	if (row == NULL || v == NULL || z == NULL || src == NULL) {
		rc = cs_error(CS_ENOMEM, "out of memory");
		goto done;
	}
	for (int x = 0; x < width; x++) {
		int last = -1;
		for (int y = 0; y < height; y++) {
			if (!isnan(h[(size_t)y * width + x]))
				last = y;
			row[(size_t)y * width + x] = last;
		}
		last = -1;
		for (int y = height - 1; y >= 0; y--) {
			if (!isnan(h[(size_t)y * width + x]))
				last = y;
			int *r = &row[(size_t)y * width + x];
			/* the upper one wins a tie: strict < */
			if (last >= 0 && (*r < 0 || last - y < y - *r))
				*r = last;
		}
	}
	int any = 0;
	for (int y = 0; y < height; y++) {
		const int *r = row + (size_t)y * width;
		int k = -1;
		for (int q = 0; q < width; q++) {
			if (r[q] < 0)
				continue;
			double fq = (double)(r[q] - y) * (r[q] - y) + (double)q * q;
			double s = -INFINITY;
			while (k >= 0) {
				int p = v[k];
				double fp = (double)(r[p] - y) * (r[p] - y) + (double)p * p;
				s = (fq - fp) / (2.0 * (q - p));
				if (s > z[k])
					break;
				k--;
			}
			k++;
			v[k] = q;
			z[k] = k == 0 ? -INFINITY : s;
			z[k + 1] = INFINITY;
		}
		if (k < 0)
			continue; /* no valid sample in any column: never at the end */
		any = 1;
		for (int x = 0, j = 0; x < width; x++) {
			while (z[j + 1] < x)
				j++;
			src[x] = v[j];
		}
		for (int x = 0; x < width; x++) {
			float *d = &h[(size_t)y * width + x];
			if (isnan(*d))
				*d = h[(size_t)r[src[x]] * width + src[x]];
		}
	}
	if (!any)
		rc = cs_error(CS_EDATA, "no valid height to fill the voids from");
done:
	free(row);
	free(v);
	free(z);
	free(src);
	return rc;
}

void cs_dem_hillshade(const float *h, int width, int height, double dx,
		      double dy, const struct cs_hillshade *s,
		      unsigned char *out)
{
	double az = s->azimuth_deg * CS_PI / 180.0;
	double alt = s->altitude_deg * CS_PI / 180.0;
	double z = s->z_factor;
	/* gdaldem_lib.cpp, GDALHillshadeAlg: x and y are the Horn gradients
	 * over 8 * ewres and 8 * nsres, nsres = -dy for a north-up grid */
	double inv_ew = 1.0 / (8.0 * dx * s->scale);
	double inv_ns = 1.0 / (8.0 * -dy * s->scale);
	double sin_alt = sin(alt);
	double cos_az_cos_alt = cos(az) * cos(alt), sin_az_cos_alt = sin(az) * cos(alt);
	for (int y = 0; y < height; y++) {
		int ya = y > 0 ? y - 1 : 0, yb = y < height - 1 ? y + 1 : y;
		const float *r0 = h + (size_t)ya * width, *r1 = h + (size_t)y * width;
		const float *r2 = h + (size_t)yb * width;
		for (int x = 0; x < width; x++) {
			int xa = x > 0 ? x - 1 : 0, xb = x < width - 1 ? x + 1 : x;
			double a = r0[xa], b = r0[x], c = r0[xb];
			double d = r1[xa], e = r1[x], f = r1[xb];
			double g = r2[xa], hh = r2[x], i = r2[xb];
			if (isnan(a + b + c + d + e + f + g + hh + i)) {
				out[(size_t)y * width + x] = 0;
				continue;
			}
			double gx = ((a + 2 * d + g) - (c + 2 * f + i)) * inv_ew * z;
			double gy = ((g + 2 * hh + i) - (a + 2 * b + c)) * inv_ns * z;
			double cang = (sin_alt - (gy * cos_az_cos_alt - gx * sin_az_cos_alt)) /
				      sqrt(1.0 + gx * gx + gy * gy);
			double v = cang <= 0.0 ? 1.0 : 1.0 + 254.0 * cang;
			out[(size_t)y * width + x] = (unsigned char)lrint(v);
		}
	}
}
