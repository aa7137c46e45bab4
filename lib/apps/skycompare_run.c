#include "apps/skycompare_run.h"

#include "core/err.h"
#include "core/vec.h"
#include "io/image.h"
#include "render/render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

void cs_skycompare_defaults(struct cs_skycompare_opts *o)
{
	memset(o, 0, sizeof *o);
	o->first = o->last = -1;
	o->rb_threshold = CS_SKY_RB_THRESHOLD;
	o->horizon_row = o->render_horizon_row = -1;
	o->split = 0.5;
	o->blend = -1.0;
	o->diff_range = 32.0;
}

/* ---- series patterns ---------------------------------------------------- */

/* Finds the one conversion: *at its '%', *len its length, *width, *zero. */
static int parse_pattern(const char *p, size_t *at, size_t *len, int *width, int *zero)
{
	int found = 0;
	for (size_t i = 0; p[i]; i++) {
		if (p[i] != '%')
			continue;
		if (p[i + 1] == '%') {
			i++;
			continue;
		}
		size_t j = i + 1;
		int z = p[j] == '0', wd = 0;
		j += z;
		if (p[j] >= '1' && p[j] <= '9')
			wd = p[j++] - '0';
		if (p[j] != 'd' || found)
			return -1;
		found = 1;
		*at = i, *len = j + 1 - i, *width = wd, *zero = z;
		i = j;
	}
	return found ? 0 : -1;
}

int cs_series_pattern_check(const char *opt, const char *pattern)
{
	size_t at, len;
	int w, z;
	if (parse_pattern(pattern, &at, &len, &w, &z) != 0)
		return cs_error(CS_EINVAL, "%s: '%s' needs exactly one index conversion such as "
				"%%d or %%05d (%%%% for a percent sign)", opt, pattern);
	return CS_OK;
}

int cs_series_name(const char *pattern, long i, char *buf, size_t size)
{
	size_t at, len, o = 0;
	int w, z;
	if (parse_pattern(pattern, &at, &len, &w, &z) != 0)
		return cs_error(CS_EINVAL, "'%s' is not a series pattern", pattern);
	char num[32];
	int nl = snprintf(num, sizeof num, z ? "%0*ld" : "%*ld", w, i);
	for (size_t k = 0; pattern[k]; k++) {
		const char *piece = pattern + k;
		size_t n = 1;
		if (k == at) {
			piece = num, n = (size_t)nl;
			k += len - 1;
		} else if (pattern[k] == '%') {
			k++; /* %% */
		}
		if (o + n >= size)
			return cs_error(CS_EINVAL, "the name for index %ld of '%s' is too long", i,
					pattern);
		memcpy(buf + o, piece, n);
		o += n;
	}
	buf[o] = '\0';
	return CS_OK;
}

/* ---- one pair ------------------------------------------------------------ */

/* Reads a picture and decides its sky: all; cloudrender's A and Z, less
 * the rows from the horizon option's down; the photo's mask; the horizon
 * option's rows; or the estimate. */
static int load(const struct cs_skycompare_opts *o, const char *path, int photo,
		struct cs_picture *p, char *how, size_t how_size)
{
	CS_TRY(cs_picture_read(path, o->exposure_ev[photo], p));
	if (!photo && o->undo_tonemap)
		cs_picture_undo_display(p, o->exposure_ev[0]);
	int row = photo ? o->horizon_row : o->render_horizon_row;
	int depth = p->alpha && p->depth;
	if (o->sky_all) {
		snprintf(how, how_size, "all");
		return cs_sky_mask_all(p);
	}
	if (row > p->height)
		return cs_error(CS_EINVAL, "--%shorizon %d is below the %dx%d picture %s",
				photo ? "" : "render-", row, p->width, p->height, path);
	if (depth) {
		snprintf(how, how_size, "%s", row >= 0 ? "depth+horizon" : "depth");
		CS_TRY(cs_sky_mask_depth(p, CS_SKY_DEPTH_M));
		if (row >= 0)
			memset(p->sky + (size_t)row * p->width, 0,
			       (size_t)(p->height - row) * p->width);
		return CS_OK;
	}
	if (photo && o->mask_path) {
		struct cs_picture m;
		snprintf(how, how_size, "mask");
		int rc = cs_picture_read(o->mask_path, 0.0, &m);
		if (rc == CS_OK)
			rc = cs_sky_mask_image(p, &m, o->mask_path);
		cs_picture_free(&m);
		return rc;
	}
	if (row >= 0) {
		snprintf(how, how_size, "horizon");
		return cs_sky_mask_horizon(p, row);
	}
	snprintf(how, how_size, "auto");
	return cs_sky_mask_auto(p);
}

/* The photo's window: --crop, then the middle part that --fov names. */
static int frame_photo(const struct cs_skycompare_opts *o, struct cs_picture *ph, int gw, int gh,
		       const char *path)
{
	if (o->have_crop) {
		int rc = cs_picture_crop(ph, o->crop[0], o->crop[1], o->crop[2], o->crop[3]);
		if (rc != CS_OK)
			return cs_error(CS_EINVAL, "--crop: %s: %s", path, cs_errmsg());
	}
	if (o->fov_deg[0] > 0.0 && o->fov_deg[1] > 0.0) {
		double r = o->fov_deg[0], p = o->fov_deg[1], f;
		if (r > p)
			return cs_error(CS_EINVAL, "--fov: the render's %g deg is wider than the "
					"photo's %g deg", r, p);
		/* a panorama's columns are linear in angle; a photograph's in
		 * the tangent of the angle from its axis */
		f = p >= 180.0 ? r / p : tan(r * CS_PI / 360.0) / tan(p * CS_PI / 360.0);
		int w = (int)lrint(ph->width * f);
		w = w < 1 ? 1 : w;
		int h = (int)lrint((double)w * gh / gw);
		h = h < 1 ? 1 : h > ph->height ? ph->height : h;
		CS_TRY(cs_picture_crop(ph, (ph->width - w) / 2, (ph->height - h) / 2, w, h));
	}
	return CS_OK;
}

enum cs_verdict cs_skycompare_verdict(const struct cs_sky_stats *render,
				      const struct cs_sky_stats *photo,
				      const struct cs_sky_diff *d, char *text, size_t size)
{
	double dc = d->d_cloud_fraction, emd = d->emd_mean, adc = fabs(dc);
	enum cs_verdict v;
	if (!(render->sky_pixels > 0 && photo->sky_pixels > 0)) {
		snprintf(text, size, "poor: %s has no sky to compare",
			 render->sky_pixels ? "the photo" : "the render");
		return CS_POOR;
	}
	v = adc <= CS_VERDICT_CLOUD && emd <= CS_VERDICT_EMD ? CS_MATCH
	    : adc <= CS_VERDICT_CLOUD_FAIR && emd <= CS_VERDICT_EMD_FAIR ? CS_FAIR : CS_POOR;
	static const char *const word[3] = {"match", "fair", "poor"};
	char cloud[96], lum[64];
	if (adc <= CS_VERDICT_CLOUD)
		snprintf(cloud, sizeof cloud, "the same cloud cover (%.2f vs %.2f)",
			 render->cls.cloud_fraction, photo->cls.cloud_fraction);
	else
		snprintf(cloud, sizeof cloud, "the render is %s (%.2f vs %.2f)",
			 dc > 0 ? "cloudier" : "clearer", render->cls.cloud_fraction,
			 photo->cls.cloud_fraction);
	double ratio = d->lum_ratio;
	if (!isfinite(ratio))
		snprintf(lum, sizeof lum, "the photo is black");
	else if (fabs(ratio - 1.0) <= CS_VERDICT_LUM)
		snprintf(lum, sizeof lum, "as bright (%+.0f %%)", 100.0 * (ratio - 1.0));
	else
		snprintf(lum, sizeof lum, "%.0f %% %s", fabs(100.0 * (ratio - 1.0)),
			 ratio > 1.0 ? "brighter" : "darker");
	snprintf(text, size, "%s: %s, %s, colours %s (EMD %.1f levels)", word[v], cloud, lum,
		 emd <= CS_VERDICT_EMD ? "alike" : emd <= CS_VERDICT_EMD_FAIR ? "differ" : "far apart",
		 emd);
	return v;
}

/* ---- pictures -------------------------------------------------------------- */

static void put(uint8_t *img, int w, int x, int y, uint8_t r, uint8_t g, uint8_t b)
{
	uint8_t *q = img + ((size_t)y * w + x) * 3;
	q[0] = r, q[1] = g, q[2] = b;
}

/* A picture's pixel, dimmed to a third where it is not sky. */
static void shown(const struct cs_picture *p, size_t i, uint8_t *out)
{
	int dim = p->sky && !p->sky[i];
	for (int c = 0; c < 3; c++)
		out[c] = dim ? (uint8_t)(p->srgb[i * 3 + c] / 3) : p->srgb[i * 3 + c];
}

/* Render | photo above, their cloud maps below (cloud white, clear sky
 * blue, not sky black), 4 grey pixels between. */
static int write_side(const char *path, const struct cs_picture *a, const struct cs_picture *b,
		      const unsigned char *ca, const unsigned char *cb)
{
	int w = a->width, h = a->height, gap = 4, W = 2 * w + gap, H = 2 * h + gap;
	uint8_t *img = malloc((size_t)W * H * 3);
	if (img == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	memset(img, 48, (size_t)W * H * 3);
	static const uint8_t cls_rgb[3][3] = {{0, 0, 0}, {60, 120, 215}, {240, 240, 240}};
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			size_t i = (size_t)y * w + x;
			shown(a, i, img + ((size_t)y * W + x) * 3);
			shown(b, i, img + ((size_t)y * W + x + w + gap) * 3);
			const uint8_t *k = cls_rgb[ca[i]], *l = cls_rgb[cb[i]];
			put(img, W, x, y + h + gap, k[0], k[1], k[2]);
			put(img, W, x + w + gap, y + h + gap, l[0], l[1], l[2]);
		}
	int rc = cs_png_write(path, W, H, 3, img);
	free(img);
	return rc;
}

/* The divider of a split screen at column xs: a white line with dark
 * edges, and a round white handle at mid-height holding two dark arrows
 * pointing left and right, as a slider a viewer could drag. */
static void draw_divider(uint8_t *img, int w, int h, int xs)
{
	double rad = h / 16.0 > 6.0 ? h / 16.0 : 6.0, yc = h / 2.0;
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			double dx = x + 0.5 - xs, dy = y + 0.5 - yc, d = hypot(dx, dy);
			double ax = fabs(dx), ay = fabs(dy);
			/* an arrow: a triangle with its tip at 0.7 rad, base at 0.25 rad */
			int arrow = ax >= 0.25 * rad && ax <= 0.7 * rad &&
				    ay <= 0.4 * (0.7 * rad - ax) / 0.45;
			if (d <= rad)
				put(img, w, x, y, arrow ? 40 : 250, arrow ? 40 : 250, arrow ? 40 : 250);
			else if (d <= rad + 1.5 || (ax > 1.0 && ax <= 2.0))
				put(img, w, x, y, 40, 40, 40);
			else if (ax <= 1.0)
				put(img, w, x, y, 250, 250, 250);
		}
}

/* A split screen (render left of the divider, photo right) with a divider
 * and a round handle, or a blend. */
static int write_overlay(const char *path, const struct cs_picture *a, const struct cs_picture *b,
			 double split, double blend)
{
	int w = a->width, h = a->height;
	uint8_t *img = malloc((size_t)w * h * 3);
	if (img == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	int xs = (int)lrint(split * w);
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			size_t i = (size_t)y * w + x;
			for (int c = 0; c < 3; c++)
				img[i * 3 + c] = blend >= 0.0
					? (uint8_t)lrint((1.0 - blend) * a->srgb[i * 3 + c] +
							 blend * b->srgb[i * 3 + c])
					: (x < xs ? a : b)->srgb[i * 3 + c];
		}
	if (blend < 0.0)
		draw_divider(img, w, h, xs);
	int rc = cs_png_write(path, w, h, 3, img);
	free(img);
	return rc;
}

/* The display luminance in sRGB-encoded levels, 0..255. */
static double level(const struct cs_picture *p, size_t i)
{
	return 255.0 * cs_srgb_oetf(cs_srgb8_luminance(p->srgb + i * 3));
}

/* The diverging colour of t in -1..1: blue (render darker), white, red
 * (render brighter). */
static void diverging(double t, uint8_t *q)
{
	t = t < -1.0 ? -1.0 : t > 1.0 ? 1.0 : t;
	double u = 1.0 - fabs(t);
	q[0] = (uint8_t)lrint(t >= 0 ? 255 : 40 + 215 * u);
	q[1] = (uint8_t)lrint(40 + 215 * u);
	q[2] = (uint8_t)lrint(t <= 0 ? 255 : 40 + 215 * u);
}

/* Render minus photo in display luminance levels, range levels at full
 * colour; outside the common sky the render in dark grey; a colour bar
 * from -range to +range along the bottom. */
static int write_diff(const char *path, const struct cs_picture *a, const struct cs_picture *b,
		      double range)
{
	int w = a->width, h = a->height, bar = h / 24 > 4 ? h / 24 : 4, H = h + bar;
	uint8_t *img = malloc((size_t)w * H * 3);
	if (img == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			size_t i = (size_t)y * w + x;
			uint8_t *q = img + i * 3;
			if ((a->sky && !a->sky[i]) || (b->sky && !b->sky[i])) {
				uint8_t g = (uint8_t)lrint(level(a, i) * 0.3);
				q[0] = q[1] = q[2] = g;
			} else {
				diverging((level(a, i) - level(b, i)) / range, q);
			}
		}
	for (int y = h; y < H; y++)
		for (int x = 0; x < w; x++)
			diverging(w > 1 ? 2.0 * x / (w - 1) - 1.0 : 0.0,
				  img + ((size_t)y * w + x) * 3);
	int rc = cs_png_write(path, w, H, 3, img);
	free(img);
	return rc;
}

/* ---- one comparison -------------------------------------------------------- */

static int pictures(const struct cs_skycompare_opts *o, long index, const struct cs_picture *a,
		    const struct cs_picture *b, const unsigned char *ca, const unsigned char *cb)
{
	const char *paths[3] = {o->side_path, o->overlay_path, o->diff_path};
	for (int k = 0; k < 3; k++) {
		if (paths[k] == NULL)
			continue;
		char name[1024];
		const char *path = paths[k];
		if (index >= 0) {
			CS_TRY(cs_series_name(paths[k], index, name, sizeof name));
			path = name;
		}
		int rc = k == 0 ? write_side(path, a, b, ca, cb)
			 : k == 1 ? write_overlay(path, a, b, o->split, o->blend)
				  : write_diff(path, a, b, o->diff_range);
		if (rc != CS_OK)
			return rc;
	}
	return CS_OK;
}

static int compare(const struct cs_skycompare_opts *o, struct cs_skycompare_pair *pr)
{
	struct cs_picture a, b;
	unsigned char *ca = NULL, *cb = NULL;
	memset(&b, 0, sizeof b);
	int rc = load(o, pr->render, 0, &a, pr->render_sky, sizeof pr->render_sky);
	if (rc == CS_OK)
		rc = load(o, pr->photo, 1, &b, pr->photo_sky, sizeof pr->photo_sky);
	if (rc != CS_OK)
		goto out;
	pr->render_w = a.width, pr->render_h = a.height;
	pr->photo_w = b.width, pr->photo_h = b.height;
	int gw = o->grid_w ? o->grid_w : a.width, gh = o->grid_h ? o->grid_h : a.height;
	if ((rc = frame_photo(o, &b, gw, gh, pr->photo)) != CS_OK)
		goto out;
	double ar = (double)a.width / a.height, ap = (double)b.width / b.height;
	pr->aspect_differs = fabs(ap / ar - 1.0) > 0.02;
	pr->grid_w = gw, pr->grid_h = gh;
	if ((rc = cs_picture_resample(&a, gw, gh)) != CS_OK ||
	    (rc = cs_picture_resample(&b, gw, gh)) != CS_OK)
		goto out;
	size_t n = (size_t)gw * gh;
	ca = malloc(n);
	cb = malloc(n);
	if (ca == NULL || cb == NULL) {
		rc = cs_error(CS_ENOMEM, "out of memory");
		goto out;
	}
	if ((rc = cs_sky_stats(&a, o->rb_threshold, ca, &pr->render_stats)) != CS_OK ||
	    (rc = cs_sky_stats(&b, o->rb_threshold, cb, &pr->photo_stats)) != CS_OK ||
	    (rc = cs_sky_diff(&a, &b, &pr->render_stats, &pr->photo_stats, ca, cb, &pr->diff)) !=
		    CS_OK)
		goto out;
	pr->verdict = cs_skycompare_verdict(&pr->render_stats, &pr->photo_stats, &pr->diff,
					    pr->verdict_text, sizeof pr->verdict_text);
	rc = pictures(o, pr->index, &a, &b, ca, cb);
out:
	free(ca);
	free(cb);
	cs_picture_free(&a);
	cs_picture_free(&b);
	return rc;
}

static int check_opts(const struct cs_skycompare_opts *o)
{
	const char *paths[3] = {o->side_path, o->overlay_path, o->diff_path};
	static const char *const names[3] = {"-o", "--overlay", "--diff"};
	int series = o->series_render != NULL;
	if (series) {
		CS_TRY(cs_series_pattern_check("--series", o->series_render));
		CS_TRY(cs_series_pattern_check("--series", o->series_photo));
	} else if (o->render_path == NULL || o->photo_path == NULL) {
		return cs_error(CS_EINVAL, "give a render and a photo, or --series");
	}
	for (int k = 0; k < 3; k++) {
		if (paths[k] == NULL)
			continue;
		if (strcmp(paths[k], "-") == 0)
			return cs_error(CS_EINVAL, "%s: the report is on standard output: name a file",
					names[k]);
		const char *dot = strrchr(paths[k], '.');
		if (dot == NULL || strcasecmp(dot, ".png") != 0)
			return cs_error(CS_EINVAL, "%s %s: the name must end in .png", names[k],
					paths[k]);
		if (series)
			CS_TRY(cs_series_pattern_check(names[k], paths[k]));
	}
	if (o->grid_w < 0 || o->grid_h < 0 || (o->grid_w == 0) != (o->grid_h == 0))
		return cs_error(CS_EINVAL, "--grid: give both a width and a height");
	if (!(o->rb_threshold > 0.0) || !(o->diff_range > 0.0) || o->split < 0.0 || o->split > 1.0 ||
	    o->blend > 1.0)
		return cs_error(CS_EINVAL, "a threshold, range, split or blend out of range");
	return CS_OK;
}

/* ---- the run --------------------------------------------------------------- */

static int add_pair(struct cs_skycompare_result *r, struct cs_skycompare_pair **pr)
{
	if ((r->npairs & (r->npairs - 1)) == 0) { /* 0, 1, 2, 4 ...: grow */
		size_t cap = r->npairs ? (size_t)r->npairs * 2 : 1;
		struct cs_skycompare_pair *np = realloc(r->pairs, cap * sizeof *np);
		if (np == NULL)
			return cs_error(CS_ENOMEM, "out of memory");
		r->pairs = np;
	}
	*pr = &r->pairs[r->npairs++];
	memset(*pr, 0, sizeof **pr);
	return CS_OK;
}

static void summarise(struct cs_skycompare_result *r)
{
	double lr = 0.0;
	int nl = 0, ne = 0;
	for (int i = 0; i < r->npairs; i++) {
		const struct cs_skycompare_pair *p = &r->pairs[i];
		if (p->status == 1)
			r->missing++;
		else if (p->status != CS_OK)
			r->failed++;
		if (p->status != CS_OK)
			continue;
		r->compared++;
		r->mean_d_cloud += p->diff.d_cloud_fraction;
		r->mean_abs_d_cloud += fabs(p->diff.d_cloud_fraction);
		if (isfinite(p->diff.emd_mean))
			r->mean_emd += p->diff.emd_mean, ne++;
		r->verdicts[p->verdict]++;
		if (isfinite(p->diff.lum_ratio) && p->diff.lum_ratio > 0.0)
			lr += log(p->diff.lum_ratio), nl++;
	}
	if (r->compared) {
		r->mean_d_cloud /= r->compared;
		r->mean_abs_d_cloud /= r->compared;
		r->mean_emd = ne ? r->mean_emd / ne : NAN;
	}
	r->mean_lum_ratio = nl ? exp(lr / nl) : NAN; /* geometric: 2x and 0.5x cancel */
}

static int run_series(const struct cs_skycompare_opts *o, struct cs_skycompare_result *r)
{
	char name[1024];
	long i = o->first;
	if (i < 0) {
		CS_TRY(cs_series_name(o->series_render, 0, name, sizeof name));
		i = access(name, F_OK) == 0 ? 0 : 1;
	}
	long i0 = i;
	for (; o->last < 0 || i <= o->last; i++) {
		struct cs_skycompare_pair *p;
		char rn[1024], pn[1024];
		CS_TRY(cs_series_name(o->series_render, i, rn, sizeof rn));
		CS_TRY(cs_series_name(o->series_photo, i, pn, sizeof pn));
		int have_r = access(rn, F_OK) == 0, have_p = access(pn, F_OK) == 0;
		if (!have_r && o->last < 0)
			break;
		CS_TRY(add_pair(r, &p));
		p->index = i;
		snprintf(p->render, sizeof p->render, "%s", rn);
		snprintf(p->photo, sizeof p->photo, "%s", pn);
		if (!have_r || !have_p) {
			p->status = 1;
			snprintf(p->message, sizeof p->message, "%.480s: missing", have_r ? pn : rn);
			continue;
		}
		p->status = compare(o, p);
		if (o->progress && o->last >= i0)
			o->progress(o->progress_user, (double)(i - i0 + 1) / (double)(o->last - i0 + 1));
		if (p->status == CS_EINVAL && r->npairs == 1)
			return p->status; /* a usage problem shows on the first pair */
		if (p->status != CS_OK)
			snprintf(p->message, sizeof p->message, "%s", cs_errmsg());
	}
	summarise(r);
	if (r->compared == 0)
		return cs_error(CS_EDATA, "%s: no pair of the series could be compared (the first "
				"render is %s)", o->series_render,
				r->npairs ? r->pairs[0].render : "absent");
	return CS_OK;
}

int cs_skycompare_run(const struct cs_skycompare_opts *o, struct cs_skycompare_result *r)
{
	memset(r, 0, sizeof *r);
	CS_TRY(check_opts(o));
	if (o->series_render)
		return run_series(o, r);
	struct cs_skycompare_pair *p;
	CS_TRY(add_pair(r, &p));
	p->index = -1;
	snprintf(p->render, sizeof p->render, "%s", o->render_path);
	snprintf(p->photo, sizeof p->photo, "%s", o->photo_path);
	p->status = compare(o, p);
	summarise(r);
	return p->status;
}

void cs_skycompare_result_free(struct cs_skycompare_result *r)
{
	free(r->pairs);
	r->pairs = NULL;
	r->npairs = 0;
}
