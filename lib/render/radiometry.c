/* radiometry.c - the ground irradiance the renderer's own light transport
 * produces, in W/m^2, to hold against a forecast's radiation: DNI (the
 * sun's beam through atmosphere and clouds, on a plane facing it), DHI (the
 * hemisphere of sky and cloud radiance times cos(zenith), traced with the
 * renderer's rays), GHI = DNI cos(zenith) + DHI.
 *
 * The renderer works in photometric units (kcd/m^2, klux, by Rec. 709
 * luminance); watts come through the luminous efficacy of daylight as
 * Littlefair (1988) measured it: the beam 70 lm/W at 10 deg sun elevation
 * rising to 95 lm/W at 60 deg (held beyond), diffuse light 144 lm/W under a
 * clear sky falling to 115 lm/W under overcast (here by the share of the
 * sun's beam that the clouds take away). */
#include "render/march.h"

#include "core/color.h"
#include "core/err.h"
#include "core/pool.h"
#include "render/camera.h"
#include "terrain/heightfield.h"

#include <math.h>
#include <stdlib.h>

enum { N_THETA = 8, N_PHI = 24 };

double cs_beam_efficacy_lm_w(double elevation_deg)
{
	double e = elevation_deg < 10.0 ? 10.0 : elevation_deg > 60.0 ? 60.0 : elevation_deg;
	return 70.0 + (e - 10.0) * 0.5;
}

double cs_diffuse_efficacy_lm_w(double clear_fraction)
{
	double f = clear_fraction < 0.0 ? 0.0 : clear_fraction > 1.0 ? 1.0 : clear_fraction;
	return 115.0 + 29.0 * f;
}

/* Pressure over sea-level pressure at an altitude in the U.S. Standard
 * Atmosphere's troposphere (the barometric formula). */
static double pressure_ratio(double altitude_m)
{
	double h = altitude_m < 11000.0 ? altitude_m : 11000.0;
	return pow(1.0 - 2.25577e-5 * h, 5.25588);
}

void cs_clear_sky_ineichen(double zenith_deg, double air_mass_abs, double linke_turbidity,
			   double altitude_m, double dni_extra_w_m2, int perez_enhancement,
			   struct cs_irradiance *out)
{
	out->ghi_w_m2 = out->dni_w_m2 = out->dhi_w_m2 = 0.0;
	double cz = cos(zenith_deg * CS_PI / 180.0), tl = linke_turbidity, m = air_mass_abs;
	if (!(cz > 0.0) || !(m > 0.0) || !(tl > 0.0) || !(dni_extra_w_m2 > 0.0))
		return;
	double fh1 = exp(-altitude_m / 8000.0), fh2 = exp(-altitude_m / 1250.0);
	double cg1 = 5.09e-5 * altitude_m + 0.868, cg2 = 3.92e-5 * altitude_m + 0.0387;
	double ghi = cg1 * dni_extra_w_m2 * cz * exp(-cg2 * m * (fh1 + fh2 * (tl - 1.0))) *
		     (perez_enhancement ? exp(0.01 * pow(m, 1.8)) : 1.0);
	double b = 0.664 + 0.163 / fh1;
	double dni = dni_extra_w_m2 * b * exp(-0.09 * m * (tl - 1.0));
	/* the model's own bound on the beam (its eq. for the diffuse share) */
	double cap = ghi * (1.0 - (0.1 - 0.2 * exp(-tl)) / (0.1 + 0.882 / fh1)) / cz;
	dni = dni < cap ? dni : cap > 0.0 ? cap : 0.0;
	out->ghi_w_m2 = ghi;
	out->dni_w_m2 = dni;
	out->dhi_w_m2 = ghi - dni * cz;
}

double cs_linke_turbidity(double aod550, double water_cm, double altitude_m)
{
	double pc = 1.0 / pressure_ratio(altitude_m);
	double w = water_cm > 0.01 ? water_cm : 0.01;
	return 3.91 * exp(0.689 * pc) * (aod550 > 0.0 ? aod550 : 0.0) + 0.376 * log(w) + 2.0 +
	       0.54 * pc - 0.5 * pc * pc + 0.16 * pc * pc * pc;
}

double cs_clear_sky_dome_scale(cs_v3 sun_dir, double sky_turbidity, double beam_turbidity,
			       double aod550, double altitude_m, double dni_extra_w_m2)
{
	cs_v3 d = cs_sky_raise(v3_norm(sun_dir), CS_CLEAR_SKY_MIN_ELEVATION_DEG * CS_PI / 180.0);
	double el = asin(d.z < -1.0 ? -1.0 : d.z > 1.0 ? 1.0 : d.z);
	struct cs_sky sky;
	cs_sky_init_beam(&sky, d, sky_turbidity, beam_turbidity);
	double dome_klux = CS_PI * cs_luminance(sky.ambient_up[0], sky.ambient_up[1], sky.ambient_up[2]);
	struct cs_irradiance cl;
	cs_clear_sky_ineichen(90.0 - el * 180.0 / CS_PI, cs_relative_air_mass(el) * pressure_ratio(altitude_m),
			      cs_linke_turbidity(aod550, CS_STANDARD_WATER_CM, altitude_m), altitude_m,
			      dni_extra_w_m2, 1, &cl);
	double want_klux = cl.dhi_w_m2 * cs_diffuse_efficacy_lm_w(1.0) / 1000.0;
	return dome_klux > 0.0 && want_klux > 0.0 ? want_klux / dome_klux : 1.0;
}

/* The direction over p's sky at (u, v) in [0, 1)^2, cosine-weighted (sin^2
 * of the zenith angle u, the azimuth 2 pi v from east), and 1 deg off the
 * sun where it falls within 0.5 deg of it: out of its disc, whose light is
 * the beam's (DNI). */
static cs_v3 dome_dir(const struct cs_scene *sc, cs_v3 p, double u, double v)
{
	cs_v3 up = v3_norm(v3(p.x, p.y, p.z + sc->earth_radius_m));
	cs_v3 e = v3_cross(v3(0.0, 1.0, 0.0), up);
	e = v3_len(e) > 1e-9 ? v3_norm(e) : v3(1.0, 0.0, 0.0);
	cs_v3 n = v3_cross(up, e);
	double sin_t = sqrt(u), cos_t = sqrt(1.0 - sin_t * sin_t), phi = v * 2.0 * CS_PI;
	cs_v3 d = v3_add(v3_scale(up, cos_t),
			 v3_add(v3_scale(e, sin_t * cos(phi)), v3_scale(n, sin_t * sin(phi))));
	if (v3_dot(d, sc->sun_dir) > cos(0.5 * CS_PI / 180.0)) {
		cs_v3 a = v3_sub(d, v3_scale(sc->sun_dir, v3_dot(d, sc->sun_dir)));
		a = v3_len(a) > 1e-9 ? v3_norm(a) : e;
		double r1 = CS_PI / 180.0;
		d = v3_norm(v3_add(v3_scale(sc->sun_dir, cos(r1)), v3_scale(a, sin(r1))));
	}
	return d;
}

void cs_irradiance_at(const struct cs_scene *sc, const struct cs_render_settings *s,
		      cs_v3 p, struct cs_irradiance *out, struct cs_render_stats *st)
{
	cs_v3 up = v3_norm(v3(p.x, p.y, p.z + sc->earth_radius_m));
	double mu0 = v3_dot(sc->sun_dir, up);
	double dni_klux = 0.0;
	/* the beam through the clouds and through the fog above p */
	if ((sc->effects & CS_FX_KEY) && mu0 > 0.0)
		dni_klux = cs_luminance(sc->sun_illuminance[0], sc->sun_illuminance[1], sc->sun_illuminance[2]) *
			   cs_render_sun_transmittance(sc, s, p, st) *
			   cs_fog_sun_transmittance(sc, cs_scene_altitude(sc, p));
	/* cosine-weighted stratified directions: E = pi x their mean radiance */
	double sum = 0.0;
	for (int i = 0; i < N_THETA; i++)
		for (int j = 0; j < N_PHI; j++) {
			struct cs_ray_result r;
			cs_render_ray(sc, s, p, dome_dir(sc, p, (i + 0.5) / N_THETA, (j + 0.5) / N_PHI), 0.5,
				      st, &r);
			sum += cs_luminance(r.rgb[0], r.rgb[1], r.rgb[2]);
		}
	cs_irradiance_from_klux(sc, p, dni_klux, CS_PI * sum / (N_THETA * N_PHI), out);
}

void cs_irradiance_from_klux(const struct cs_scene *sc, cs_v3 p, double dni_klux,
			     double dhi_klux, struct cs_irradiance *out)
{
	cs_v3 up = v3_norm(v3(p.x, p.y, p.z + sc->earth_radius_m));
	double mu0 = v3_dot(sc->sun_dir, up);
	double el = asin(mu0 < -1.0 ? -1.0 : mu0 > 1.0 ? 1.0 : mu0) * 180.0 / CS_PI;
	/* the share of clear sky: the beam's area mean through the clouds,
	 * taken vertically (a low sun would count thin cloud as overcast) */
	double clear = sc->deck.on && sc->deck.mu0 > 0.0 ? pow(sc->deck.direct_below, sc->deck.mu0)
							  : sc->deck.on ? 0.0 : 1.0;
	out->dni_w_m2 = dni_klux * 1000.0 / cs_beam_efficacy_lm_w(el);
	out->dhi_w_m2 = dhi_klux * 1000.0 / cs_diffuse_efficacy_lm_w(clear);
	out->ghi_w_m2 = out->dni_w_m2 * (mu0 > 0.0 ? mu0 : 0.0) + out->dhi_w_m2;
}

/* 2 m above the ground at (x, y): the terrain where it is, else the flat
 * ground, on the sphere */
static cs_v3 above_ground(const struct cs_scene *sc, double x, double y)
{
	double R = sc->earth_radius_m, h = sc->ground_alt_m, th;
	if (sc->terrain && cs_hfield_height(sc->terrain, x, y, &th))
		h = th;
	h += 2.0;
	return v3(x, y, sqrt((R + h) * (R + h) - x * x - y * y) - R);
}

/* The altitude the ground's dome and the field's top plane see the sky
 * from: 2 m above the flat ground, or where it rains or snows 1 m under
 * the precipitation's top (the raining layer's base) or under the lowest
 * layer's base if that is lower (the capture's rain hour has cumulus from
 * 650 m under its nimbostratus at 834 m): the light at the top of the
 * rain's column, which cs_rain_column takes there (under the dome the
 * ground takes what comes down through the column).  From the ground,
 * the rays seeing no rain, the bright gaps of a broken deck low around
 * the sky lit the rain under its thick cells as if nothing were in the
 * way: 8 mm/h under the capture's rain hour's nimbostratus alone, +92 %
 * against the path tracer at high, +64 % from under the base. */
static double sky_alt_m(const struct cs_scene *sc)
{
	if (!CS_FX_IS(sc, CS_FX_RAIN | CS_FX_SNOW))
		return sc->ground_alt_m + 2.0;
	double top = sc->rain_top_m;
	for (int i = 0; i < sc->nlayers; i++)
		if (sc->layers[i].site < 0 && sc->layers[i].base_m > sc->ground_alt_m + 3.0)
			top = fmin(top, sc->layers[i].base_m);
	return fmax(top - 1.0, sc->ground_alt_m + 2.0);
}

/* The point at altitude alt_m over (x, y), on the sphere. */
static cs_v3 sky_point(const struct cs_scene *sc, double alt_m, double x, double y)
{
	double R = sc->earth_radius_m;
	return v3(x, y, sqrt((R + alt_m) * (R + alt_m) - x * x - y * y) - R);
}

cs_v3 cs_irradiance_area_point(const struct cs_scene *sc, double size_m, int n, int i, int j)
{
	return above_ground(sc, ((i + 0.5) / n - 0.5) * size_m, ((j + 0.5) / n - 0.5) * size_m);
}

void cs_irradiance_area(const struct cs_scene *sc, const struct cs_render_settings *s,
			double size_m, int n, struct cs_irradiance *out,
			struct cs_render_stats *st)
{
	struct cs_irradiance sum = {0.0, 0.0, 0.0};
	for (int j = 0; j < n; j++)
		for (int i = 0; i < n; i++) {
			struct cs_irradiance one;
			cs_irradiance_at(sc, s, cs_irradiance_area_point(sc, size_m, n, i, j), &one, st);
			sum.ghi_w_m2 += one.ghi_w_m2;
			sum.dni_w_m2 += one.dni_w_m2;
			sum.dhi_w_m2 += one.dhi_w_m2;
		}
	out->ghi_w_m2 = sum.ghi_w_m2 / (n * n);
	out->dni_w_m2 = sum.dni_w_m2 / (n * n);
	out->dhi_w_m2 = sum.dhi_w_m2 / (n * n);
}

/* The sum of the radiance of m x m rays over p's sky in strata, their
 * offsets in the strata turned from point to point by the point's index k
 * (the R2 sequence, Roberts 2018) so that a grid's rays fill the
 * hemisphere between the strata's corners. */
static void sky_rays(const struct cs_scene *sc, const struct cs_render_settings *s, cs_v3 p,
		     int k, int m, struct cs_render_stats *st, double sum[3])
{
	double ou = fmod(0.5 + k * 0.7548776662466927, 1.0);
	double ov = fmod(0.5 + k * 0.5698402909980532, 1.0);
	for (int a = 0; a < m; a++)
		for (int b = 0; b < m; b++) {
			struct cs_ray_result r;
			cs_render_ray(sc, s, p, dome_dir(sc, p, (a + ou) / m, (b + ov) / m), 0.5, st, &r);
			for (int c = 0; c < 3; c++)
				sum[c] += r.rgb[c];
		}
}

struct dome_job {
	const struct cs_scene *sc;
	const struct cs_render_settings *s;
	double (*row)[3]; /* each row's sum of radiance */
	double alt_m;     /* the points' altitude (sky_alt_m) */
};

/* Row j of the dome's points, 2 x 2 rays each. */
static void dome_row(void *user, int j, int worker)
{
	(void)worker;
	const struct dome_job *job = user;
	const int n = CS_GROUND_DOME_POINTS;
	struct cs_render_stats st = {0};
	double sum[3] = {0.0, 0.0, 0.0};
	for (int i = 0; i < n; i++)
		sky_rays(job->sc, job->s,
			 sky_point(job->sc, job->alt_m, ((i + 0.5) / n - 0.5) * CS_DECK_AREA_M,
				   ((j + 0.5) / n - 0.5) * CS_DECK_AREA_M),
			 j * n + i, 2, &st, sum);
	for (int c = 0; c < 3; c++)
		job->row[j][c] = sum[c];
}

/* The scene whose sky lights the ground: the open sky over flat ground,
 * the terrain's own horizon being its ambient occlusion's
 * (cs_ground_light), no star's disc, and no rain or snow: the light
 * under the clouds, which lights the top of the precipitation's column
 * (the field's top plane; the dome's, which cs_rain_column takes down to
 * the ground).  NULL: out of memory. */
static struct cs_scene *open_sky(const struct cs_scene *sc)
{
	struct cs_scene *flat = malloc(sizeof *flat);
	if (flat == NULL)
		return NULL;
	*flat = *sc;
	flat->terrain = NULL;
	flat->effects &= ~(unsigned)(CS_FX_TERRAIN | CS_FX_WATER | CS_FX_STARS | CS_FX_RAIN |
				     CS_FX_SNOW);
	return flat;
}

int cs_ground_sky_dome(const struct cs_scene *sc, const struct cs_render_settings *s, int nthreads,
		       double rgb[3])
{
	enum { N = CS_GROUND_DOME_POINTS };
	_Static_assert(CS_GROUND_DOME_RAYS == 4, "dome_row's 2 x 2 strata");
	double row[N][3];
	struct cs_scene *flat = open_sky(sc);
	if (flat == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	struct dome_job job = {flat, s, row, sky_alt_m(sc)};
	int rc = cs_pool_run(N, nthreads, dome_row, &job, NULL, NULL, NULL);
	free(flat);
	if (rc != CS_OK)
		return rc;
	double sum[3] = {0.0, 0.0, 0.0};
	for (int j = 0; j < N; j++)
		for (int c = 0; c < 3; c++)
			sum[c] += row[j][c];
	for (int c = 0; c < 3; c++)
		rgb[c] = sum[c] / ((double)N * N * CS_GROUND_DOME_RAYS);
	return CS_OK;
}

/* The most rays a point of the ground's field takes (the camera's own
 * ground in a frame that sees little else) and the fewest. */
#define FIELD_RAYS_MAX 4096
#define FIELD_RAYS_MIN 1
/* The scale of the fall of a sky-only frame's rays with the distance
 * from the camera. */
#define FIELD_AIR_RADIUS_M 3000.0

struct field_job {
	const struct cs_scene *sc;
	const struct cs_render_settings *s;
	const struct cs_ground_field *f;
	double *acc; /* 4 a point: its rays' sum of radiance, then their count */
	double alt_m; /* the points' altitude (sky_alt_m) */
};

static void field_row(void *user, int j, int worker)
{
	(void)worker;
	const struct field_job *job = user;
	const struct cs_ground_field *f = job->f;
	struct cs_render_stats st = {0};
	for (int i = 0; i < f->n; i++) {
		size_t at = (size_t)j * f->n + i;
		double *o = job->acc + 4 * at;
		o[0] = o[1] = o[2] = 0.0;
		cs_v3 p = sky_point(job->sc, job->alt_m, f->x0_m + i * f->step_m,
				    f->y0_m + j * f->step_m);
		sky_rays(job->sc, job->s, p, (int)at, (int)sqrt(o[3]), &st, o);
	}
}

/* [1 2 1] / 4 along one axis of an n x n grid of k values a point, the
 * edge's value repeated beyond it. */
static void blur121(const double *in, double *out, int n, int k, int along_rows)
{
	for (int j = 0; j < n; j++)
		for (int i = 0; i < n; i++) {
			int a = along_rows ? i : j;
			size_t at = (size_t)j * n + i, step = along_rows ? 1 : (size_t)n;
			size_t lo = a > 0 ? at - step : at, hi = a < n - 1 ? at + step : at;
			for (int c = 0; c < k; c++)
				out[k * at + c] = 0.25 * in[k * lo + c] + 0.5 * in[k * at + c] +
						  0.25 * in[k * hi + c];
		}
}

/* Each point's share of the frame's ground: the camera's rays through
 * every 4th pixel each way that meet the ground on the grid, each to its
 * four points by the bilinear weights the ground's lookup takes. */
static void ground_seen(const struct cs_scene *sc, const struct cs_camera *cam,
			const struct cs_ground_field *f, double *share)
{
	struct cs_render_stats st = {0};
	for (int j = 2; j < cam->height; j += 4)
		for (int i = 2; i < cam->width; i += 4) {
			cs_v3 d;
			int on_terrain;
			if (!cs_camera_ray(cam, i, j, &d))
				continue;
			double t = cs_find_ground(sc, cam->pos, d, &on_terrain, &st);
			if (!isfinite(t))
				continue;
			cs_v3 p = v3_mad(cam->pos, d, t);
			double u = (p.x - f->x0_m) / f->step_m, v = (p.y - f->y0_m) / f->step_m;
			if (!(u >= 0.0 && v >= 0.0 && u <= f->n - 1 && v <= f->n - 1))
				continue;
			int a = (int)u < f->n - 2 ? (int)u : f->n - 2, b = (int)v < f->n - 2 ? (int)v : f->n - 2;
			double x = u - a, y = v - b;
			size_t at = (size_t)b * f->n + a;
			share[at] += (1.0 - x) * (1.0 - y);
			share[at + 1] += x * (1.0 - y);
			share[at + f->n] += (1.0 - x) * y;
			share[at + f->n + 1] += x * y;
		}
}

/* The field's points, at altitude alt_m, traced with rays[k] rays each (a
 * square; NULL: FIELD_RAYS_MIN), their area mean into f->mean, and each
 * point's blurred mean into rgb; acc and tmp are scratch, 4 doubles a
 * point. */
static int field_pass(const struct cs_scene *flat, const struct cs_render_settings *s,
		      struct cs_ground_field *f, double alt_m, const double *rays, int nthreads,
		      double *acc, double *tmp, float *rgb)
{
	size_t points = (size_t)f->n * f->n;
	for (size_t k = 0; k < points; k++)
		acc[4 * k + 3] = rays != NULL ? rays[k] : FIELD_RAYS_MIN;
	struct field_job job = {flat, s, f, acc, alt_m};
	int rc = cs_pool_run(f->n, nthreads, field_row, &job, NULL, NULL, NULL);
	if (rc != CS_OK)
		return rc;
	/* the area's mean: of the points' own means */
	double mean[3] = {0.0, 0.0, 0.0};
	for (size_t k = 0; k < points; k++)
		for (int c = 0; c < 3; c++)
			mean[c] += acc[4 * k + c] / acc[4 * k + 3];
	for (int c = 0; c < 3; c++)
		f->mean[c] = mean[c] / (double)points;
	/* each point the mean of its rays and its neighbours', every ray of
	 * the same weight in the blur (the sums and the counts blurred
	 * alike): a point of many rays keeps its own */
	blur121(acc, tmp, f->n, 4, 1);
	blur121(tmp, acc, f->n, 4, 0);
	for (size_t k = 0; k < points; k++)
		for (int c = 0; c < 3; c++)
			rgb[3 * k + c] = (float)(acc[4 * k + c] / acc[4 * k + 3]);
	return CS_OK;
}

int cs_ground_sky_field(const struct cs_scene *sc, const struct cs_render_settings *s,
			const struct cs_camera *cam, int nthreads, struct cs_ground_field *out)
{
	*out = (struct cs_ground_field){0};
	const int n = CS_GROUND_FIELD_POINTS;
	const double side = CS_DECK_AREA_M;
	/* the points on a lattice of the world, the square's middle the point
	 * nearest the camera: a camera that moves from frame to frame keeps
	 * the points where they were, and their light */
	const double step = side / n;
	struct cs_ground_field f = {
		.n = n, .planes = 1, .step_m = step,
		.x0_m = (floor(cam->pos.x / step + 0.5) - n / 2) * step,
		.y0_m = (floor(cam->pos.y / step + 0.5) - n / 2) * step,
		.fade_m = side / 8.0,
	};
	/* under rain or snow two planes, traced in turn: the top plane, the
	 * light at the precipitation's top (its rays see none of it), then
	 * the ground plane, its rays from 2 m above the ground through the
	 * precipitation, lit by the top plane.  The ground under a broken
	 * deck sees the bright gaps low around its sky through the rain,
	 * which from under the base it does not, and what came down the
	 * column from there was all it took: the study's rain-deck-below at
	 * high, its ground -40 -> -25 % against the path tracer (with the
	 * rain's light, march_rain), the picture -18.3 -> -9.1 %; under black
	 * heaps in 4 mm/h without the sun (test_ground_sky), 0.44 -> 0.085
	 * rms off the path tracer's diffuse irradiance point by point.  A
	 * pass more: the capture's rain hour at 640x360 and medium on 2
	 * threads 1.26 -> 1.40 s. */
	int wet = CS_FX_IS(sc, CS_FX_RAIN | CS_FX_SNOW);
	size_t points = (size_t)n * n, planes = wet ? 2 : 1;
	double *count = malloc(points * sizeof *count);
	double *acc = malloc(points * 4 * sizeof *acc), *tmp = malloc(points * 4 * sizeof *tmp);
	float *rgb = malloc(planes * points * 3 * sizeof *rgb), *first = NULL;
	float *top = rgb == NULL ? NULL : rgb + (planes - 1) * points * 3;
	struct cs_scene *flat = open_sky(sc), *rain = NULL;
	/* the haze under the clouds is lit by the field (cs_ground_sky), and
	 * the field's rays see it: a first pass of one ray a point lights it
	 * for the (top) plane's pass (traced with the area's mean alone, the
	 * haze over the camera under a thick part of a broken deck added half
	 * of the light); the ground plane's haze takes the top plane's */
	int again = flat != NULL && cs_scene_air_lit(flat);
	if (again)
		first = malloc(points * 3 * sizeof *first);
	if (wet && flat != NULL && (rain = malloc(sizeof *rain)) != NULL) {
		*rain = *flat;
		rain->effects |= sc->effects & (CS_FX_RAIN | CS_FX_SNOW);
	}
	if (count == NULL || acc == NULL || tmp == NULL || rgb == NULL || flat == NULL ||
	    (again && first == NULL) || (wet && rain == NULL)) {
		free(count);
		free(acc);
		free(tmp);
		free(rgb);
		free(first);
		free(flat);
		free(rain);
		return cs_error(CS_ENOMEM, "out of memory for the ground's light (%d x %d points)", n, n);
	}
	int rc = CS_OK;
	flat->ground_field = (struct cs_ground_field){0};
	if (again) {
		rc = field_pass(flat, s, &f, sky_alt_m(sc), NULL, nthreads, acc, tmp, first);
		flat->ground_field = f;
		flat->ground_field.rgb = first;
	}
	/* rays where the frame sees the ground: the error of the ground's
	 * mean is least for a point's rays in proportion to its share */
	double total = 0.0;
	for (size_t k = 0; k < points; k++)
		count[k] = 0.0;
	ground_seen(sc, cam, &f, count);
	for (size_t k = 0; k < points; k++)
		total += count[k];
	/* a frame that sees no ground traces the field for its haze and rain
	 * (cs_frame_scene): the rays to the points around the camera, over
	 * whose ground the haze and the rain in its view are nearest: views
	 * of the capture's rain hour 30 deg up at high, 96x54, against a
	 * field of 256 rays a point, -0.75 and -1.06 % in the mean, 0.8 and
	 * 1.1 % off a pixel on average (one ray a point, the review's
	 * measure: -1.1 and -3.4 % in the mean, up to 9.5 % a pixel) */
	if (total == 0.0) {
		for (size_t k = 0; k < points; k++) {
			double dx = f.x0_m + (double)(k % (size_t)n) * step - cam->pos.x;
			double dy = f.y0_m + (double)(k / (size_t)n) * step - cam->pos.y;
			count[k] = exp(-(dx * dx + dy * dy) / (FIELD_AIR_RADIUS_M * FIELD_AIR_RADIUS_M));
			total += count[k];
		}
	}
	for (size_t k = 0; k < points; k++) {
		double want = FIELD_RAYS_MIN +
			      (total > 0.0 ? CS_GROUND_FIELD_RAYS * count[k] / total : 0.0);
		int m = (int)sqrt(want < FIELD_RAYS_MAX ? want : FIELD_RAYS_MAX);
		count[k] = m * m;
	}
	if (rc == CS_OK)
		rc = field_pass(flat, s, &f, sky_alt_m(sc), count, nthreads, acc, tmp, top);
	if (rc == CS_OK && wet) {
		/* the ground's plane, its rays' rain lit by the top's */
		struct cs_ground_field g = f;
		rain->ground_field = f;
		rain->ground_field.rgb = top;
		rc = field_pass(rain, s, &g, sc->ground_alt_m + 2.0, count, nthreads, acc, tmp, rgb);
		for (int c = 0; c < 3; c++) {
			f.top_mean[c] = f.mean[c];
			f.mean[c] = g.mean[c];
		}
		f.planes = 2;
	}
	free(count);
	free(flat);
	free(rain);
	free(first);
	free(acc);
	free(tmp);
	if (rc != CS_OK) {
		free(rgb);
		return rc;
	}
	f.rgb = rgb;
	*out = f;
	return CS_OK;
}
