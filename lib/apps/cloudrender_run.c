#include "apps/cloudrender_run.h"

#include "io/skyclass.h"

#include "core/err.h"
#include "core/geo.h"
#include "io/exr.h"
#include "io/image.h"
#include "terrain/heightfield.h"
#include "render/scene.h"
#include "terrain/terrain.h"
#include "astro/sun.h"
#include "core/time.h"
#include "noise/volume.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

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
}

int cs_output_kind(const char *path)
{
	if (strcmp(path, "-") == 0)
		return 'p';
	const char *dot = strrchr(path, '.');
	if (dot && strcasecmp(dot, ".png") == 0)
		return 'p';
	if (dot && strcasecmp(dot, ".exr") == 0)
		return 'e';
	return 0;
}

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static int write_outputs(const struct cs_cloudrender_opts *o,
			 struct cs_cloudrender_result *r, const float *px)
{
	size_t n = (size_t)o->width * o->height;
	uint8_t *rgb = NULL;
	int rc = CS_OK;
	r->exposure_ev = o->exposure_auto ? cs_auto_exposure_ev(px, 5, n) : o->exposure_ev;
	for (int i = 0; i < o->noutputs && rc == CS_OK; i++) {
		if (cs_output_kind(o->outputs[i]) == 'e') {
			const struct cs_exr_channel ch[5] = {
				{"R", 0, px + 0, 5}, {"G", 0, px + 1, 5}, {"B", 0, px + 2, 5},
				{"A", 0, px + 3, 5}, {"Z", 1, px + 4, 5},
			};
			char when[32];
			cs_time_format(r->wx.time_utc, when, sizeof when);
			const struct cs_exr_attr attrs[] = {
				{"cloudscapeTimeUTC", CS_EXR_STRING, {0, 0, 0}, when, 0},
				{"cloudscapeQuality", CS_EXR_STRING, {0, 0, 0}, o->quality, 0},
				{"cloudscapeUnits", CS_EXR_STRING, {0, 0, 0},
				 "RGB: radiance in kcd/m^2, linear sRGB; A: 1 - cloud transmittance; Z: metres", 0},
			};
			rc = cs_exr_write(o->outputs[i], o->width, o->height, ch, 5, attrs, 3);
		} else {
			if (rgb == NULL) {
				rgb = malloc(n * 3);
				if (rgb == NULL)
					return cs_error(CS_ENOMEM, "out of memory");
				cs_tonemap_srgb8(px, 5, n, r->exposure_ev, rgb);
			}
			rc = cs_png_write(o->outputs[i], o->width, o->height, 3, rgb);
		}
	}
	free(rgb);
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
static void measure_irradiance(const struct cs_scene *sc, const struct cs_render_settings *s,
			       cs_v3 pos, struct cs_cloudrender_result *r)
{
	struct cs_render_stats st = {0};
	r->area_size_m = 10000.0;
	cs_irradiance_at(sc, s, pos, &r->irr_camera, &st);
	cs_irradiance_area(sc, s, r->area_size_m, 5, &r->irr_area, &st);
}

/* Every check that needs no file: outputs, size, streams, settings, view. */
static int check_run(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r,
		     const struct cs_view **view)
{
	if (o->noutputs < 1)
		return cs_error(CS_EINVAL, "no output: give -o FILE.png or -o FILE.exr");
	for (int i = 0; i < o->noutputs; i++)
		if (cs_output_kind(o->outputs[i]) == 0)
			return cs_error(CS_EINVAL, "output '%s': the name must end in .png or .exr",
					o->outputs[i]);
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
	if (o->view && (*view = cs_view_find(o->view)) == NULL)
		return cs_error(CS_EINVAL, "unknown view '%s' (see --list-views)", o->view);
	return CS_OK;
}

/* The weather (and the time), then the noise volume. */
static int load_inputs(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r,
		       struct cs_volume *noise)
{
	int rc = CS_OK;
	if (o->wx_path)
		rc = cs_wx_read(o->wx_path, &r->wx);
	else
		cs_wx_default(&r->wx);
	if (rc != CS_OK)
		return rc;
	if (o->have_time)
		r->wx.time_utc = o->time_utc;
	double t0 = now_s();
	if (o->noise_path) {
		rc = cs_volume_read_exr(o->noise_path, noise);
	} else {
		rc = cs_volume_new(noise, o->noise_size, o->noise_size);
		if (rc == CS_OK)
			rc = cs_volume_bake(noise, o->threads, NULL, NULL);
	}
	r->t_noise_s = now_s() - t0;
	return rc;
}

/* What a run holds besides the scene: the terrain and its colour. */
struct ground {
	struct cs_terrain terrain;
	struct cs_hfield hf;
	int have_terrain, have_hf;
	uint8_t *drape;
};

static int load_terrain(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r,
			struct cs_scene *sc, struct ground *g)
{
	if (!o->terrain_path)
		return o->terrain_color_path ? cs_error(CS_EINVAL, "--terrain-color needs --terrain")
					     : CS_OK;
	int rc = cs_terrain_read(o->terrain_path, &g->terrain);
	if (rc != CS_OK)
		return rc;
	g->have_terrain = 1;
	rc = place_terrain(sc, &r->wx, &g->terrain, &g->hf);
	if (rc != CS_OK)
		return rc;
	g->have_hf = 1;
	sc->terrain = &g->hf;
	sc->effects |= CS_FX_TERRAIN;
	if (o->terrain_color_path) {
		rc = cs_png_read_rgb8(o->terrain_color_path, &g->drape, &sc->terrain_color_w,
				      &sc->terrain_color_h);
		if (rc != CS_OK)
			return rc;
		sc->terrain_color = g->drape;
	}
	return CS_OK;
}

/* The camera: the default eye 2 m above the site looking south-south-east,
 * a named view, or an explicit place and look; on the terrain where there
 * is one; never below the ground. */
static int place_camera(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r,
			const struct cs_scene *sc, const struct cs_view *view,
			const struct ground *g, struct cs_camera *cam)
{
	double lat = r->wx.site.lat_deg, lon = r->wx.site.lon_deg;
	double alt = r->wx.site.alt_m + 2.0, az = 160.0, el = 8.0, fov = 70.0;
	if (view) {
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
	if (alt < ground)
		return cs_error(CS_EINVAL, "the camera at %.1f m is below the %s (%.1f m)",
				alt, over_terrain ? "terrain" : "ground", ground);
	int rc = cs_camera_init(cam, sc, pos, r->wx.site.lat_deg, az, el, fov, o->width, o->height);
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

/* The frame, what is measured on it, and the outputs. */
static int render_and_write(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r,
			    const struct cs_scene *sc, const struct cs_camera *cam, float *px)
{
	double t0 = now_s();
	int rc = cs_render_image(sc, cam, &r->settings, o->threads, o->progress,
				 o->progress_user, px, &r->stats);
	r->t_render_s = now_s() - t0;
	if (rc != CS_OK)
		return rc;
	r->cloud_fraction_rb = r->cloud_fraction_alpha = -1.0;
	if (o->projection == CS_PROJ_FISHEYE && (rc = sky_imager(cam, sc, px, r)) != CS_OK)
		return rc;
	if (o->irradiance) {
		t0 = now_s();
		measure_irradiance(sc, &r->settings, cam->pos, r);
		r->t_irradiance_s = now_s() - t0;
	}
	t0 = now_s();
	rc = write_outputs(o, r, px);
	r->t_write_s = now_s() - t0;
	return rc;
}

int cs_cloudrender_run(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r)
{
	memset(r, 0, sizeof *r);
	const struct cs_view *view;
	int rc = check_run(o, r, &view);
	if (rc != CS_OK)
		return rc;
	struct cs_volume noise;
	memset(&noise, 0, sizeof noise);
	rc = load_inputs(o, r, &noise);
	if (rc != CS_OK) {
		cs_volume_free(&noise);
		return rc;
	}
	double t0 = now_s();
	struct ground g;
	memset(&g, 0, sizeof g);
	struct cs_scene *sc = malloc(sizeof *sc);
	float *px = malloc((size_t)o->width * o->height * 5 * sizeof(float));
	struct cs_camera cam;
	if (sc == NULL || px == NULL)
		rc = cs_error(CS_ENOMEM, "out of memory for a %dx%d image", o->width, o->height);
	if (rc == CS_OK && (rc = cs_scene_build(sc, &r->wx, r->wx.time_utc, &noise)) == CS_OK)
		r->scene = sc;
	if (rc == CS_OK && r->settings.haze_steps == 0) /* asked for their mean only */
		sc->effects &= ~(unsigned)CS_FX_SHAFTS;
	if (rc == CS_OK)
		rc = load_terrain(o, r, sc, &g);
	if (rc == CS_OK)
		rc = place_camera(o, r, sc, view, &g, &cam);
	r->t_scene_s = now_s() - t0;
	if (rc == CS_OK)
		rc = render_and_write(o, r, sc, &cam, px);
	free(px);
	free(g.drape);
	if (g.have_hf)
		cs_hfield_free(&g.hf);
	if (g.have_terrain)
		cs_terrain_free(&g.terrain);
	if (r->scene) { /* what it pointed to is gone: terrain, colour, noise */
		r->scene->terrain = NULL;
		r->scene->terrain_color = NULL;
		r->scene->noise = NULL;
	}
	if (rc != CS_OK) {
		free(sc);
		r->scene = NULL;
	}
	cs_volume_free(&noise);
	return rc;
}

void cs_cloudrender_result_free(struct cs_cloudrender_result *r)
{
	free(r->scene);
	r->scene = NULL;
}
