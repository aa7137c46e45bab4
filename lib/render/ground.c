/* ground.c - the light leaving the ground: flat ground or the terrain's
 * heightfield, lit by the sun (through the clouds: their shadows) and the
 * sky, with the terrain's own soft shadows and horizon occlusion. */
#include "render/march.h"

#include "io/cpt.h"
#include "render/water.h"
#include "terrain/heightfield.h"

#include <math.h>

/* the distances of the horizon search for ambient occlusion */
static CS_CONST const double ao_dist_m[3] = {40.0, 150.0, 600.0};
/* albedos of the made-up land cover where no colour image is given */
static CS_CONST const double grass[3] = {0.10, 0.14, 0.06};
static CS_CONST const double rock[3] = {0.22, 0.20, 0.18};
static CS_CONST const double snow[3] = {0.80, 0.82, 0.88};

/* Soft shadow of the terrain on itself toward the sun: the smallest ratio
 * of clearance to distance along the way (a penumbra cone of about 1/8
 * radian), 0 when the path is blocked. */
CS_HD CS_COLD static double terrain_shadow(const struct cs_hfield *f, cs_v3 p, cs_v3 sun)
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
CS_HD CS_COLD static double terrain_ao(const struct cs_hfield *f, cs_v3 p, double h0)
{
	double occ = 0.0;
	for (int k = 0; k < 8; k++) {
		double a = k * (CS_PI / 4.0), best = 0.0;
		for (int i = 0; i < 3; i++) {
			double h;
			cs_hfield_height(f, p.x + ao_dist_m[i] * cos(a), p.y + ao_dist_m[i] * sin(a), &h);
			double s = (h - h0) / sqrt((h - h0) * (h - h0) + ao_dist_m[i] * ao_dist_m[i]);
			best = s > best ? s : best;
		}
		occ += best;
	}
	return 1.0 - occ / 8.0;
}

CS_HD static double srgb_to_linear(double c)
{
	return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

/* Ground colour of the terrain: from the colour image when there is one,
 * else from the palette (its sRGB colour at the height), else grass, rock
 * on steep slopes and snow high up. */
CS_HD static void terrain_albedo(const struct cs_scene *sc, double x, double y,
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
	if (sc->terrain_cpt) {
		double c[3];
		cs_cpt_color(sc->terrain_cpt, h, c);
		for (int k = 0; k < 3; k++)
			alb[k] = srgb_to_linear(c[k] / 255.0);
		return;
	}
	double steep = n.z < 0.7 ? 1.0 : n.z > 0.85 ? 0.0 : (0.85 - n.z) / 0.15;
	double high = h < 2400.0 ? 0.0 : h > 2900.0 ? 1.0 : (h - 2400.0) / 500.0;
	high *= n.z > 0.6 ? 1.0 : 0.0; /* snow does not stick to cliffs */
	for (int k = 0; k < 3; k++) {
		double g = grass[k] + steep * (rock[k] - grass[k]);
		alb[k] = g + high * (snow[k] - g);
	}
}

/* Whether the terrain sample nearest to world (x, y) is water. */
CS_HD static int water_at(const struct cs_scene *sc, double x, double y)
{
	const struct cs_hfield *f = sc->terrain;
	if (!CS_BUILT(CS_FX_WATER) || sc->terrain_water == NULL)
		return 0;
	double col = f->a[0] + f->a[1] * x + f->a[2] * y;
	double row = f->b[0] + f->b[1] * x + f->b[2] * y;
	int i = (int)floor(col + 0.5), j = (int)floor(row + 0.5);
	if (i < 0 || j < 0 || i >= f->w || j >= f->h)
		return 0;
	return sc->terrain_water[(size_t)j * f->w + i] >= 0.5f;
}

/* Plane k of field f at p (mean: the plane's), bilinear between its
 * points and fading to the mean beyond them. */
CS_HD static void field_at(const struct cs_ground_field *f, int k, const double mean[3], cs_v3 p,
			   double out[3])
{
	double u = (p.x - f->x0_m) / f->step_m, v = (p.y - f->y0_m) / f->step_m, top = f->n - 1;
	double cu = fmin(fmax(u, 0.0), top), cv = fmin(fmax(v, 0.0), top); /* (NaN: 0) */
	double out_m = fmax(fabs(u - cu), fabs(v - cv)) * f->step_m;
	double w = out_m >= f->fade_m ? 1.0 : out_m / f->fade_m;
	int i = (int)cu, j = (int)cv;
	i = i > f->n - 2 ? f->n - 2 : i;
	j = j > f->n - 2 ? f->n - 2 : j;
	double a = cu - i, b = cv - j;
	const float *q = f->rgb + 3 * ((size_t)k * f->n * f->n + (size_t)j * f->n + i);
	const float *r = q + 3 * (size_t)f->n;
	for (int c = 0; c < 3; c++) {
		double near = (1.0 - b) * ((1.0 - a) * q[c] + a * q[3 + c]) +
			      b * ((1.0 - a) * r[c] + a * r[3 + c]);
		out[c] = near + w * (mean[c] - near);
	}
}

/* Whether the frame's field has its two planes (rain or snow). */
CS_HD static int two_planes(const struct cs_scene *sc)
{
	return sc->ground_field.rgb != NULL && sc->ground_field.planes > 1;
}

/* The field's ground plane at p (top: its top plane), or without a field
 * the frame's one value. */
CS_HD static void field_plane(const struct cs_scene *sc, cs_v3 p, int top, double out[3])
{
	const struct cs_ground_field *f = &sc->ground_field;
	if (f->rgb == NULL) {
		for (int k = 0; k < 3; k++)
			out[k] = sc->deck.sky_ground[k];
		return;
	}
	int k = top && f->planes > 1 ? f->planes - 1 : 0;
	field_at(f, k, k > 0 ? f->top_mean : f->mean, p, out);
}

CS_HD double cs_rain_height(const struct cs_scene *sc, double alt_m)
{
	double top = sc->rain_top_m - sc->ground_alt_m;
	double h = top > 0.0 ? (alt_m - sc->ground_alt_m) / top : 0.0;
	return h > 0.0 ? (h < 1.0 ? h : 1.0) : 0.0; /* (NaN: 0) */
}

CS_HD void cs_ground_sky(const struct cs_scene *sc, cs_v3 p, double out[3])
{
	field_plane(sc, p, 0, out);
	if (two_planes(sc)) {
		double h = cs_rain_height(sc, cs_scene_altitude(sc, p)), top[3];
		if (h > 0.0) {
			field_plane(sc, p, 1, top);
			for (int k = 0; k < 3; k++)
				out[k] += h * (top[k] - out[k]);
		}
	}
}

CS_HD void cs_rain_top_sky(const struct cs_scene *sc, cs_v3 p, double out[3])
{
	field_plane(sc, p, 1, out);
}

CS_HD int cs_rain_ground_sky(const struct cs_scene *sc, cs_v3 p, double out[3])
{
	if (!two_planes(sc))
		return 0;
	field_plane(sc, p, 0, out);
	return 1;
}

/* Under rain or snow at p, of the light under the clouds (sky) what comes
 * down through its column (cs_rain_column, the ground of albedo alb
 * under it), in place, unless the field has its two planes (the ground
 * plane's rays crossed the rain: cs_ground_sky); the sun's beam's
 * transmittance through the rain toward it (1 where none falls). */
CS_HD static double rain_over(const struct cs_scene *sc, cs_v3 p, const double alb[3],
			      double sky[3])
{
	if (!CS_FX_IS(sc, CS_FX_RAIN | CS_FX_SNOW))
		return 1.0;
	double sigma = sc->rain_extinction_per_m * cs_rain_shaft(sc, p.x, p.y);
	double h = sc->rain_top_m - cs_scene_altitude(sc, p);
	if (!(sigma > 0.0 && h > 0.0))
		return 1.0;
	if (!two_planes(sc)) {
		double mean[3], down[3];
		cs_rain_column(sc->precip_albedo, sigma * h, sigma * h, alb, mean, down);
		for (int k = 0; k < 3; k++)
			sky[k] *= down[k];
	}
	return sc->sun_dir.z > 0.0 ? exp(-sigma * h / sc->sun_dir.z) : 1.0;
}

CS_HD CS_COLD void cs_water_light(const struct cs_scene *sc, const struct cs_render_settings *s,
			  cs_v3 p, cs_v3 d, int on_terrain, struct cs_render_stats *st,
			  double rgb[3])
{
	cs_v3 n = v3_norm(v3(p.x, p.y, p.z + sc->earth_radius_m)); /* level water */
	double cv = -v3_dot(d, n);
	cv = cv > 1e-4 ? cv : 1e-4;
	/* the sky in the mirror direction: under a deck what it lets through */
	cs_v3 r = v3_norm(v3_mad(d, n, 2.0 * cv));
	double sky[3] = {0.0, 0.0, 0.0}, ground[3], rain_beam = 1.0;
	if (sc->deck.on) {
		const double water[3] = {CS_WATER_DIFFUSE_ALBEDO, CS_WATER_DIFFUSE_ALBEDO,
					 CS_WATER_DIFFUSE_ALBEDO};
		cs_ground_sky(sc, p, ground);
		rain_beam = rain_over(sc, p, water, ground);
	}
	if (CS_FX_IS(sc, CS_FX_SKY)) {
		if (sc->deck.on)
			for (int k = 0; k < 3; k++)
				sky[k] = ground[k];
		else
			cs_scene_sky(sc, r, sky);
	}
	double F = cs_water_fresnel(cv);
	/* the water body: light that entered, scattered and came back up */
	const double body[3] = {CS_WATER_BODY_R, CS_WATER_BODY_G, CS_WATER_BODY_B};
	const double *amb = sc->deck.on ? ground : sc->ambient_up;
	double cosi = v3_dot(n, sc->sun_dir), sunT = 0.0;
	if (CS_FX_IS(sc, CS_FX_KEY) && cosi > 0.0) {
		double self = on_terrain ? terrain_shadow(sc->terrain, p, sc->sun_dir) : 1.0;
		sunT = CS_FX_IS(sc, CS_FX_CLOUD_SHADOWS) && self > 0.0
			       ? self * cs_render_sun_transmittance(sc, s, p, st)
			       : self;
		sunT *= rain_beam;
	}
	double glint = 0.0;
	if (sunT > 0.0) {
		cs_v3 v = v3_scale(d, -1.0);
		cs_v3 h = v3_norm(v3_add(v, sc->sun_dir));
		glint = cs_water_glint(cv, cosi, v3_dot(h, n), v3_dot(v, h), sc->water_mss);
	}
	for (int k = 0; k < 3; k++)
		rgb[k] = F * sky[k] +
			 (1.0 - F) * body[k] * (sc->sun_illuminance[k] * cosi * sunT / CS_PI +
						(CS_FX_IS(sc, CS_FX_SKY) ? amb[k] : 0.0)) +
			 glint * sc->sun_illuminance[k] * sunT;
}

CS_HD CS_COLD void cs_ground_surface(const struct cs_scene *sc, cs_v3 p, int on_terrain,
			     cs_v3 *normal, double alb[3])
{
	cs_v3 n = v3_norm(v3(p.x, p.y, p.z + sc->earth_radius_m));
	for (int k = 0; k < 3; k++)
		alb[k] = sc->ground_albedo[k];
	if (on_terrain) {
		double h;
		cs_hfield_height(sc->terrain, p.x, p.y, &h);
		n = cs_hfield_normal(sc->terrain, p.x, p.y);
		terrain_albedo(sc, p.x, p.y, h, n, alb);
	}
	if (sc->noise && !(on_terrain && (sc->terrain_color || sc->terrain_cpt))) {
		/* fields and woods: the albedo varies over ~1 km and ~150 m, which
		 * also shows the eye how far away the ground is */
		double v = 0.6 * cs_volume_sample(sc->noise, 1, p.x / 4000.0, p.y / 4000.0, 0.3) +
			   0.4 * cs_volume_sample(sc->noise, 3, p.x / 600.0, p.y / 600.0, 0.7);
		double k = 0.4 + 1.2 * v;
		for (int c = 0; c < 3; c++)
			alb[c] *= k;
	}
	for (int c = 0; c < 3; c++)
		alb[c] *= sc->ground_wet > 0.0 ? sc->ground_wet : 1.0;
	*normal = n;
}

CS_HD CS_COLD void cs_ground_light(const struct cs_scene *sc,
			 const struct cs_render_settings *s, cs_v3 p, cs_v3 d,
			 int on_terrain, struct cs_render_stats *st, double rgb[3])
{
	on_terrain = CS_BUILT(CS_FX_TERRAIN) && on_terrain;
	if (on_terrain && water_at(sc, p.x, p.y)) {
		cs_water_light(sc, s, p, d, on_terrain, st, rgb);
		return;
	}
	cs_v3 n;
	double alb[3], ao = 1.0, self = 1.0;
	cs_ground_surface(sc, p, on_terrain, &n, alb);
	if (on_terrain) {
		double h;
		cs_hfield_height(sc->terrain, p.x, p.y, &h);
		ao = terrain_ao(sc->terrain, p, h);
	}
	double cosi = v3_dot(n, sc->sun_dir), alt = cs_scene_altitude(sc, p);
	int key = CS_FX_IS(sc, CS_FX_KEY);
	int fog = CS_BUILT(CS_FX_FOG) && sc->fog_beta_per_m > 0.0 && alt < sc->fog_top_m;
	if (key && cosi > 0.0 && on_terrain)
		self = terrain_shadow(sc->terrain, p, sc->sun_dir);
	/* the clouds' transmittance of the sun's beam */
	double Tc = 1.0, direct = 0.0;
	if (key && CS_FX_IS(sc, CS_FX_CLOUD_SHADOWS) && cosi > 0.0 && self > 0.0)
		Tc = cs_render_sun_transmittance(sc, s, p, st);
	if (key && cosi > 0.0) {
		/* and the fog's beam transmittance: in fog at a low sun the
		 * ground sees no direct sun (the reference integrator showed
		 * the ground 2.9 times too bright without it) */
		double T = Tc * cs_fog_sun_transmittance(sc, alt);
		direct = cosi * T * self / CS_PI;
	}
	/* the sky light, or under clouds what they let through; in fog the
	 * light the fog scatters down there (its solution: the sky's and the
	 * sun's light through the fog above and the ground's own returned) */
	double ground[3];
	if (sc->deck.on) {
		cs_ground_sky(sc, p, ground);
		direct *= rain_over(sc, p, alb, ground);
	}
	const double *sky = sc->deck.on ? ground : sc->ambient_up;
	double diffuse[3];
	if (fog && sc->fog.on) {
		cs_fog_down(sc, alt, diffuse);
		for (int k = 0; k < 3; k++)
			diffuse[k] *= ao / CS_PI;
	} else {
		for (int k = 0; k < 3; k++)
			diffuse[k] = CS_FX_IS(sc, CS_FX_SKY) ? sky[k] * ao : 0.0;
	}
	for (int k = 0; k < 3; k++)
		rgb[k] = alb[k] * (sc->sun_illuminance[k] * direct + diffuse[k]);
}
