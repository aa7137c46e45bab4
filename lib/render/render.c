#include "render/render.h"

#include "core/err.h"
#include "core/hash.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static const struct {
	const char *name;
	struct cs_render_settings s;
} presets[] = {
	{"low", {24, 96, 4, 2, 1, 1.0, 0, 0.02}},
	{"medium", {48, 192, 6, 3, 1, 1.0, 0, 0.01}},
	{"high", {96, 384, 8, 3, 1, 1.0, 0, 0.005}},
	{"reference", {384, 1536, 24, 4, 1, 1.0, 0, 0.0005}},
};

int cs_render_quality(const char *name, struct cs_render_settings *s)
{
	for (size_t i = 0; i < sizeof presets / sizeof presets[0]; i++)
		if (strcmp(name, presets[i].name) == 0) {
			*s = presets[i].s;
			return CS_OK;
		}
	return cs_error(CS_EINVAL, "unknown quality '%s' (expected low, medium, high or reference)",
			name);
}

int cs_render_settings_check(const struct cs_render_settings *s)
{
	if (s->steps < 1 || s->steps > 100000)
		return cs_error(CS_EINVAL, "steps must be 1..100000, not %d", s->steps);
	if (s->max_steps < s->steps || s->max_steps > 1000000)
		return cs_error(CS_EINVAL, "max steps must be steps..1000000, not %d",
				s->max_steps);
	if (s->light_steps < 1 || s->light_steps > 10000)
		return cs_error(CS_EINVAL, "light steps must be 1..10000, not %d",
				s->light_steps);
	if (s->ms_octaves < 1 || s->ms_octaves > 4)
		return cs_error(CS_EINVAL, "multiple-scattering octaves must be 1..4");
	if (!(s->jitter >= 0.0 && s->jitter <= 1.0))
		return cs_error(CS_EINVAL, "jitter must be 0..1");
	if (!(s->min_transmittance >= 0.0 && s->min_transmittance < 1.0))
		return cs_error(CS_EINVAL, "minimum transmittance must be in [0, 1)");
	return CS_OK;
}

double cs_phase_hg(double cos_theta, double g)
{
	double denom = 1.0 + g * g - 2.0 * g * cos_theta;
	denom = denom > 1e-12 ? denom : 1e-12;
	return (1.0 - g * g) / (4.0 * CS_PI * denom * sqrt(denom));
}

double cs_scene_altitude(const struct cs_scene *sc, cs_v3 p)
{
	cs_v3 q = v3(p.x, p.y, p.z + sc->earth_radius_m);
	return v3_len(q) - sc->earth_radius_m;
}

/* Ray against the sphere of radius r about the Earth's centre: the entry
 * and exit distances (t0 <= t1), or 0 if the line misses it.  Written to
 * avoid cancellation: c = (|oc| - r)(|oc| + r), and the smaller root from
 * the larger one (q) by Vieta. */
static int sphere_hit(const struct cs_scene *sc, cs_v3 o, cs_v3 d, double r,
		      double *t0, double *t1)
{
	cs_v3 oc = v3(o.x, o.y, o.z + sc->earth_radius_m);
	double dist = v3_len(oc);
	double b = v3_dot(oc, d);
	double c = (dist - r) * (dist + r);
	double disc = b * b - c;
	if (!(disc >= 0.0))
		return 0;
	double sq = sqrt(disc);
	double q = -b - (b >= 0.0 ? sq : -sq);
	double a0 = q, a1 = q != 0.0 ? c / q : 0.0;
	*t0 = a0 < a1 ? a0 : a1;
	*t1 = a0 < a1 ? a1 : a0;
	return 1;
}

/* The parts of [0, tmax] inside the shell r_in < |p - centre| < r_out. */
static int shell_intervals(const struct cs_scene *sc, cs_v3 o, cs_v3 d,
			   double r_in, double r_out, double tmax, double iv[2][2])
{
	double a0, a1, b0, b1;
	if (!sphere_hit(sc, o, d, r_out, &a0, &a1))
		return 0;
	a0 = a0 > 0.0 ? a0 : 0.0;
	a1 = a1 < tmax ? a1 : tmax;
	if (!(a1 > a0))
		return 0;
	if (!sphere_hit(sc, o, d, r_in, &b0, &b1) || b1 <= a0 || b0 >= a1) {
		iv[0][0] = a0, iv[0][1] = a1;
		return 1;
	}
	int n = 0;
	if (b0 > a0)
		iv[n][0] = a0, iv[n][1] = b0, n++;
	if (b1 < a1)
		iv[n][0] = b1, iv[n][1] = a1, n++;
	return n;
}

static double extinction_at(const struct cs_scene *sc, unsigned mask, cs_v3 p,
			    double alt)
{
	double sigma = 0.0;
	for (int i = 0; i < sc->nlayers; i++)
		if (mask & (1u << i))
			sigma += cs_cloud_extinction(&sc->layers[i], sc->noise, p.x,
						     p.y, alt);
	return sigma;
}

/* Optical depth from p toward the sun through every layer: light_steps
 * midpoint samples over each part of the path in a layer of mask (the
 * layers the sample is in), a third as many, at least 2, in the others
 * (cirrus shading the cumulus below it).  A path through one layer is
 * capped at 20 km: beyond that a cloud is either opaque long before or too
 * thin to matter. */
static double light_depth(const struct cs_scene *sc,
			  const struct cs_render_settings *s, cs_v3 p,
			  unsigned mask, struct cs_render_stats *st)
{
	double tau = 0.0;
	int others = s->light_steps / 3 > 2 ? s->light_steps / 3 : 2;
	for (int i = 0; i < sc->nlayers; i++) {
		const struct cs_cloud_layer *l = &sc->layers[i];
		int steps = (mask & (1u << i)) ? s->light_steps : others;
		double iv[2][2];
		int n = shell_intervals(sc, p, sc->sun_dir,
					sc->earth_radius_m + l->base_m,
					sc->earth_radius_m + l->top_m, 20000.0, iv);
		for (int k = 0; k < n; k++) {
			double len = iv[k][1] - iv[k][0];
			double dt = len / steps;
			for (int j = 0; j < steps; j++) {
				cs_v3 q = v3_mad(p, sc->sun_dir, iv[k][0] + (j + 0.5) * dt);
				tau += cs_cloud_extinction(l, sc->noise, q.x, q.y,
							   cs_scene_altitude(sc, q)) * dt;
			}
			st->light_samples += (uint64_t)steps;
		}
	}
	return tau;
}

struct interval {
	double t0, t1;
	unsigned mask; /* layers; 0 = the rain shaft */
};

/* The light the haze scatters toward the eye along d: the sky's radiance at
 * the same azimuth and the same angle from the horizon, looking up (for a
 * plane-parallel haze layer the path looking down at an angle sees what the
 * path looking up at it sees), at least 1 degree up. */
static void haze_light(const struct cs_scene *sc, cs_v3 d, double rgb[3])
{
	if (!(sc->effects & CS_FX_SKY)) {
		rgb[0] = rgb[1] = rgb[2] = 0.0;
		return;
	}
	double up = fabs(d.z) > 0.0175 ? fabs(d.z) : 0.0175;
	double flat = sqrt(d.x * d.x + d.y * d.y);
	double dir[3] = {1.0, 0.0, 0.0};
	if (flat > 1e-9) {
		double k = sqrt(1.0 - up * up) / flat;
		dir[0] = d.x * k, dir[1] = d.y * k;
	} else {
		dir[0] = sqrt(1.0 - up * up);
	}
	dir[2] = up;
	cs_sky_radiance(&sc->sky, dir, rgb);
}

/* Haze optical depth along a straight ray leaving altitude h0 with vertical
 * direction component dz over distance t, for an aerosol extinction
 * decreasing exponentially with height (flat-Earth approximation). */
static double haze_depth(const struct cs_scene *sc, double h0, double dz, double t)
{
	double H = sc->haze_scale_height_m, b = sc->haze_beta0_per_m * exp(-h0 / H);
	if (fabs(dz) * t < 1e-3 * H)
		return b * t;
	double x = -dz * t / H;
	x = x > 50.0 ? 50.0 : x; /* going down a very long way: capped, finite */
	return b * H * -expm1(x) / dz;
}

double cs_render_sun_transmittance(const struct cs_scene *sc,
				   const struct cs_render_settings *s, cs_v3 p,
				   struct cs_render_stats *st)
{
	if (!(sc->effects & CS_FX_SUN) || sc->nlayers == 0)
		return 1.0;
	return exp(-light_depth(sc, s, p, (1u << sc->nlayers) - 1u, st));
}

/* Soft shadow of the terrain on itself toward the sun: the smallest ratio
 * of clearance to distance along the way (a penumbra cone of about 1/8
 * radian), 0 when the path is blocked. */
static double terrain_shadow(const struct cs_hfield *f, cs_v3 p, cs_v3 sun)
{
	double res = 1.0, t = 2.0;
	for (int k = 0; k < 48 && t < 20000.0; k++) {
		cs_v3 q = v3_mad(p, sun, t);
		double alt = cs_hfield_altitude(f, q), h;
		if (alt > f->max_m || !cs_hfield_height(f, q.x, q.y, &h))
			break;
		double gap = alt - h;
		if (gap <= 0.0)
			return 0.0;
		double r = 8.0 * gap / t;
		res = r < res ? r : res;
		t += gap * 0.5 < 2.0 ? 2.0 : gap * 0.5 > 400.0 ? 400.0 : gap * 0.5;
	}
	return res;
}

/* Ambient occlusion from the terrain's horizon: the mean over 8 directions
 * of the sine of the highest elevation seen within 600 m. */
static double terrain_ao(const struct cs_hfield *f, cs_v3 p, double h0)
{
	static const double dist[3] = {40.0, 150.0, 600.0};
	double occ = 0.0;
	for (int k = 0; k < 8; k++) {
		double a = k * (CS_PI / 4.0), best = 0.0;
		for (int i = 0; i < 3; i++) {
			double h;
			cs_hfield_height(f, p.x + dist[i] * cos(a), p.y + dist[i] * sin(a), &h);
			double s = (h - h0) / sqrt((h - h0) * (h - h0) + dist[i] * dist[i]);
			best = s > best ? s : best;
		}
		occ += best;
	}
	return 1.0 - occ / 8.0;
}

static double srgb_to_linear(double c)
{
	return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

/* Ground colour of the terrain: from the colour image when there is one,
 * else grass, rock on steep slopes and snow high up. */
static void terrain_albedo(const struct cs_scene *sc, double x, double y,
			   double h, cs_v3 n, double alb[3])
{
	const struct cs_hfield *f = sc->terrain;
	if (sc->terrain_color) {
		double col = f->a[0] + f->a[1] * x + f->a[2] * y;
		double row = f->b[0] + f->b[1] * x + f->b[2] * y;
		int i = (int)(col / (f->w - 1) * (sc->terrain_color_w - 1) + 0.5);
		int j = (int)(row / (f->h - 1) * (sc->terrain_color_h - 1) + 0.5);
		i = i < 0 ? 0 : i >= sc->terrain_color_w ? sc->terrain_color_w - 1 : i;
		j = j < 0 ? 0 : j >= sc->terrain_color_h ? sc->terrain_color_h - 1 : j;
		const uint8_t *px = sc->terrain_color + ((size_t)j * sc->terrain_color_w + i) * 3;
		for (int k = 0; k < 3; k++)
			alb[k] = srgb_to_linear(px[k] / 255.0);
		return;
	}
	static const double grass[3] = {0.10, 0.14, 0.06}, rock[3] = {0.22, 0.20, 0.18},
			    snow[3] = {0.80, 0.82, 0.88};
	double steep = n.z < 0.7 ? 1.0 : n.z > 0.85 ? 0.0 : (0.85 - n.z) / 0.15;
	double high = h < 2400.0 ? 0.0 : h > 2900.0 ? 1.0 : (h - 2400.0) / 500.0;
	high *= n.z > 0.6 ? 1.0 : 0.0; /* snow does not stick to cliffs */
	for (int k = 0; k < 3; k++) {
		double g = grass[k] + steep * (rock[k] - grass[k]);
		alb[k] = g + high * (snow[k] - g);
	}
}

static void ground_light(const struct cs_scene *sc,
			 const struct cs_render_settings *s, cs_v3 p,
			 int on_terrain, struct cs_render_stats *st, double rgb[3])
{
	cs_v3 up = v3_norm(v3(p.x, p.y, p.z + sc->earth_radius_m));
	cs_v3 n = up;
	double alb[3] = {sc->ground_albedo[0], sc->ground_albedo[1], sc->ground_albedo[2]};
	double ao = 1.0, self = 1.0;
	if (on_terrain) {
		double h;
		cs_hfield_height(sc->terrain, p.x, p.y, &h);
		n = cs_hfield_normal(sc->terrain, p.x, p.y);
		terrain_albedo(sc, p.x, p.y, h, n, alb);
		ao = terrain_ao(sc->terrain, p, h);
	}
	if (sc->noise && !(on_terrain && sc->terrain_color)) {
		/* fields and woods: the albedo varies over ~1 km and ~150 m, which
		 * also shows the eye how far away the ground is */
		double v = 0.6 * cs_volume_sample(sc->noise, 1, p.x / 4000.0, p.y / 4000.0, 0.3) +
			   0.4 * cs_volume_sample(sc->noise, 3, p.x / 600.0, p.y / 600.0, 0.7);
		double k = 0.4 + 1.2 * v;
		for (int c = 0; c < 3; c++)
			alb[c] *= k;
	}

	double cosi = v3_dot(n, sc->sun_dir);
	double direct = 0.0;
	if ((sc->effects & CS_FX_SUN) && cosi > 0.0) {
		if (on_terrain)
			self = terrain_shadow(sc->terrain, p, sc->sun_dir);
		double T = (sc->effects & CS_FX_CLOUD_SHADOWS) && self > 0.0
				   ? cs_render_sun_transmittance(sc, s, p, st)
				   : 1.0;
		direct = cosi * T * self / CS_PI;
	}
	for (int k = 0; k < 3; k++)
		rgb[k] = alb[k] * (sc->sun_illuminance[k] * direct +
				   ((sc->effects & CS_FX_SKY) ? sc->ambient_up[k] * ao : 0.0));
}

void cs_render_ray(const struct cs_scene *sc, const struct cs_render_settings *s,
		   cs_v3 o, cs_v3 d, double jitter_u, struct cs_render_stats *st,
		   struct cs_ray_result *out)
{
	double L[3] = {0.0, 0.0, 0.0};
	double T = 1.0, Tcloud = 1.0, depth = CS_SKY_DEPTH_M;
	double R = sc->earth_radius_m;

	/* the ground (the terrain, and flat ground around it), or nothing */
	double tg = INFINITY, g0, g1;
	int on_terrain = 0;
	if ((sc->effects & CS_FX_GROUND) &&
	    sphere_hit(sc, o, d, R + sc->ground_alt_m, &g0, &g1) && g1 >= 0.0) {
		tg = g0 > 0.0 ? g0 : 0.0;
		double hh;
		cs_v3 p = v3_mad(o, d, tg);
		if (sc->terrain && cs_hfield_height(sc->terrain, p.x, p.y, &hh))
			tg = INFINITY; /* inside the grid the terrain is the ground */
	}
	if (sc->terrain) {
		double tt;
		unsigned long cells = 0;
		if (cs_hfield_intersect(sc->terrain, o, d, isfinite(tg) ? tg : 1e7, &tt, &cells)) {
			tg = tt;
			on_terrain = 1;
		}
		st->terrain_cells += cells;
	}
	double tmax = isfinite(tg) ? tg : 1e7;

	/* the intervals the ray spends in each layer, and in the rain */
	struct interval iv[2 * CS_SCENE_MAX_LAYERS + 2];
	int n = 0;
	for (int i = 0; i < sc->nlayers; i++) {
		double a[2][2];
		int k = shell_intervals(sc, o, d, R + sc->layers[i].base_m,
					R + sc->layers[i].top_m, tmax, a);
		for (int j = 0; j < k; j++)
			iv[n++] = (struct interval){a[j][0], a[j][1], 1u << i};
	}
	if (sc->effects & CS_FX_RAIN) {
		double a[2][2];
		int k = shell_intervals(sc, o, d, R + sc->ground_alt_m - 1.0,
					R + sc->rain_top_m, tmax, a);
		for (int j = 0; j < k; j++)
			iv[n++] = (struct interval){a[j][0], a[j][1], 0u};
	}
	/* in order along the ray (insertion sort: n is tiny) */
	for (int i = 1; i < n; i++)
		for (int j = i; j > 0 && iv[j].t0 < iv[j - 1].t0; j--) {
			struct interval tmp = iv[j];
			iv[j] = iv[j - 1];
			iv[j - 1] = tmp;
		}

	double cos_theta = v3_dot(d, sc->sun_dir);
	double phase[4];
	for (int k = 0; k < s->ms_octaves; k++) {
		double c = pow(0.5, k); /* octave k: phase eccentricity x 0.5^k */
		phase[k] = sc->w_forward * cs_phase_hg(cos_theta, sc->g_forward * c) +
			   (1.0 - sc->w_forward) * cs_phase_hg(cos_theta, sc->g_back * c);
	}
	int sun = (sc->effects & CS_FX_SUN) != 0;
	int terminated = 0;

	for (int i = 0; i < n && !terminated; i++) {
		double t0 = iv[i].t0, t1 = iv[i].t1;
		/* overlapping cloud layers are marched together */
		unsigned mask = iv[i].mask;
		if (mask == 0) { /* rain: grey, homogeneous, lit by the sky */
			double sig = sc->rain_extinction_per_m, len = t1 - t0;
			double tr = exp(-sig * len);
			for (int k = 0; k < 3; k++)
				L[k] += T * (1.0 - tr) * 0.9 * sc->ambient_up[k];
			T *= tr;
			continue;
		}
		while (i + 1 < n && iv[i + 1].mask != 0 && iv[i + 1].t0 < t1) {
			i++;
			mask |= iv[i].mask;
			t1 = iv[i].t1 > t1 ? iv[i].t1 : t1;
		}
		st->layer_crossings++;
		/* the step: a layer's thickness over the steps, with thick layers
		 * (towering cumulonimbus) sampled as if 2.5 km thick so that
		 * their dense cores are not undersampled; max_steps bounds it */
		double dt0 = INFINITY;
		for (int l = 0; l < sc->nlayers; l++)
			if (mask & (1u << l)) {
				double th = sc->layers[l].top_m - sc->layers[l].base_m;
				th = (th < 2500.0 ? th : 2500.0) / s->steps;
				dt0 = th < dt0 ? th : dt0;
			}
		const struct cs_cloud_layer *amb = NULL; /* for the ambient light */
		for (int l = 0; l < sc->nlayers && amb == NULL; l++)
			if (mask & (1u << l))
				amb = &sc->layers[l];
		double len = t1 - t0;
		double steps = ceil(len / dt0);
		int ns = steps < 1.0 ? 1 : steps > s->max_steps ? s->max_steps : (int)steps;
		double dt = len / ns;
		for (int j = 0; j < ns; j++) {
			double t = t0 + (j + jitter_u) * dt;
			cs_v3 p = v3_mad(o, d, t);
			double alt = cs_scene_altitude(sc, p);
			double sigma = extinction_at(sc, mask, p, alt);
			st->density_samples++;
			if (sigma <= 0.0)
				continue;
			if (depth == CS_SKY_DEPTH_M)
				depth = t0 + j * dt;
			double ss = sc->albedo * sigma; /* scattering coefficient */
			double S[3] = {0.0, 0.0, 0.0};
			if (sun) {
				double tau = light_depth(sc, s, p, mask, st);
				/* multiple-scattering octaves (Wrenninge 2013):
				 * scattering a^k, extinction b^k, eccentricity c^k,
				 * a = b = c = 0.5 */
				double w = 0.0, a = 1.0, b = 1.0;
				for (int k = 0; k < s->ms_octaves; k++) {
					w += a * exp(-b * tau) * phase[k];
					a *= 0.5;
					b *= 0.5;
				}
				for (int k = 0; k < 3; k++)
					S[k] += ss * sc->sun_illuminance[k] * w;
			}
			if (s->ambient) {
				/* isotropic sky light, brighter toward the top of
				 * the (lowest) layer of this crossing */
				double hb = (alt - amb->base_m) / (amb->top_m - amb->base_m);
				hb = hb < 0.0 ? 0.0 : hb > 1.0 ? 1.0 : hb;
				for (int k = 0; k < 3; k++)
					S[k] += ss * (sc->ambient_up[k] * (0.4 + 0.6 * hb) +
						      sc->ambient_down[k] * (1.0 - hb) * 0.5);
			}
			/* Energy-conserving step (Hillaire 2015): the source is
			 * integrated against the transmittance over the step,
			 * S (1 - exp(-sigma dt)) / sigma, not S dt. */
			double tr = exp(-sigma * dt);
			double integ = -expm1(-sigma * dt) / sigma;
			for (int k = 0; k < 3; k++)
				L[k] += T * S[k] * integ;
			T *= tr;
			Tcloud *= tr;
			if (T < s->min_transmittance) {
				terminated = 1;
				break;
			}
		}
	}
	if (terminated)
		st->rays_terminated_early++;

	/* aerial perspective on the clouds, then the background behind them */
	double h0 = cs_scene_altitude(sc, o);
	cs_v3 up = v3_norm(v3(o.x, o.y, o.z + R));
	double dz = v3_dot(d, up);
	double hz[3] = {0.0, 0.0, 0.0};
	int haze = (sc->effects & CS_FX_HAZE) && sc->haze_beta0_per_m > 0.0;
	if (haze)
		haze_light(sc, d, hz);
	if (haze && depth < CS_SKY_DEPTH_M) {
		double th = exp(-haze_depth(sc, h0, dz, depth));
		for (int k = 0; k < 3; k++)
			L[k] = L[k] * th + (1.0 - Tcloud) * (1.0 - th) * hz[k];
	}
	double bg[3] = {0.0, 0.0, 0.0};
	if (!terminated) {
		if (isfinite(tg)) {
			ground_light(sc, s, v3_mad(o, d, tg), on_terrain, st, bg);
			if (haze) {
				double th = exp(-haze_depth(sc, h0, dz, tg));
				for (int k = 0; k < 3; k++)
					bg[k] = bg[k] * th + (1.0 - th) * hz[k];
			}
			if (depth == CS_SKY_DEPTH_M)
				depth = tg;
		} else if (sc->effects & CS_FX_SKY) {
			double dd[3] = {d.x, d.y, d.z}, disk[3];
			cs_sky_radiance(&sc->sky, dd, bg);
			cs_sky_sun_disk(&sc->sky, dd, disk);
			for (int k = 0; k < 3; k++)
				bg[k] += disk[k];
		}
	}
	for (int k = 0; k < 3; k++) {
		double v = L[k] + T * bg[k];
		out->rgb[k] = isfinite(v) && v > 0.0 ? v : 0.0;
	}
	out->transmittance = Tcloud >= 0.0 && Tcloud <= 1.0 ? Tcloud : 0.0;
	out->depth_m = isfinite(depth) ? depth : CS_SKY_DEPTH_M;
}

int cs_camera_init(struct cs_camera *c, const struct cs_scene *sc, cs_v3 pos,
		   double origin_lat_deg, double azimuth_deg, double elevation_deg,
		   double fov_deg, int width, int height)
{
	if (width < 1 || height < 1 || width > 32768 || height > 32768)
		return cs_error(CS_EINVAL, "image size %dx%d out of range 1..32768",
				width, height);
	if (!(fov_deg > 0.0 && fov_deg < 180.0))
		return cs_error(CS_EINVAL, "field of view must be between 0 and 180 degrees");
	if (!(elevation_deg >= -90.0 && elevation_deg <= 90.0) || !isfinite(azimuth_deg))
		return cs_error(CS_EINVAL, "look elevation must be -90..90 degrees");
	double lat0 = origin_lat_deg * CS_PI / 180.0;
	cs_v3 up = v3_norm(v3(pos.x, pos.y, pos.z + sc->earth_radius_m));
	cs_v3 axis = v3(0.0, cos(lat0), sin(lat0)); /* the Earth's axis */
	cs_v3 east = v3_cross(axis, up);
	if (v3_len(east) < 1e-9) /* at a pole: any east will do */
		east = v3(1.0, 0.0, 0.0);
	east = v3_norm(east);
	cs_v3 north = v3_cross(up, east);
	double az = azimuth_deg * CS_PI / 180.0, el = elevation_deg * CS_PI / 180.0;
	cs_v3 horiz = v3_add(v3_scale(east, sin(az)), v3_scale(north, cos(az)));
	c->fwd = v3_norm(v3_add(v3_scale(horiz, cos(el)), v3_scale(up, sin(el))));
	cs_v3 right = v3_cross(c->fwd, up);
	c->right = v3_len(right) > 1e-9 ? v3_norm(right)
					 : v3_norm(v3_cross(c->fwd, north)); /* straight up or down */
	c->up = v3_cross(c->right, c->fwd);
	c->pos = pos;
	c->width = width;
	c->height = height;
	c->tan_half_fov = tan(fov_deg * CS_PI / 360.0);
	return CS_OK;
}

cs_v3 cs_camera_ray(const struct cs_camera *c, int i, int j)
{
	double sx = (2.0 * (i + 0.5) / c->width - 1.0) * c->tan_half_fov;
	double sy = (1.0 - 2.0 * (j + 0.5) / c->height) * c->tan_half_fov *
		    c->height / c->width;
	return v3_norm(v3_add(c->fwd, v3_add(v3_scale(c->right, sx),
					     v3_scale(c->up, sy))));
}

struct render_job {
	const struct cs_scene *sc;
	const struct cs_camera *cam;
	const struct cs_render_settings *s;
	float *out;
	atomic_int next_row, rows_done;
	struct cs_render_stats stats[256];
};

enum { ROWS_PER_TASK = 4 };

struct worker_arg {
	struct render_job *job;
	int index;
};

static void *render_worker(void *arg)
{
	struct worker_arg *wa = arg;
	struct render_job *job = wa->job;
	const struct cs_camera *cam = job->cam;
	struct cs_render_stats *st = &job->stats[wa->index];
	for (;;) {
		int r0 = atomic_fetch_add(&job->next_row, ROWS_PER_TASK);
		if (r0 >= cam->height)
			break;
		int r1 = r0 + ROWS_PER_TASK < cam->height ? r0 + ROWS_PER_TASK : cam->height;
		for (int j = r0; j < r1; j++) {
			for (int i = 0; i < cam->width; i++) {
				double u = 0.5;
				if (job->s->jitter > 0.0) {
					uint32_t h = cs_hash3i(i, j, 0x6a697474, job->s->seed);
					u = 0.5 + job->s->jitter * (cs_hash_unit(h) - 0.5);
				}
				struct cs_ray_result r;
				cs_render_ray(job->sc, job->s, cam->pos, cs_camera_ray(cam, i, j),
					      u, st, &r);
				float *px = job->out + ((size_t)j * cam->width + i) * 5;
				px[0] = (float)r.rgb[0];
				px[1] = (float)r.rgb[1];
				px[2] = (float)r.rgb[2];
				px[3] = (float)(1.0 - r.transmittance);
				px[4] = (float)r.depth_m;
				st->pixels++;
			}
		}
		atomic_fetch_add(&job->rows_done, r1 - r0);
	}
	return NULL;
}

int cs_render_image(const struct cs_scene *sc, const struct cs_camera *cam,
		    const struct cs_render_settings *s, int nthreads,
		    cs_progress_fn progress, void *user, float *out,
		    struct cs_render_stats *stats)
{
	int rc = cs_render_settings_check(s);
	if (rc != CS_OK)
		return rc;
	if (nthreads <= 0) {
		long n = sysconf(_SC_NPROCESSORS_ONLN);
		nthreads = n > 0 ? (int)n : 1;
	}
	nthreads = nthreads > 256 ? 256 : nthreads;
	struct render_job *job = calloc(1, sizeof *job);
	if (job == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	job->sc = sc;
	job->cam = cam;
	job->s = s;
	job->out = out;
	atomic_init(&job->next_row, 0);
	atomic_init(&job->rows_done, 0);
	pthread_t tid[256];
	struct worker_arg args[256];
	int started = 0;
	for (; started < nthreads; started++) {
		args[started] = (struct worker_arg){job, started};
		if (pthread_create(&tid[started], NULL, render_worker, &args[started]) != 0)
			break;
	}
	if (started == 0) {
		args[0] = (struct worker_arg){job, 0};
		render_worker(&args[0]);
	}
	while (progress && started > 0 && atomic_load(&job->rows_done) < cam->height) {
		if (progress)
			progress(user, (double)atomic_load(&job->rows_done) / cam->height);
		struct timespec ts = {0, 20 * 1000 * 1000};
		nanosleep(&ts, NULL);
	}
	for (int i = 0; i < started; i++)
		pthread_join(tid[i], NULL);
	if (progress)
		progress(user, 1.0);
	memset(stats, 0, sizeof *stats);
	for (int i = 0; i < 256; i++) {
		stats->pixels += job->stats[i].pixels;
		stats->density_samples += job->stats[i].density_samples;
		stats->light_samples += job->stats[i].light_samples;
		stats->rays_terminated_early += job->stats[i].rays_terminated_early;
		stats->layer_crossings += job->stats[i].layer_crossings;
		stats->terrain_cells += job->stats[i].terrain_cells;
	}
	free(job);
	return CS_OK;
}
