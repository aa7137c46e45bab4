/* alphashift - how two renders' cloud alpha relate, for the tool tests.
 *
 *   alphashift A.exr B.exr [R]
 *
 * Reads the A channel (1 - cloud transmittance) of two EXRs of one size
 * and prints two lines:
 *
 *   corr C            the Pearson correlation of the two alphas, pixel by
 *                     pixel
 *   shift DX DY C     the shift (pixels, x right, y down) that carries A
 *                     onto B, B(x + DX, y + DY) ~ A(x, y): the integer
 *                     shift within +-R (default 32) whose overlap
 *                     correlates best, refined to a fraction of a pixel by
 *                     a parabola through it and its neighbours; C the
 *                     correlation at the integer shift
 *
 * Exit 1 when a file cannot be read, the sizes differ or an alpha is
 * constant (no correlation). */
#include "core/err.h"
#include "core/fileio.h"
#include "io/exr.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static float *alpha(const char *path, int *w, int *h)
{
	unsigned char *data;
	size_t len;
	float *px = NULL;
	static const char *const ch[1] = {"A"};
	if (cs_read_all(path, (size_t)1 << 30, &data, &len) != CS_OK) {
		fprintf(stderr, "alphashift: %s\n", cs_errmsg());
		return NULL;
	}
	if (cs_exr_read_channels(data, len, path, ch, 1, w, h, &px) != CS_OK)
		fprintf(stderr, "alphashift: %s\n", cs_errmsg());
	free(data);
	return px;
}

/* Correlation of A(x, y) with B(x + dx, y + dy) over their overlap; NaN
 * when either is constant there. */
static double corr(const float *a, const float *b, int w, int h, int dx, int dy)
{
	double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
	long n = 0;
	for (int y = 0; y < h; y++) {
		int yb = y + dy;
		if (yb < 0 || yb >= h)
			continue;
		for (int x = 0; x < w; x++) {
			int xb = x + dx;
			if (xb < 0 || xb >= w)
				continue;
			double p = a[(long)y * w + x], q = b[(long)yb * w + xb];
			sa += p, sb += q, saa += p * p, sbb += q * q, sab += p * q;
			n++;
		}
	}
	if (n < 2)
		return NAN;
	double va = saa - sa * sa / n, vb = sbb - sb * sb / n;
	if (!(va > 0) || !(vb > 0))
		return NAN;
	return (sab - sa * sb / n) / sqrt(va * vb);
}

/* The vertex of the parabola through (-1, l), (0, c), (1, r). */
static double vertex(double l, double c, double r)
{
	double d = l - 2 * c + r;
	if (!isfinite(l) || !isfinite(r) || !(d < 0))
		return 0;
	double v = 0.5 * (l - r) / d;
	return v < -0.5 ? -0.5 : v > 0.5 ? 0.5 : v;
}

int main(int argc, char **argv)
{
	if (argc != 3 && argc != 4) {
		fprintf(stderr, "usage: alphashift A.exr B.exr [R]\n");
		return 2;
	}
	int range = argc == 4 ? atoi(argv[3]) : 32, wa, ha, wb, hb;
	float *a = alpha(argv[1], &wa, &ha), *b = alpha(argv[2], &wb, &hb);
	int rc = 1;
	if (a == NULL || b == NULL)
		goto out;
	if (wa != wb || ha != hb) {
		fprintf(stderr, "alphashift: %dx%d and %dx%d differ\n", wa, ha, wb, hb);
		goto out;
	}
	double c0 = corr(a, b, wa, ha, 0, 0), best = -2;
	int bx = 0, by = 0;
	for (int dy = -range; dy <= range; dy++)
		for (int dx = -range; dx <= range; dx++) {
			double c = corr(a, b, wa, ha, dx, dy);
			if (c > best)
				best = c, bx = dx, by = dy;
		}
	if (isnan(c0) || best < -1) {
		fprintf(stderr, "alphashift: an alpha is constant\n");
		goto out;
	}
	double fx = vertex(corr(a, b, wa, ha, bx - 1, by), best,
			   corr(a, b, wa, ha, bx + 1, by));
	double fy = vertex(corr(a, b, wa, ha, bx, by - 1), best,
			   corr(a, b, wa, ha, bx, by + 1));
	printf("corr %.4f\nshift %.2f %.2f %.4f\n", c0, bx + fx, by + fy, best);
	rc = 0;
out:
	free(a);
	free(b);
	return rc;
}
