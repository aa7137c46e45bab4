#include "io/picture.h"

#include "core/err.h"
#include "core/fileio.h"
#include "io/exr.h"
#include "io/image.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal.h>

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* An EXR larger than this is not a frame (cloudrender's 16384 x 16384 limit
 * with five channels of 4 bytes would be 5 GiB). */
#define MAX_FILE_BYTES ((size_t)2 << 30)
#define MAX_PIXELS 1e8

double cs_srgb8_to_linear(int level)
{
	double v = level / 255.0;
	return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
}

double cs_aces_inverse(double y)
{
	y = y < 0.0 ? 0.0 : y > 1.0 ? 1.0 : y;
	double a = 2.43 * y - 2.51, b = 0.59 * y - 0.03, c = 0.14 * y;
	if (c == 0.0)
		return 0.0;
	/* a < 0 <= c: the roots have opposite signs; this one is positive */
	return (-b - sqrt(b * b - 4.0 * a * c)) / (2.0 * a);
}

void cs_picture_undo_display(struct cs_picture *p, double exposure_ev)
{
	if (p->hdr)
		return;
	double lut[256], k = 16.0 / pow(2.0, exposure_ev);
	for (int i = 0; i < 256; i++)
		lut[i] = k * cs_aces_inverse(cs_srgb8_to_linear(i));
	size_t n = (size_t)p->width * p->height * 3;
	for (size_t i = 0; i < n; i++)
		p->lin[i] = (float)lut[p->srgb[i]];
	p->hdr = 1;
}

void cs_picture_free(struct cs_picture *p)
{
	free(p->srgb);
	free(p->lin);
	free(p->alpha);
	free(p->depth);
	free(p->sky);
	p->srgb = p->sky = NULL;
	p->lin = p->alpha = p->depth = NULL;
}

int cs_picture_alloc(struct cs_picture *p, int width, int height, int with_ad)
{
	memset(p, 0, sizeof *p);
	if (width < 1 || height < 1 || (double)width * height > MAX_PIXELS)
		return cs_error(CS_EINVAL, "a %dx%d picture is too large", width, height);
	size_t n = (size_t)width * height;
	p->width = width;
	p->height = height;
	p->srgb = calloc(n, 3);
	p->lin = calloc(n * 3, sizeof *p->lin);
	if (with_ad) {
		p->alpha = calloc(n, sizeof *p->alpha);
		p->depth = calloc(n, sizeof *p->depth);
	}
	if (!p->srgb || !p->lin || (with_ad && (!p->alpha || !p->depth))) {
		cs_picture_free(p);
		return cs_error(CS_ENOMEM, "out of memory for a %dx%d picture", width, height);
	}
	return CS_OK;
}

/* The linear values of the display bytes. */
static void decode_srgb(struct cs_picture *p)
{
	double lut[256];
	for (int i = 0; i < 256; i++)
		lut[i] = cs_srgb8_to_linear(i);
	size_t n = (size_t)p->width * p->height * 3;
	for (size_t i = 0; i < n; i++)
		p->lin[i] = (float)lut[p->srgb[i]];
}

static int read_png(const char *path, struct cs_picture *p)
{
	uint8_t *rgb;
	int w, h;
	CS_TRY(cs_png_read_rgb8(path, &rgb, &w, &h));
	int rc = cs_picture_alloc(p, w, h, 0);
	if (rc != CS_OK) {
		free(rgb);
		return rc;
	}
	free(p->srgb);
	p->srgb = rgb;
	decode_srgb(p);
	snprintf(p->format, sizeof p->format, "PNG");
	return CS_OK;
}

static int read_exr(const char *path, const unsigned char *data, size_t len,
		    double exposure_ev, struct cs_picture *p)
{
	static const char *const rgbaz[5] = {"R", "G", "B", "A", "Z"};
	float *px = NULL;
	int w, h, nch = 5;
	if (cs_exr_read_channels(data, len, path, rgbaz, 5, &w, &h, &px) != CS_OK) {
		/* not one of cloudrender's: colour alone (a named missing R, G or
		 * B is the message then) */
		nch = 3;
		CS_TRY(cs_exr_read_channels(data, len, path, rgbaz, 3, &w, &h, &px));
	}
	int rc = cs_picture_alloc(p, w, h, nch == 5);
	if (rc != CS_OK) {
		free(px);
		return rc;
	}
	size_t n = (size_t)w * h;
	for (size_t i = 0; i < n; i++) {
		for (int c = 0; c < 3; c++) {
			float v = px[i * nch + c];
			p->lin[i * 3 + c] = isfinite(v) && v > 0.0f ? v : 0.0f;
		}
		if (nch == 5) {
			p->alpha[i] = px[i * 5 + 3];
			p->depth[i] = px[i * 5 + 4];
		}
	}
	free(px);
	cs_tonemap_srgb8(p->lin, 3, n, exposure_ev, p->srgb);
	p->hdr = 1;
	snprintf(p->format, sizeof p->format, "OpenEXR");
	return CS_OK;
}

/* GDAL's messages, kept for the error (never printed). */
struct gdal_msg {
	char text[256];
};

static void on_gdal_error(CPLErr cls, CPLErrorNum no, const char *msg)
{
	(void)no;
	struct gdal_msg *g = CPLGetErrorHandlerUserData();
	if (cls >= CE_Failure && g->text[0] == '\0')
		snprintf(g->text, sizeof g->text, "%s", msg);
}

static pthread_once_t gdal_once = PTHREAD_ONCE_INIT;

static void register_drivers(void)
{
	GDALAllRegister();
}

/* One band as 8-bit levels (16-bit samples scaled by 255/65535). */
static int read_band(GDALRasterBandH b, int w, int h, uint8_t *out, size_t stride)
{
	size_t n = (size_t)w * h;
	uint16_t *buf = malloc(n * sizeof *buf);
	if (buf == NULL)
		return -1;
	GDALDataType t = GDALGetRasterDataType(b);
	int sixteen = t == GDT_UInt16 || t == GDT_Int16;
	if (GDALRasterIO(b, GF_Read, 0, 0, w, h, buf, w, h, GDT_UInt16, 0, 0) != CE_None) {
		free(buf);
		return -1;
	}
	for (size_t i = 0; i < n; i++)
		out[i * stride] = sixteen ? (uint8_t)((buf[i] * 255u + 32767u) / 65535u)
				: (uint8_t)(buf[i] > 255 ? 255 : buf[i]);
	free(buf);
	return 0;
}

static int read_gdal_open(const char *path, GDALDatasetH ds, struct gdal_msg *g,
			  struct cs_picture *p)
{
	int w = GDALGetRasterXSize(ds), h = GDALGetRasterYSize(ds);
	int nb = GDALGetRasterCount(ds);
	if (nb < 1)
		return cs_error(CS_EDATA, "%s: no raster band", path);
	if ((double)w * h > MAX_PIXELS)
		return cs_error(CS_EDATA, "%s: a %dx%d image is too large", path, w, h);
	GDALRasterBandH b1 = GDALGetRasterBand(ds, 1);
	GDALDataType t = GDALGetRasterDataType(b1);
	if (t != GDT_Byte && t != GDT_UInt16 && t != GDT_Int16)
		return cs_error(CS_EDATA, "%s: %s samples: only 8- and 16-bit pictures are compared",
				path, GDALGetDataTypeName(t));
	CS_TRY(cs_picture_alloc(p, w, h, 0));
	snprintf(p->format, sizeof p->format, "%s", GDALGetDriverShortName(GDALGetDatasetDriver(ds)));
	size_t n = (size_t)w * h;
	GDALColorTableH ct = GDALGetRasterColorTable(b1);
	int fail = 0;
	if (nb >= 3 && !ct) {
		for (int c = 0; c < 3 && !fail; c++)
			fail = read_band(GDALGetRasterBand(ds, c + 1), w, h, p->srgb + c, 3);
	} else {
		fail = read_band(b1, w, h, p->srgb, 3);
		for (size_t i = 0; i < n && !fail; i++) {
			uint8_t v = p->srgb[i * 3];
			if (ct) {
				const GDALColorEntry *e = GDALGetColorEntry(ct, v);
				p->srgb[i * 3] = e ? (uint8_t)e->c1 : 0;
				p->srgb[i * 3 + 1] = e ? (uint8_t)e->c2 : 0;
				p->srgb[i * 3 + 2] = e ? (uint8_t)e->c3 : 0;
			} else {
				p->srgb[i * 3 + 1] = p->srgb[i * 3 + 2] = v;
			}
		}
	}
	if (fail)
		return cs_error(CS_EDATA, "%s: cannot read its pixels: %s", path,
				g->text[0] ? g->text : "a read error");
	decode_srgb(p);
	return CS_OK;
}

static int read_gdal(const char *path, struct cs_picture *p)
{
	struct gdal_msg g = {{0}};
	pthread_once(&gdal_once, register_drivers);
	CPLPushErrorHandlerEx(on_gdal_error, &g);
	char *pam = CPLStrdup(CPLGetThreadLocalConfigOption("GDAL_PAM_ENABLED", ""));
	CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", "NO");
	GDALDatasetH ds = GDALOpenEx(path, GDAL_OF_RASTER | GDAL_OF_READONLY, NULL, NULL, NULL);
	int rc;
	if (ds == NULL)
		rc = cs_error(CS_EDATA, "%s: not a picture that PNG, OpenEXR or GDAL can read%s%s", path,
			      g.text[0] ? ": " : "", g.text);
	else
		rc = read_gdal_open(path, ds, &g, p);
	if (ds)
		GDALClose(ds);
	CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", pam[0] ? pam : NULL);
	CPLFree(pam);
	CPLPopErrorHandler();
	return rc;
}

int cs_picture_read(const char *path, double exposure_ev, struct cs_picture *p)
{
	memset(p, 0, sizeof *p);
	unsigned char magic[8] = {0};
	FILE *f = fopen(path, "rb");
	if (f == NULL)
		return cs_error(CS_EIO, "%s: cannot open: %s", path, strerror(errno));
	size_t got = fread(magic, 1, sizeof magic, f);
	int err = ferror(f) ? errno : 0;
	fclose(f);
	if (err)
		return cs_error(CS_EIO, "%s: cannot read: %s", path, strerror(err));
	if (got == 0)
		return cs_error(CS_EDATA, "%s: empty file", path);
	if (got == 8 && memcmp(magic, "\x89PNG\r\n\x1a\n", 8) == 0)
		return read_png(path, p);
	if (got >= 4 && memcmp(magic, "v/1\x01", 4) == 0) {
		unsigned char *data;
		size_t len;
		CS_TRY(cs_read_all(path, MAX_FILE_BYTES, &data, &len));
		int rc = read_exr(path, data, len, exposure_ev, p);
		free(data);
		return rc;
	}
	return read_gdal(path, p);
}

int cs_picture_crop(struct cs_picture *p, int x, int y, int w, int h)
{
	if (x < 0 || y < 0 || w < 1 || h < 1 || x + w > p->width || y + h > p->height)
		return cs_error(CS_EINVAL, "the window %dx%d at %d,%d is not inside the %dx%d picture",
				w, h, x, y, p->width, p->height);
	struct cs_picture q;
	CS_TRY(cs_picture_alloc(&q, w, h, 0));
	if (p->sky && (q.sky = malloc((size_t)w * h)) == NULL) {
		cs_picture_free(&q);
		return cs_error(CS_ENOMEM, "out of memory");
	}
	for (int j = 0; j < h; j++) {
		size_t s = (size_t)(y + j) * p->width + x, d = (size_t)j * w;
		memcpy(q.srgb + d * 3, p->srgb + s * 3, (size_t)w * 3);
		memcpy(q.lin + d * 3, p->lin + s * 3, (size_t)w * 3 * sizeof *q.lin);
		if (p->sky)
			memcpy(q.sky + d, p->sky + s, (size_t)w);
	}
	q.hdr = p->hdr;
	memcpy(q.format, p->format, sizeof q.format);
	cs_picture_free(p);
	*p = q;
	return CS_OK;
}

/* The source pixels a target pixel covers along one axis: target i of m
 * covers [a, b) = [i n/m, (i+1) n/m) of n, pixels first..last. */
struct span {
	double a, b;
	int first, last;
};

static void cover(int i, int m, int n, struct span *s)
{
	s->a = (double)i * n / m;
	s->b = (double)(i + 1) * n / m;
	s->first = (int)floor(s->a);
	s->last = (int)ceil(s->b) - 1;
	if (s->last >= n)
		s->last = n - 1;
}

/* The length of source pixel k inside the span. */
static double overlap(const struct span *s, int k)
{
	double lo = fmax(s->a, k), hi = fmin(s->b, k + 1.0);
	return hi > lo ? hi - lo : 0.0;
}

int cs_picture_resample(struct cs_picture *p, int width, int height)
{
	if (width == p->width && height == p->height)
		return CS_OK;
	struct cs_picture q;
	CS_TRY(cs_picture_alloc(&q, width, height, 0));
	int rc = p->sky ? cs_mask_resample(p->sky, p->width, p->height, width, height, &q.sky)
			: CS_OK;
	if (rc != CS_OK) {
		cs_picture_free(&q);
		return rc;
	}
	struct span sx, sy;
	for (int j = 0; j < height; j++) {
		cover(j, height, p->height, &sy);
		for (int i = 0; i < width; i++) {
			cover(i, width, p->width, &sx);
			double acc[6] = {0}, wsum = 0.0;
			for (int y = sy.first; y <= sy.last; y++)
				for (int x = sx.first; x <= sx.last; x++) {
					double wt = overlap(&sy, y) * overlap(&sx, x);
					size_t s = (size_t)y * p->width + x;
					for (int c = 0; c < 3; c++) {
						acc[c] += wt * p->srgb[s * 3 + c];
						acc[3 + c] += wt * p->lin[s * 3 + c];
					}
					wsum += wt;
				}
			size_t d = (size_t)j * width + i;
			for (int c = 0; c < 3; c++) {
				q.srgb[d * 3 + c] = (uint8_t)lrint(acc[c] / wsum);
				q.lin[d * 3 + c] = (float)(acc[3 + c] / wsum);
			}
		}
	}
	q.hdr = p->hdr;
	memcpy(q.format, p->format, sizeof q.format);
	cs_picture_free(p);
	*p = q;
	return CS_OK;
}

int cs_mask_resample(const uint8_t *m, int w, int h, int width, int height, uint8_t **out)
{
	*out = malloc((size_t)width * height);
	if (*out == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	struct span sx, sy;
	for (int j = 0; j < height; j++) {
		cover(j, height, h, &sy);
		for (int i = 0; i < width; i++) {
			cover(i, width, w, &sx);
			double on = 0.0, all = 0.0;
			for (int y = sy.first; y <= sy.last; y++)
				for (int x = sx.first; x <= sx.last; x++) {
					double wt = overlap(&sy, y) * overlap(&sx, x);
					on += wt * (m[(size_t)y * w + x] != 0);
					all += wt;
				}
			(*out)[(size_t)j * width + i] = on >= 0.5 * all;
		}
	}
	return CS_OK;
}
