/* imgerr - the error of a rendering against two independent renderings of
 * the reference integrator (linear HDR, from EXR files), for
 * scripts/accuracy-study.
 *
 *   imgerr TEST.exr REF1.exr REF2.exr
 *
 * prints one line: relMSE, the mean absolute relative error of luminance,
 * and the bias of the mean luminance, TEST against the references.
 * With two references A and B of independent noise, E[(f - A)(f - B)] is
 * (f - mu)^2 exactly: the squared error without the references' own
 * variance.  relMSE = sum over pixels and channels of (f - A)(f - B) over
 * the sum of A B (the mean square of the true image).  With IMGERR_KINDS
 * set, the bias per kind of pixel of the test image (sky; ground, with
 * less than 0.01 of cloud in front of it; cloud), or "none" where it has
 * no pixel of that kind; with
 * IMGERR_BLOCKS=CXxCY, the test's mean luminance over the references' in
 * CX x CY blocks, a line per row of blocks; with IMGERR_REFS set, a last
 * line "refs R": the relMSE of either reference alone, for two of the same
 * paths, the sum of (A - B)^2 / 2 over the same sum of A B (the path
 * tracer's own error at the references' paths). */
#include "core/color.h"
#include "core/fileio.h"
#include "io/exr.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static float *load_ch(const char *path, const char *const *ch, int nch, int *w, int *h)
{
	unsigned char *data = NULL;
	size_t len;
	float *px = NULL;
	if (cs_read_all(path, (size_t)1 << 30, &data, &len) != CS_OK ||
	    cs_exr_read_channels(data, len, path, ch, nch, w, h, &px) != CS_OK) {
		fprintf(stderr, "imgerr: %s\n", cs_errmsg());
		exit(1);
	}
	free(data);
	return px;
}

static float *load(const char *path, int *w, int *h)
{
	static const char *const ch[] = {"R", "G", "B"};
	return load_ch(path, ch, 3, w, h);
}

int main(int argc, char **argv)
{
	if (argc != 4) {
		fprintf(stderr, "usage: imgerr TEST.exr REF1.exr REF2.exr\n");
		return 2;
	}
	int w[3], h[3];
	float *f = load(argv[1], &w[0], &h[0]), *a = load(argv[2], &w[1], &h[1]),
	      *b = load(argv[3], &w[2], &h[2]);
	if (w[0] != w[1] || w[0] != w[2] || h[0] != h[1] || h[0] != h[2]) {
		fprintf(stderr, "imgerr: the images differ in size\n");
		return 1;
	}
	static const char *const az[] = {"A", "Z"};
	float *z = load_ch(argv[1], az, 2, &w[1], &h[1]);
	size_t n = (size_t)w[0] * h[0];
	/* the mean luminance per kind of pixel (of the test image): sky, ground,
	 * cloud (alpha >= 0.01) */
	double cf[3] = {0.0, 0.0, 0.0}, cr[3] = {0.0, 0.0, 0.0};
	size_t nk[3] = {0, 0, 0};
	double se = 0.0, ss = 0.0, sab = 0.0, are = 0.0, yf = 0.0, yr = 0.0;
	for (size_t i = 0; i < n; i++) {
		for (int k = 0; k < 3; k++) {
			double x = f[i * 3 + k], p = a[i * 3 + k], q = b[i * 3 + k];
			se += (x - p) * (x - q);
			ss += p * q;
			sab += (p - q) * (p - q);
		}
		double y = cs_luminance(f[i * 3], f[i * 3 + 1], f[i * 3 + 2]);
		double r = 0.5 * (cs_luminance(a[i * 3], a[i * 3 + 1], a[i * 3 + 2]) +
				  cs_luminance(b[i * 3], b[i * 3 + 1], b[i * 3 + 2]));
		are += fabs(y - r) / (r + 1e-3 * (r > 0 ? r : 1.0) + 1e-6);
		yf += y, yr += r;
		int kind = z[i * 2] >= 0.01f ? 2 : z[i * 2 + 1] < 1e9f ? 1 : 0;
		cf[kind] += y, cr[kind] += r, nk[kind]++;
	}
	printf("%.4g %.4g %.4f", se / ss, are / n, yr > 0 ? yf / yr - 1.0 : 0.0);
	if (argc > 4 || getenv("IMGERR_KINDS"))
		for (int k = 0; k < 3; k++) {
			const char *name = k == 0 ? "sky" : k == 1 ? "ground" : "cloud";
			if (nk[k] > 0)
				printf(" %s %.4f", name, cr[k] > 0 ? cf[k] / cr[k] - 1.0 : 0.0);
			else
				printf(" %s none", name);
		}
	printf("\n");
	/* IMGERR_BLOCKS=CXxCY: the test's mean luminance over the
	 * references' in CX x CY blocks, a row of blocks a line, top first */
	const char *bl = getenv("IMGERR_BLOCKS");
	int cx, cy;
	if (bl != NULL && sscanf(bl, "%dx%d", &cx, &cy) == 2 && cx > 0 && cy > 0 && cx <= w[0] &&
	    cy <= h[0]) {
		for (int by = 0; by < cy; by++) {
			for (int bx = 0; bx < cx; bx++) {
				double sf = 0.0, sr = 0.0;
				for (int y = by * h[0] / cy; y < (by + 1) * h[0] / cy; y++)
					for (int x = bx * w[0] / cx; x < (bx + 1) * w[0] / cx; x++) {
						size_t i = (size_t)y * w[0] + x;
						sf += cs_luminance(f[i * 3], f[i * 3 + 1], f[i * 3 + 2]);
						sr += 0.5 * (cs_luminance(a[i * 3], a[i * 3 + 1], a[i * 3 + 2]) +
							     cs_luminance(b[i * 3], b[i * 3 + 1], b[i * 3 + 2]));
					}
				printf(bx ? " %5.2f" : "%5.2f", sr > 0.0 ? sf / sr : 0.0);
			}
			printf("\n");
		}
	}
	if (getenv("IMGERR_REFS"))
		printf("refs %.4g\n", 0.5 * sab / ss);
	free(f), free(a), free(b), free(z);
	return 0;
}
