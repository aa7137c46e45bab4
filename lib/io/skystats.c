#include "io/skystats.h"

#include "core/color.h"
#include "core/err.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

static double lut[256];
static pthread_once_t lut_once = PTHREAD_ONCE_INIT;

static void fill_lut(void)
{
	for (int i = 0; i < 256; i++)
		lut[i] = cs_srgb8_to_linear(i);
}

double cs_srgb8_luminance(const unsigned char *rgb)
{
	pthread_once(&lut_once, fill_lut);
	return cs_luminance(lut[rgb[0]], lut[rgb[1]], lut[rgb[2]]);
}

static int new_mask(struct cs_picture *p)
{
	free(p->sky);
	p->sky = calloc((size_t)p->width * p->height, 1);
	return p->sky ? CS_OK : cs_error(CS_ENOMEM, "out of memory");
}

int cs_sky_mask_all(struct cs_picture *p)
{
	CS_TRY(new_mask(p));
	memset(p->sky, 1, (size_t)p->width * p->height);
	return CS_OK;
}

int cs_sky_mask_depth(struct cs_picture *p, double sky_depth_m)
{
	if (p->alpha == NULL || p->depth == NULL)
		return cs_error(CS_EINVAL, "no A and Z channels for a sky mask");
	CS_TRY(new_mask(p));
	size_t n = (size_t)p->width * p->height;
	for (size_t i = 0; i < n; i++)
		p->sky[i] = p->alpha[i] > 0.0f || p->depth[i] >= 0.5 * sky_depth_m;
	return CS_OK;
}

int cs_sky_mask_horizon(struct cs_picture *p, int row)
{
	CS_TRY(new_mask(p));
	row = row < 0 ? 0 : row > p->height ? p->height : row;
	memset(p->sky, 1, (size_t)row * p->width);
	return CS_OK;
}

int cs_sky_mask_image(struct cs_picture *p, const struct cs_picture *mask, const char *mask_name)
{
	if (mask->width != p->width || mask->height != p->height)
		return cs_error(CS_EDATA, "%s: the mask is %dx%d, its picture %dx%d", mask_name,
				mask->width, mask->height, p->width, p->height);
	CS_TRY(new_mask(p));
	size_t n = (size_t)p->width * p->height;
	for (size_t i = 0; i < n; i++)
		p->sky[i] = cs_srgb8_luminance(mask->srgb + i * 3) >= 0.5;
	return CS_OK;
}

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

static int cmp_int(const void *a, const void *b)
{
	int x = *(const int *)a, y = *(const int *)b;
	return (x > y) - (x < y);
}

/* The median of v[0..n) (sorts v): the mean of the two middle values. */
static double median(double *v, size_t n)
{
	if (n == 0)
		return 0.0;
	qsort(v, n, sizeof *v, cmp_double);
	return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int cs_sky_mask_auto(struct cs_picture *p)
{
	int w = p->width, h = p->height;
	size_t n = (size_t)w * h;
	double *y = malloc(n * sizeof *y), *top = malloc(n * sizeof *top);
	int *hz = malloc((size_t)w * sizeof *hz), *win = malloc((size_t)w * sizeof *win);
	int rc = y && top && hz && win ? new_mask(p) : cs_error(CS_ENOMEM, "out of memory");
	if (rc != CS_OK)
		goto out;
	for (size_t i = 0; i < n; i++)
		y[i] = cs_srgb8_luminance(p->srgb + i * 3);
	pthread_once(&lut_once, fill_lut);
	int rows = h / 10 > 0 ? h / 10 : 1;
	memcpy(top, y, (size_t)rows * w * sizeof *top);
	double dark = CS_SKY_AUTO_DARK * median(top, (size_t)rows * w);
	int run = h / 50 > 2 ? h / 50 : 2;
	for (int i = 0; i < w; i++) {
		int j, k = 0;
		for (j = 0; j < h; j++) {
			size_t q = (size_t)j * w + i;
			const unsigned char *c = p->srgb + q * 3;
			int ground = y[q] < dark || lut[c[2]] < CS_SKY_AUTO_BLUE * lut[c[1]];
			k = ground ? k + 1 : 0;
			if (k == run)
				break;
		}
		hz[i] = j < h ? j - run + 1 : h;
	}
	int half = w / 64; /* a window of about width/32 columns */
	for (int i = 0; i < w; i++) {
		int lo = i - half < 0 ? 0 : i - half, hi = i + half >= w ? w - 1 : i + half, m = 0;
		for (int k = lo; k <= hi; k++)
			win[m++] = hz[k];
		qsort(win, (size_t)m, sizeof *win, cmp_int);
		for (int j = 0; j < win[m / 2]; j++)
			p->sky[(size_t)j * w + i] = 1;
	}
out:
	free(y);
	free(top);
	free(hz);
	free(win);
	return rc;
}

int cs_sky_stats(const struct cs_picture *p, double rb_threshold, unsigned char *cls,
		 struct cs_sky_stats *s)
{
	memset(s, 0, sizeof *s);
	size_t n = (size_t)p->width * p->height;
	s->pixels = (long)n;
	s->mean_lum_kcd_m2 = -1.0;
	double *ys = malloc((n ? n : 1) * sizeof *ys);
	if (ys == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	double sum_y = 0.0, sum_rgb[3] = {0}, sum_kcd = 0.0;
	size_t m = 0;
	for (size_t i = 0; i < n; i++) {
		if (p->sky && !p->sky[i])
			continue;
		const unsigned char *c = p->srgb + i * 3;
		ys[m] = cs_srgb8_luminance(c);
		sum_y += ys[m++];
		for (int k = 0; k < 3; k++) {
			sum_rgb[k] += c[k];
			s->hist[k][c[k]]++;
		}
		const float *l = p->lin + i * 3;
		sum_kcd += cs_luminance(l[0], l[1], l[2]);
	}
	s->sky_pixels = (long)m;
	if (m) {
		s->mean_lum = sum_y / (double)m;
		s->median_lum = median(ys, m);
		if (p->hdr)
			s->mean_lum_kcd_m2 = sum_kcd / (double)m;
		for (int k = 0; k < 3; k++) {
			s->mean_rgb[k] = sum_rgb[k] / (double)m;
			long cum = 0;
			int lvl = 0;
			while ((cum += s->hist[k][lvl]) * 2 < (long)m)
				lvl++;
			s->median_rgb[k] = lvl;
		}
	}
	free(ys);
	cs_sky_classify_map(p->lin, 3, n, p->sky, rb_threshold, cls, &s->cls);
	return CS_OK;
}

static double total(const long *a, int n)
{
	double t = 0.0;
	for (int k = 0; k < n; k++)
		t += (double)a[k];
	return t;
}

double cs_hist_emd(const long *a, const long *b, int n)
{
	double ta = total(a, n), tb = total(b, n);
	if (ta <= 0.0 || tb <= 0.0)
		return NAN;
	double ca = 0.0, cb = 0.0, d = 0.0;
	for (int k = 0; k + 1 < n; k++) {
		ca += a[k] / ta;
		cb += b[k] / tb;
		d += fabs(ca - cb);
	}
	return d;
}

double cs_hist_chi2(const long *a, const long *b, int n)
{
	double ta = total(a, n), tb = total(b, n);
	if (ta <= 0.0 || tb <= 0.0)
		return NAN;
	double d = 0.0;
	for (int k = 0; k < n; k++) {
		double p = a[k] / ta, q = b[k] / tb;
		if (p + q > 0.0)
			d += (p - q) * (p - q) / (p + q);
	}
	return 0.5 * d;
}

int cs_sky_diff(const struct cs_picture *a, const struct cs_picture *b,
		const struct cs_sky_stats *sa, const struct cs_sky_stats *sb,
		const unsigned char *ca, const unsigned char *cb, struct cs_sky_diff *d)
{
	memset(d, 0, sizeof *d);
	if (a->width != b->width || a->height != b->height)
		return cs_error(CS_EINVAL, "pictures of different sizes (%dx%d, %dx%d)", a->width,
				a->height, b->width, b->height);
	d->d_cloud_fraction = sa->cls.cloud_fraction - sb->cls.cloud_fraction;
	d->d_mean_lum = sa->mean_lum - sb->mean_lum;
	d->lum_ratio = sb->mean_lum > 0.0 ? sa->mean_lum / sb->mean_lum : NAN;
	for (int k = 0; k < 3; k++) {
		d->emd[k] = cs_hist_emd(sa->hist[k], sb->hist[k], CS_SKY_BINS);
		d->chi2[k] = cs_hist_chi2(sa->hist[k], sb->hist[k], CS_SKY_BINS);
		d->emd_mean += d->emd[k] / 3.0;
		d->chi2_mean += d->chi2[k] / 3.0;
	}
	size_t n = (size_t)a->width * a->height;
	double sum[3] = {0}, sum_abs = 0.0;
	long both = 0, classified = 0, differ = 0;
	for (size_t i = 0; i < n; i++) {
		if ((a->sky && !a->sky[i]) || (b->sky && !b->sky[i]))
			continue;
		both++;
		for (int k = 0; k < 3; k++) {
			int e = (int)a->srgb[i * 3 + k] - (int)b->srgb[i * 3 + k];
			sum[k] += e;
			sum_abs += abs(e);
		}
		if (ca && cb && ca[i] != CS_SKY_NONE && cb[i] != CS_SKY_NONE) {
			classified++;
			differ += ca[i] != cb[i];
		}
	}
	d->common_pixels = both;
	if (both) {
		for (int k = 0; k < 3; k++)
			d->mean_d_level[k] = sum[k] / (double)both;
		d->mean_abs_d_level = sum_abs / (3.0 * (double)both);
	}
	d->cloud_disagree = classified ? (double)differ / (double)classified : 0.0;
	return CS_OK;
}
