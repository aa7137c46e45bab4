#include "apps/cloudrender_run.h"
#include "apps/cloudrender_session.h"

#include "io/skyclass.h"

#include "core/color.h"
#include "core/err.h"
#include "core/geo.h"
#include "io/exr.h"
#include "render/device.h"
#include "io/image.h"
#include "io/caption.h"
#include "io/cpt.h"
#include "render/water.h"
#include "io/raster.h"
#include "core/fileio.h"
#include "terrain/heightfield.h"
#include "render/reference.h"
#include "render/scene.h"
#include "render/camera.h"
#include "terrain/terrain.h"
#include "astro/sun.h"
#include "core/time.h"
#include "noise/cache.h"
#include "noise/volume.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

#ifndef CS_VERSION
#define CS_VERSION "unknown"
#endif

void cs_cloudrender_defaults(struct cs_cloudrender_opts *o)
{
	memset(o, 0, sizeof *o);
	o->noise_size = 64;
	o->width = 640;
	o->height = 360;
	o->quality = "medium";
	cs_render_quality("medium", &o->settings);
	o->seed = -1;
	o->haze_steps = -1;
	o->min_transmittance = -1.0;
	o->tower_cell_m = -1.0;
	o->heap_towers = -1;
	o->deck_lattice = -1;
	o->ground_sky = -1;
	o->march = o->light_march = -1;
	o->spp = 64;
	o->frames_from = o->frames_to = -1;
}

void cs_cloudrender_settings(const struct cs_cloudrender_opts *o,
			     struct cs_render_settings *s)
{
	*s = o->settings;
	if (o->steps > 0) {
		s->steps = o->steps;
		if (s->max_steps < 4 * o->steps) /* room for thick layers */
			s->max_steps = 4 * o->steps;
	}
	if (o->light_steps > 0)
		s->light_steps = o->light_steps;
	if (o->ms_octaves > 0)
		s->ms_octaves = o->ms_octaves;
	if (o->no_ambient)
		s->ambient = 0;
	if (o->no_jitter)
		s->jitter = 0.0;
	if (o->seed >= 0)
		s->seed = (uint32_t)o->seed;
	if (o->haze_steps >= 0)
		s->haze_steps = o->haze_steps;
	if (o->max_steps > 0)
		s->max_steps = o->max_steps < s->steps ? s->steps : o->max_steps;
	if (o->min_transmittance >= 0.0)
		s->min_transmittance = o->min_transmittance;
	if (o->march >= 0)
		s->march = o->march;
	if (o->light_march >= 0)
		s->light_march = o->light_march;
	if (o->tower_cell_m >= 0.0)
		s->tower_cell_m = o->tower_cell_m;
	if (o->heap_towers >= 0)
		s->heap_towers = o->heap_towers;
	if (o->deck_lattice >= 0)
		s->deck_lattice = o->deck_lattice;
	if (o->ground_sky >= 0)
		s->ground_sky = o->ground_sky;
	/* On a GPU, where the light is looked up in the cache (low, medium
	 * and high), a cloudy sample's light at every sample: faster there and
	 * no less accurate (an H200 at 1920x1080: low 8.51 -> 7.11 ms a frame,
	 * medium 10.78 -> 9.03; the study's relative MSE 0.01537 -> 0.01515
	 * and 0.01195 -> 0.01171), where it costs the CPU 5 to 20 %
	 * (cloudrender(1), GPU).  A light that marches keeps 2 (high when it
	 * marched: 46.4 against 49.2 ms). */
	if (o->source_every > 0)
		s->source_every = o->source_every;
	else if (o->device == CS_DEVICE_CUDA && !o->reference && CS_LIGHT_CACHED(s->light_march))
		s->source_every = 1;
}

enum cs_out_format cs_output_format(const char *path)
{
	if (strcmp(path, "-") == 0)
		return CS_FMT_PNG;
	const char *dot = strrchr(path, '.');
	if (dot == NULL || strchr(dot, '/'))
		return CS_FMT_NONE;
	return cs_output_format_named(dot + 1);
}

enum cs_out_format cs_output_format_named(const char *name)
{
	static const struct {
		const char *name;
		enum cs_out_format f;
	} names[] = {
		{"png", CS_FMT_PNG}, {"exr", CS_FMT_EXR}, {"gtiff", CS_FMT_TIFF},
		{"tiff", CS_FMT_TIFF}, {"tif", CS_FMT_TIFF}, {"jpeg", CS_FMT_JPEG},
		{"jpg", CS_FMT_JPEG},
	};
	for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
		if (strcasecmp(name, names[i].name) == 0)
			return names[i].f;
	return CS_FMT_NONE;
}

enum cs_out_format cs_output_format_of(const struct cs_cloudrender_opts *o, int i)
{
	return o->formats[i] != CS_FMT_NONE ? o->formats[i] : cs_output_format(o->outputs[i]);
}

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* The display encodings of a frame, made once for all the outputs that
 * need them. */
struct display {
	uint8_t *rgb8;
	uint16_t *rgb16;
};

static int want_rgb8(struct display *d, const float *px, size_t n, double ev)
{
	if (d->rgb8 != NULL)
		return CS_OK;
	if ((d->rgb8 = malloc(n * 3)) == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	cs_tonemap_srgb8(px, 5, n, ev, d->rgb8);
	return CS_OK;
}

static int want_rgb16(struct display *d, const float *px, size_t n, double ev)
{
	if (d->rgb16 != NULL)
		return CS_OK;
	if ((d->rgb16 = malloc(n * 3 * sizeof *d->rgb16)) == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	cs_tonemap_srgb16(px, 5, n, ev, d->rgb16);
	return CS_OK;
}

/* What a frame says it shows (cloudrender_meta.c), for its outputs. */
struct meta {
	char *json;               /* the description, JSON */
	char text[1024];          /* the same in words: the caption's lines */
	char software[64];
	char cap_date[24];        /* EXR capDate: "YYYY:MM:DD hh:mm:ss" */
};

static int make_meta(const struct cs_cloudrender_opts *o, const struct cs_cloudrender_result *r,
		     struct meta *m)
{
	char when[32];
	cs_cloudrender_caption_text(r, m->text, sizeof m->text);
	snprintf(m->software, sizeof m->software, "cloudrender (cloudscape) %s", CS_VERSION);
	cs_time_format(r->wx.time_utc, when, sizeof when); /* 2021-06-14T16:45:00Z */
	snprintf(m->cap_date, sizeof m->cap_date, "%.4s:%.2s:%.2s %.8s", when, when + 5,
		 when + 8, when + 11);
	return cs_cloudrender_meta_json(o, r, &m->json);
}

/* The PNG, with the frame's description in its text chunks. */
static int write_png(const struct cs_cloudrender_opts *o, const struct meta *m,
		     struct cs_outfile *of, const char *name, const struct display *d)
{
	const struct cs_png_text text[] = {
		{"Software", m->software, 0},
		{"Description", m->text, 1},
		{"cloudscape", m->json, 1},
	};
	return cs_png_write_text_to(of, name, o->width, o->height, 3, o->png16 ? 16 : 8,
				    o->png16 ? (const void *)d->rgb16 : (const void *)d->rgb8,
				    text, 3);
}

/* The EXR, with the frame's description in its attributes: OpenEXR's
 * standard capDate, utcOffset, latitude, longitude, altitude and
 * comments, and ours. */
static int write_exr(const struct cs_cloudrender_opts *o, const struct cs_cloudrender_result *r,
		     const struct meta *m, struct cs_outfile *of, const char *name,
		     const float *px)
{
	const struct cs_exr_channel ch[5] = {
		{"R", o->use_float, px + 0, 5}, {"G", o->use_float, px + 1, 5},
		{"B", o->use_float, px + 2, 5}, {"A", o->use_float, px + 3, 5},
		{"Z", 1, px + 4, 5},
	};
	char when[32];
	cs_time_format(r->wx.time_utc, when, sizeof when);
	const struct cs_exr_attr attrs[] = {
		{"cloudscapeTimeUTC", CS_EXR_STRING, {0, 0, 0}, when, 0},
		{"cloudscapeQuality", CS_EXR_STRING, {0, 0, 0}, o->quality, 0},
		{"cloudscapeUnits", CS_EXR_STRING, {0, 0, 0},
		 "RGB: radiance in kcd/m^2, linear sRGB; A: 1 - cloud transmittance; Z: metres", 0},
		{"cloudscapeSoftware", CS_EXR_STRING, {0, 0, 0}, m->software, 0},
		{"cloudscapeFrame", CS_EXR_STRING, {0, 0, 0}, m->json, 0},
		{"comments", CS_EXR_STRING, {0, 0, 0}, m->text, 0},
		{"capDate", CS_EXR_STRING, {0, 0, 0}, m->cap_date, 0},
		{"utcOffset", CS_EXR_FLOAT, {0, 0, 0}, NULL, 0.0},
		{"latitude", CS_EXR_FLOAT, {0, 0, 0}, NULL, r->cam_lat_deg},
		{"longitude", CS_EXR_FLOAT, {0, 0, 0}, NULL, r->cam_lon_deg},
		{"altitude", CS_EXR_FLOAT, {0, 0, 0}, NULL, r->cam_alt_m},
	};
	return cs_exr_write_to(of, name, o->width, o->height, ch, 5, attrs,
			       (int)(sizeof attrs / sizeof attrs[0]), o->threads);
}

/* One output, into its open temporary. */
static int write_one(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r,
		     const float *px, int i, struct cs_outfile *of, struct display *d,
		     const struct meta *m)
{
	const char *name = strcmp(o->outputs[i], "-") == 0 ? "standard output" : o->outputs[i];
	size_t n = (size_t)o->width * o->height;
	int w = o->width, h = o->height, rc;
	switch (cs_output_format_of(o, i)) {
	case CS_FMT_EXR:
		return write_exr(o, r, m, of, name, px);
	case CS_FMT_TIFF:
		if (o->use_float) {
			static const char *const bands[5] = {"R", "G", "B", "A", "Z"};
			static const char *const opts[] = {"COMPRESS=DEFLATE", "PREDICTOR=3",
							   "PHOTOMETRIC=RGB", "ALPHA=NO", NULL};
			return cs_raster_write_to(of, name, "GTiff", w, h, 5, CS_SAMPLE_F32, px,
						  opts, bands);
		} else {
			static const char *const opts[] = {"COMPRESS=DEFLATE", "PREDICTOR=2",
							   "PHOTOMETRIC=RGB", NULL};
			if ((rc = want_rgb16(d, px, n, r->exposure_ev)) != CS_OK)
				return rc;
			return cs_raster_write_to(of, name, "GTiff", w, h, 3, CS_SAMPLE_U16,
						  d->rgb16, opts, NULL);
		}
	case CS_FMT_JPEG: {
		char q[32];
		snprintf(q, sizeof q, "QUALITY=%d", o->jpeg_quality > 0 ? o->jpeg_quality : 90);
		const char *const opts[] = {q, NULL};
		if ((rc = want_rgb8(d, px, n, r->exposure_ev)) != CS_OK)
			return rc;
		return cs_raster_write_to(of, name, "JPEG", w, h, 3, CS_SAMPLE_U8, d->rgb8, opts,
					  NULL);
	}
	case CS_FMT_PNG:
		rc = o->png16 ? want_rgb16(d, px, n, r->exposure_ev)
			      : want_rgb8(d, px, n, r->exposure_ev);
		return rc == CS_OK ? write_png(o, m, of, name, d) : rc;
	case CS_FMT_NONE:
		break;
	}
	return cs_error(CS_EINVAL, "output '%s': unknown format", o->outputs[i]);
}

/* Every output written to its temporary first, then all renamed: a run
 * that fails leaves none of them. */
static int write_outputs(const struct cs_cloudrender_opts *o,
			 struct cs_cloudrender_result *r, float *px)
{
	size_t n = (size_t)o->width * o->height;
	r->exposure_ev = o->exposure_auto ? cs_auto_exposure_ev(px, 5, n) : o->exposure_ev;
	struct meta m;
	int rc = make_meta(o, r, &m);
	if (rc == CS_OK && o->caption) {
		/* white on every display: 8 x the tone curve's input that
		 * saturates ACES (7.24 x 16 kcd/m^2 at 0 EV), below half's range */
		double white = 128.0 / exp2(r->exposure_ev);
		cs_caption_stamp(px, 5, o->width, o->height, 3, m.text,
				 (float)(white < 60000.0 ? white : 60000.0));
	}
	struct cs_outset set;
	cs_outset_init(&set, o->no_clobber ? CS_OUT_NO_CLOBBER : 0);
	struct display d = {NULL, NULL};
	for (int i = 0; i < o->noutputs && rc == CS_OK; i++) {
		struct cs_outfile *of;
		rc = cs_outset_open(&set, o->outputs[i], &of);
		if (rc == CS_OK)
			rc = write_one(o, r, px, i, of, &d, &m);
	}
	if (rc == CS_OK)
		rc = cs_outset_commit(&set);
	cs_outset_abort(&set);
	free(d.rgb8);
	free(d.rgb16);
	free(m.json);
	return rc;
}

/* Places the heightfield: three corners' geographic positions on the
 * sphere fix the affine map from world to grid. */
static int place_terrain(const struct cs_scene *sc, const struct cs_wx *wx,
			 const struct cs_terrain *t, struct cs_hfield *hf)
{
	static const int corner[3] = {0, 1, 3}; /* upper-left, upper-right, lower-left */
	double col[3] = {0, t->width - 1, 0}, row[3] = {0, 0, t->height - 1}, x[3], y[3];
	for (int k = 0; k < 3; k++) {
		cs_v3 p = cs_geo_to_world(wx->site.lat_deg, wx->site.lon_deg, sc->earth_radius_m,
					  t->corner_lat[corner[k]], t->corner_lon[corner[k]], 0.0);
		x[k] = p.x, y[k] = p.y;
	}
	double a[3], b[3];
	int rc = cs_hfield_place(col, row, x, y, a, b);
	if (rc == CS_OK)
		rc = cs_hfield_init(hf, t->h, t->width, t->height, a, b, sc->earth_radius_m);
	return rc;
}

/* The option checks no single option shows: both standard streams once. */
static int check_streams(const struct cs_cloudrender_opts *o)
{
	int to_stdout = 0;
	for (int i = 0; i < o->noutputs; i++)
		to_stdout += strcmp(o->outputs[i], "-") == 0;
	if (to_stdout > 1)
		return cs_error(CS_EINVAL, "only one output can go to standard output");
	if (o->wx_path && o->noise_path && strcmp(o->wx_path, "-") == 0 &&
	    strcmp(o->noise_path, "-") == 0)
		return cs_error(CS_EINVAL, "--wx - and --noise - cannot both read standard input");
	return CS_OK;
}

/* What an all-sky imager would see in a fisheye render: the sky's pixels
 * more than CS_SKY_MIN_ELEVATION_DEG above the horizon (not ground, not
 * within 8 degrees of the sun, which imagers shade) classified by their
 * red/blue ratio. */
static int sky_imager(const struct cs_camera *cam, const struct cs_scene *sc, const float *px,
		      struct cs_cloudrender_result *r)
{
	size_t n = (size_t)cam->width * cam->height;
	unsigned char *use = calloc(n, 1);
	if (use == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	long opaque = 0;
	double min_up = sin(CS_SKY_MIN_ELEVATION_DEG * CS_PI / 180.0);
	double shade = cos(8.0 * CS_PI / 180.0); /* the imager's sun shade */
	for (int j = 0; j < cam->height; j++)
		for (int i = 0; i < cam->width; i++) {
			size_t k = (size_t)j * cam->width + i;
			const float *p = px + k * 5;
			cs_v3 d;
			if (!cs_camera_ray(cam, i, j, &d) || v3_dot(d, cam->zenith) < min_up)
				continue;
			if ((sc->effects & CS_FX_KEY) && v3_dot(d, sc->sun_dir) > shade)
				continue;
			if (p[3] <= 0.0f && p[4] < 0.5f * (float)CS_SKY_DEPTH_M)
				continue; /* ground or terrain */
			if (!(p[2] > 0.0f))
				continue; /* black: not classified, not counted */
			use[k] = 1;
			opaque += p[3] > 0.5f;
		}
	struct cs_sky_class c;
	cs_sky_classify(px, 5, n, use, CS_SKY_RB_THRESHOLD, &c);
	r->cloud_fraction_rb = c.cloud_fraction;
	r->cloud_fraction_alpha = c.sky_pixels ? (double)opaque / c.sky_pixels : 0.0;
	free(use);
	return CS_OK;
}

/* The ground irradiance at the camera and over 10 km around the site
 * (5 x 5 points): a forecast's radiation is a mean over its grid cell, and
 * under broken cloud one point is either in a shadow or not. */
/* The ground irradiance by the integrator the run renders with (the
 * reference: 16 x spp paths a point).  The march's rays see the sky as a
 * frame looking up from the camera would draw it (cs_frame_scene of a
 * small all-sky camera there): with the ground's field that lights the
 * haze and the rain where they are (measured on the scene as it is, the
 * haze over the camera under the thick part of the meteoblue capture's
 * rain hour took the camera's DHI from 24 to 55 W/m^2). */
static int measure_irradiance(const struct cs_cloudrender_opts *o, const struct cs_scene *sc,
			      const struct cs_render_settings *s, cs_v3 pos,
			      struct cs_cloudrender_result *r)
{
	struct cs_render_stats st = {0};
	r->area_size_m = CS_IRRADIANCE_AREA_M;
	if (o->reference) {
		struct cs_reference_settings rs = {o->spp, s->seed, o->max_bounces};
		int paths = o->spp < 65536 ? 16 * o->spp : 1048576;
		cs_reference_irradiance_at(sc, &rs, pos, paths, &r->irr_camera, &st);
		cs_reference_irradiance_area(sc, &rs, r->area_size_m, 5, paths, &r->irr_area, &st);
		return CS_OK;
	}
	struct cs_camera up;
	struct cs_scene *frame = NULL;
	uint64_t evaluations;
	int lit, rc = cs_camera_init(&up, sc, pos, r->wx.site.lat_deg, 0.0, 90.0, 70.0, 64, 64);
	up.projection = CS_PROJ_FISHEYE;
	if (rc == CS_OK)
		rc = cs_frame_scene(sc, &up, s, o->threads, &frame, &evaluations, &lit);
	if (rc != CS_OK)
		return rc;
	const struct cs_scene *use = frame != NULL ? frame : sc;
	cs_irradiance_at(use, s, pos, &r->irr_camera, &st);
	cs_irradiance_area(use, s, r->area_size_m, 5, &r->irr_area, &st);
	cs_frame_scene_free(frame);
	return CS_OK;
}

/* --camera-agl and --look-at: in range, and no look given twice. */
static int check_camera(const struct cs_cloudrender_opts *o)
{
	if (o->have_look && o->have_look_at)
		return cs_error(CS_EINVAL, "--look and --look-at exclude each other");
	if (o->have_camera_agl && !(o->camera_agl_m >= 0.0 && o->camera_agl_m <= 100000.0))
		return cs_error(CS_EINVAL, "the camera's height above the ground must be "
				"0..100000 m, not %g", o->camera_agl_m);
	if (o->have_look_at && !(fabs(o->look_at_lat_deg) <= 90.0 &&
				 fabs(o->look_at_lon_deg) <= 360.0 &&
				 isfinite(o->look_at_alt_m)))
		return cs_error(CS_EINVAL, "--look-at %g,%g,%g is not a place", o->look_at_lat_deg,
				o->look_at_lon_deg, o->look_at_alt_m);
	return CS_OK;
}

/* The camera's place and look by --camera-agl and --look-at, once the
 * ground under it (m above sea level) is known: *alt, *pos, *az, *el. */
static int place_camera_easy(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r,
			     const struct cs_scene *sc, double lat, double lon, double ground,
			     double *alt, cs_v3 *pos, double *az, double *el)
{
	if (o->have_camera_agl) {
		*alt = ground + o->camera_agl_m;
		*pos = cs_geo_to_world(r->wx.site.lat_deg, r->wx.site.lon_deg, sc->earth_radius_m,
				       lat, lon, *alt);
	}
	if (!o->have_look_at)
		return CS_OK;
	if (cs_look_at(sc->earth_radius_m, lat, lon, *alt, o->look_at_lat_deg, o->look_at_lon_deg,
		       o->look_at_alt_m, az, el) != 0)
		return cs_error(CS_EINVAL, "--look-at %g,%g,%g is where the camera is",
				o->look_at_lat_deg, o->look_at_lon_deg, o->look_at_alt_m);
	snprintf(r->look_why, sizeof r->look_why, "--look-at %.5f,%.5f,%.0f",
		 o->look_at_lat_deg, o->look_at_lon_deg, o->look_at_alt_m);
	return CS_OK;
}

/* Every check that needs no file: outputs, size, streams, settings, view. */
static int check_run(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r,
		     const struct cs_view **view)
{
	*view = NULL;
	if (o->noutputs < 1)
		return cs_error(CS_EINVAL, "no output: give -o FILE.png or -o FILE.exr");
	for (int i = 0; i < o->noutputs; i++)
		if (cs_output_format_of(o, i) == CS_FMT_NONE)
			return cs_error(CS_EINVAL, "output '%s': unknown format: the name must end "
					"in " CS_OUT_EXTENSIONS " (or give -of)", o->outputs[i]);
	if (o->jpeg_quality < 0 || o->jpeg_quality > 100)
		return cs_error(CS_EINVAL, "JPEG quality %d is outside 1..100", o->jpeg_quality);
	if (o->width < 1 || o->height < 1)
		return cs_error(CS_EINVAL, "image size %dx%d is impossible (1..16384 a side)",
				o->width, o->height);
	if (o->width > 16384 || o->height > 16384 || (double)o->width * o->height > 1e8)
		return cs_error(CS_EINVAL, "image size %dx%d is too large: it would need about "
				"%.3g GB of memory (%d bytes a pixel); the most is 16384 a side "
				"and 10^8 pixels (about %.1f GB)", o->width, o->height,
				(double)o->width * o->height * CS_CLOUDRENDER_BYTES_PER_PIXEL / 1e9,
				CS_CLOUDRENDER_BYTES_PER_PIXEL,
				1e8 * CS_CLOUDRENDER_BYTES_PER_PIXEL / 1e9);
	int rc = check_streams(o);
	if (rc != CS_OK)
		return rc;
	cs_cloudrender_settings(o, &r->settings);
	rc = cs_render_settings_check(&r->settings);
	if (rc != CS_OK)
		return rc;
	*view = NULL;
	if (o->view && (*view = cs_viewset_find(o->views, o->view)) == NULL)
		return cs_error(CS_EINVAL, "unknown view '%s' (see --list-views)", o->view);
	return check_camera(o);
}

/* The noise volume (the weather is the series', read_series()). */
static int load_inputs(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r,
		       struct cs_volume *noise)
{
	int rc = CS_OK;
	double t0 = now_s();
	if (o->noise_path) {
		rc = cs_volume_read_exr(o->noise_path, noise, o->threads);
	} else {
		int hit;
		rc = cs_volume_new(noise, o->noise_size, o->noise_size);
		if (rc == CS_OK) /* from the cache when an earlier run baked it */
			rc = cs_noise_cache_bake(noise, o->threads, &hit);
	}
	r->t_noise_s = now_s() - t0;
	return rc;
}

/* What a run holds besides the scene: the terrain and its colour, read
 * once for all the frames, and the heightfield placed around a site. */
struct ground {
	struct cs_terrain terrain;
	struct cs_hfield hf;
	int have_terrain, have_hf;
	double hf_lat_deg, hf_lon_deg; /* the site the heightfield is placed around */
	int hf_placed;                 /* how often it was (a GPU's copy is stale) */
	uint8_t *drape;
	int drape_w, drape_h;
	struct cs_cpt *cpt;
};

static int load_terrain(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r,
			struct cs_scene *sc, struct ground *g)
{
	if (!o->terrain_path)
		return o->terrain_color_path ? cs_error(CS_EINVAL, "--terrain-color needs --terrain")
		       : o->terrain_cpt_path ? cs_error(CS_EINVAL, "--terrain-cpt needs --terrain")
					     : CS_OK;
	if (o->terrain_color_path && o->terrain_cpt_path)
		return cs_error(CS_EINVAL, "--terrain-color and --terrain-cpt exclude each other");
	int rc = CS_OK;
	if (!g->have_terrain) { /* the first frame: the files */
		rc = cs_terrain_read(o->terrain_path, &g->terrain);
		if (rc != CS_OK)
			return rc;
		g->have_terrain = 1;
		if (o->terrain_color_path) {
			rc = cs_png_read_rgb8(o->terrain_color_path, &g->drape, &g->drape_w,
					      &g->drape_h);
			if (rc != CS_OK)
				return rc;
		}
		if (o->terrain_cpt_path) {
			if ((g->cpt = malloc(sizeof *g->cpt)) == NULL)
				return cs_error(CS_ENOMEM, "out of memory");
			CS_TRY(cs_cpt_read(o->terrain_cpt_path, g->cpt));
		}
	}
	if (!g->have_hf || g->hf_lat_deg != r->wx.site.lat_deg ||
	    g->hf_lon_deg != r->wx.site.lon_deg) { /* the world is centred on the site */
		if (g->have_hf)
			cs_hfield_free(&g->hf);
		g->have_hf = 0;
		rc = place_terrain(sc, &r->wx, &g->terrain, &g->hf);
		if (rc != CS_OK)
			return rc;
		g->have_hf = 1;
		g->hf_lat_deg = r->wx.site.lat_deg, g->hf_lon_deg = r->wx.site.lon_deg;
		g->hf_placed++;
	}
	sc->terrain = &g->hf;
	sc->effects |= CS_FX_TERRAIN;
	if (g->drape) {
		sc->terrain_color = g->drape;
		sc->terrain_color_w = g->drape_w, sc->terrain_color_h = g->drape_h;
	}
	if (g->cpt)
		sc->terrain_cpt = g->cpt;
	if (g->terrain.water && cs_terrain_water_count(&g->terrain) > 0) {
		sc->terrain_water = g->terrain.water;
		sc->water_mss = cs_water_slope_variance(r->wx.wind_speed_m_s);
		sc->effects |= CS_FX_WATER;
	}
	return CS_OK;
}

/* The camera: the default eye 2 m above the site looking where the clouds
 * are (cs_default_look), a named view, or an explicit place and look; on
 * the terrain where there is one; never below the ground. */
static int place_camera(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r,
			const struct cs_scene *sc, const struct cs_view *view,
			const struct ground *g, struct cs_camera *cam)
{
	double lat = r->wx.site.lat_deg, lon = r->wx.site.lon_deg;
	double alt = r->wx.site.alt_m + 2.0, az = 0.0, el = 8.0, fov = 70.0;
	snprintf(r->look_why, sizeof r->look_why, "--look");
	if (view) {
		snprintf(r->look_why, sizeof r->look_why, "view %s", view->name);
		lat = view->place->lat_deg, lon = view->place->lon_deg;
		alt = cs_view_alt_m(view);
		az = view->azimuth_deg, el = view->elevation_deg, fov = view->fov_deg;
	}
	if (o->have_camera)
		lat = o->cam_lat_deg, lon = o->cam_lon_deg, alt = o->cam_alt_m;
	if (o->have_look)
		az = o->look_az_deg, el = o->look_el_deg;
	if (o->fov_deg > 0.0)
		fov = o->fov_deg;
	cs_v3 pos = cs_geo_to_world(r->wx.site.lat_deg, r->wx.site.lon_deg,
				    sc->earth_radius_m, lat, lon, alt);
	double ground = sc->ground_alt_m, th;
	int over_terrain = g->have_hf && cs_hfield_height(&g->hf, pos.x, pos.y, &th);
	if (over_terrain) {
		ground = th;
		if (!view && !o->have_camera) { /* the default eye stands on the terrain */
			alt = th + 2.0;
			pos = cs_geo_to_world(r->wx.site.lat_deg, r->wx.site.lon_deg,
					      sc->earth_radius_m, lat, lon, alt);
		}
	}
	int rc = place_camera_easy(o, r, sc, lat, lon, ground, &alt, &pos, &az, &el);
	if (rc != CS_OK)
		return rc;
	if (alt < ground)
		return cs_error(CS_EINVAL, "the camera at %.1f m is below the %s (%.1f m)",
				alt, over_terrain ? "terrain" : "ground", ground);
	if (!view && !o->have_look && !o->have_look_at) {
		double fx[CS_WX_MAX_FAR], fy[CS_WX_MAX_FAR];
		for (int f = 0; f < r->wx.nfar; f++) {
			cs_v3 p = cs_geo_to_world(r->wx.site.lat_deg, r->wx.site.lon_deg,
						  sc->earth_radius_m, r->wx.far[f].site.lat_deg,
						  r->wx.far[f].site.lon_deg, 0.0);
			fx[f] = p.x, fy[f] = p.y;
		}
		char why[128];
		cs_default_look(sc, alt, fov, o->width, o->height, fx, fy, r->wx.nfar, &az,
				&el, why, sizeof why);
		snprintf(r->look_why, sizeof r->look_why, "default view: %s", why);
	}
	r->cam_lat_deg = lat, r->cam_lon_deg = lon, r->cam_alt_m = alt;
	r->look_az_deg = az, r->look_el_deg = el, r->fov_deg = fov;
	rc = cs_camera_init(cam, sc, pos, r->wx.site.lat_deg, az, el, fov, o->width, o->height);
	if (rc != CS_OK)
		return rc;
	cam->projection = o->projection;
	r->camera_site_km = cs_great_circle_m(lat, lon, r->wx.site.lat_deg,
					      r->wx.site.lon_deg) / 1000.0;
	r->camera_terrain_km = g->have_terrain ? cs_great_circle_m(lat, lon, g->terrain.center_lat,
								   g->terrain.center_lon) / 1000.0
					       : -1.0;
	struct cs_sun sun;
	if (cs_sun_position(r->wx.time_utc, r->wx.site.lat_deg, r->wx.site.lon_deg, &sun) == CS_OK) {
		r->sun_azimuth_deg = sun.azimuth_deg;
		r->sun_elevation_deg = sun.apparent_elevation_deg;
	}
	return CS_OK;
}

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

/* The scene on the GPU (*gpu) for this frame: uploaded anew where the
 * terrain was placed anew (fresh), else its struct sent again (its noise
 * and terrain travel once a series). */
static int device_scene(struct cs_cuda_scene **gpu, int fresh, const struct cs_scene *sc)
{
	if (*gpu && fresh) {
		cs_cuda_scene_free(*gpu);
		*gpu = NULL;
	}
	return *gpu ? cs_cuda_scene_update(*gpu, sc) : cs_cuda_scene_new(sc, gpu);
}

/* The reference integrator's frame, on the CPU or the GPU, and how
 * converged it is: the relative standard error of each pixel's mean
 * luminance. */
static int render_reference(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r,
			    struct cs_cuda_scene **gpu, int gpu_fresh, const struct cs_scene *sc,
			    const struct cs_camera *cam, float *px)
{
	size_t n = (size_t)cam->width * cam->height;
	float *var = malloc(n * sizeof *var);
	double *rse = malloc(n * sizeof *rse);
	struct cs_reference_settings rs = {o->spp, r->settings.seed, o->max_bounces};
	int rc = var && rse ? CS_OK : cs_error(CS_ENOMEM, "out of memory");
	if (rc == CS_OK && o->device == CS_DEVICE_CUDA) {
		rc = device_scene(gpu, gpu_fresh, sc);
		if (rc == CS_OK)
			rc = cs_cuda_reference(*gpu, cam, &rs, o->progress, o->progress_user, px,
					       var, &r->stats, &r->device_kernel_ms);
		r->device_kernel = "reference";
	} else if (rc == CS_OK)
		rc = cs_render_reference(sc, cam, &rs, o->threads, o->progress, o->progress_user,
					 px, var, &r->stats);
	size_t m = 0;
	for (size_t i = 0; rc == CS_OK && i < n; i++) {
		double y = cs_luminance(px[i * 5], px[i * 5 + 1], px[i * 5 + 2]);
		if (y > 0.0)
			rse[m++] = sqrt(var[i]) / y;
	}
	r->ref_rse_median = r->ref_rse_p95 = -1.0;
	if (m > 0) {
		qsort(rse, m, sizeof *rse, cmp_double);
		r->ref_rse_median = rse[m / 2];
		r->ref_rse_p95 = rse[(size_t)(0.95 * (double)(m - 1))];
	}
	free(var);
	free(rse);
	return rc;
}

/* The frame on the GPU (render/device.h), rendered and copied back; with
 * device_bench, that many warm frames timed.  The scene stays on the device
 * for the frames of a series (*gpu): its noise and terrain travel once,
 * again only when the terrain was placed anew (fresh); each frame sends
 * its own layers, sky and sun. */
static int render_device(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r,
			 struct cs_cuda_scene **gpu, int fresh, const struct cs_scene *sc,
			 const struct cs_camera *cam, float *px)
{
	/* the light caches, the towers' light and the ground's dome: built
	 * on the host (the CPU pool) into a copy of the scene, which the
	 * device takes its copies from (cs_frame_scene) */
	struct cs_scene *cached;
	uint64_t cache_evaluations;
	int ground_lit;
	int rc = cs_frame_scene(sc, cam, &r->settings, o->threads, &cached, &cache_evaluations,
				&ground_lit);
	if (cached != NULL)
		sc = cached;
	if (rc == CS_OK)
		rc = device_scene(gpu, fresh, sc);
	int volumes = cached != NULL ? cs_light_cache_volumes(cached) : 0;
	cs_frame_scene_free(cached);
	if (rc == CS_OK)
		rc = cs_cuda_render(*gpu, cam, &r->settings, px, &r->stats, &r->device_kernel_ms);
	if (rc == CS_OK) {
		r->device_kernel = cs_cuda_kernel_name(*gpu, &r->settings);
		r->stats.light_samples += cache_evaluations;
		r->stats.cache_cells = cache_evaluations;
		r->stats.cache_volumes = volumes;
		r->stats.ground_lit = ground_lit;
	}
	if (rc == CS_OK && o->device_bench > 0)
		rc = cs_cuda_bench(*gpu, cam, &r->settings, o->device_bench, &r->device_frame_ms);
	return rc;
}

/* --device: the settings cs_render_settings_gpu_check refuses are
 * CPU-only, and the benchmark times the march (usage errors); a GPU that
 * is not there is a runtime error (exit 1) that says why, checked before
 * any work. */
static int check_device(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r)
{
	if (o->device != CS_DEVICE_CUDA)
		return o->device_bench > 0 ? cs_error(CS_EINVAL, "--device-bench needs --device cuda")
					   : CS_OK;
	if (o->reference && o->device_bench > 0)
		return cs_error(CS_EINVAL, "--device-bench times the march, not the reference "
				"integrator (use --integrator march)");
	struct cs_render_settings s;
	cs_cloudrender_settings(o, &s);
	if (!o->reference && cs_render_settings_gpu_check(&s) != CS_OK)
		return cs_error(CS_EINVAL, "--device cuda: %s", cs_errmsg());
	if (!cs_device_available(r->device_name, sizeof r->device_name))
		return cs_error(CS_EIO, "--device cuda: %s", r->device_name);
	return CS_OK;
}

/* The frame and what is measured on it. */
static int render_frame(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r,
			struct cs_cuda_scene **gpu, int gpu_fresh, const struct cs_scene *sc,
			const struct cs_camera *cam, float *px)
{
	double t0 = now_s();
	int rc = o->reference ? render_reference(o, r, gpu, gpu_fresh, sc, cam, px)
		 : o->device == CS_DEVICE_CUDA ? render_device(o, r, gpu, gpu_fresh, sc, cam, px)
			      : cs_render_image(sc, cam, &r->settings, o->threads, o->progress,
						o->progress_user, px, &r->stats);
	r->t_render_s = now_s() - t0;
	if (rc != CS_OK)
		return rc;
	r->cloud_fraction_rb = r->cloud_fraction_alpha = -1.0;
	if (o->projection == CS_PROJ_FISHEYE && (rc = sky_imager(cam, sc, px, r)) != CS_OK)
		return rc;
	if (o->irradiance) {
		t0 = now_s();
		rc = measure_irradiance(o, sc, &r->settings, cam->pos, r);
		r->t_irradiance_s = now_s() - t0;
	}
	return rc;
}

int cs_cr_write(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r, float *px)
{
	double t0 = now_s();
	int rc = write_outputs(o, r, px);
	r->t_write_s = now_s() - t0;
	return rc;
}

/* What the frames of a run share: the view, the noise, the terrain, the
 * scene and the frame buffer, made once. */
struct cs_cr_session {
	const struct cs_view *view;
	struct cs_volume noise;
	struct ground g;
	struct cs_scene *sc;
	float *px;
	struct cs_cuda_scene *gpu;     /* --device cuda: the scene on the device */
	int gpu_hf_placed;             /* g.hf_placed when it was uploaded */
};

int cs_cr_session_open(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r,
		       struct cs_cr_session **out)
{
	*out = NULL;
	const struct cs_view *view;
	int rc = check_run(o, r, &view);
	if (rc == CS_OK)
		rc = check_device(o, r);
	if (rc != CS_OK)
		return rc;
	struct cs_cr_session *s = calloc(1, sizeof *s);
	if (s == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	s->view = view;
	*out = s;
	return CS_OK;
}

int cs_cr_session_load(struct cs_cr_session *s, const struct cs_cloudrender_opts *o,
		       struct cs_cloudrender_result *r)
{
	int rc = load_inputs(o, r, &s->noise);
	if (rc != CS_OK)
		return rc;
	s->sc = malloc(sizeof *s->sc);
	s->px = malloc((size_t)o->width * o->height * 5 * sizeof(float));
	if (s->sc == NULL || s->px == NULL)
		return cs_error(CS_ENOMEM, "out of memory for a %dx%d image", o->width, o->height);
	return CS_OK;
}

/* The scene of r->wx, with its terrain, and the camera. */
static int frame_scene(struct cs_cr_session *s, const struct cs_cloudrender_opts *o,
		       struct cs_cloudrender_result *r, struct cs_camera *cam)
{
	struct cs_scene *sc = s->sc;
	r->scene = NULL;
	struct cs_scene_opts so = {o->sky_level};
	int rc = cs_scene_build_opts(sc, &r->wx, r->wx.time_utc, &s->noise, o->threads, &so);
	if (rc != CS_OK)
		return rc;
	r->scene = sc;
	/* the heaps' tilted columns where the settings light them as towers
	 * (for the irradiance too, which reads the scene itself) */
	cs_scene_tilt_fields(sc, &r->settings, o->threads);
	if (r->settings.haze_steps == 0) /* asked for their mean only */
		sc->effects &= ~(unsigned)CS_FX_SHAFTS;
	if (o->no_haze) { /* the air clear; the fog stays */
		sc->haze_beta0_per_m = 0.0;
		sc->effects &= ~(unsigned)CS_FX_SHAFTS;
	}
	rc = load_terrain(o, r, sc, &s->g);
	if (rc == CS_OK)
		rc = place_camera(o, r, sc, s->view, &s->g, cam);
	return rc;
}

int cs_cr_session_look(struct cs_cr_session *s, const struct cs_cloudrender_opts *o,
		       struct cs_cloudrender_result *r)
{
	struct cs_camera cam;
	return frame_scene(s, o, r, &cam);
}

int cs_cr_session_render(struct cs_cr_session *s, const struct cs_cloudrender_opts *o,
			 struct cs_cloudrender_result *r, float **px)
{
	double t0 = now_s();
	struct cs_camera cam;
	int rc = frame_scene(s, o, r, &cam);
	r->t_scene_s = now_s() - t0;
	if (rc == CS_OK && o->ready)
		o->ready(o->ready_user, r);
	if (rc == CS_OK) {
		int fresh = s->gpu_hf_placed != s->g.hf_placed;
		s->gpu_hf_placed = s->g.hf_placed;
		rc = render_frame(o, r, &s->gpu, fresh, s->sc, &cam, s->px);
	}
	*px = s->px;
	return rc;
}

int cs_cr_session_frame(struct cs_cr_session *s, const struct cs_cloudrender_opts *o,
			struct cs_cloudrender_result *r)
{
	float *px;
	int rc = cs_cr_session_render(s, o, r, &px);
	return rc == CS_OK ? cs_cr_write(o, r, px) : rc;
}

void cs_cr_session_close(struct cs_cr_session *s, struct cs_cloudrender_result *r)
{
	if (s == NULL)
		return;
	cs_cuda_scene_free(s->gpu);
	free(s->px);
	free(s->g.drape);
	free(s->g.cpt);
	if (s->g.have_hf)
		cs_hfield_free(&s->g.hf);
	if (s->g.have_terrain)
		cs_terrain_free(&s->g.terrain);
	if (r->scene == s->sc && s->sc) { /* the result keeps the last scene, not
					   * what it pointed to: terrain, colour, noise */
		s->sc->terrain = NULL;
		s->sc->terrain_color = NULL;
		s->sc->terrain_water = NULL;
		s->sc->terrain_cpt = NULL;
		s->sc->noise = NULL;
	} else {
		free(s->sc);
	}
	cs_volume_free(&s->noise);
	free(s);
}

void cs_cloudrender_result_free(struct cs_cloudrender_result *r)
{
	free(r->scene);
	r->scene = NULL;
}
