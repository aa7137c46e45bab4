/* haze.c - aerial perspective: the haze between the eye and what it sees,
 * from the visibility (an aerosol layer thinning exponentially with
 * height), lit by the sky; and fog, a layer of constant extinction from
 * the ground up. */
#include "render/march.h"

#include <math.h>

/* The light the haze scatters toward the eye along d under a clear sky:
 * the sky's radiance at the same azimuth and the same angle from the
 * horizon, looking up (for a plane-parallel haze layer the path looking
 * down at an angle sees what the path looking up at it sees), at least 1
 * degree up.  Of that, what exceeds the clear dome's cosine-mean radiance
 * (which an isotropic dome scatters back) is the sun's part, which a
 * cloud's shadow takes away. */
CS_HD CS_COLD void cs_haze_light(const struct cs_scene *sc, cs_v3 d, double clear[3], double sun[3])
{
	for (int k = 0; k < 3; k++)
		clear[k] = sun[k] = 0.0;
	if (!CS_FX_IS(sc, CS_FX_SKY))
		return;
	double up = fabs(d.z) > 0.0175 ? fabs(d.z) : 0.0175;
	double flat = sqrt(d.x * d.x + d.y * d.y);
	cs_v3 dir = v3(1.0, 0.0, up);
	if (flat > 1e-9) {
		double k = sqrt(1.0 - up * up) / flat;
		dir.x = d.x * k, dir.y = d.y * k;
	} else {
		dir.x = sqrt(1.0 - up * up);
	}
	cs_scene_sky(sc, dir, clear);
	for (int k = 0; k < 3; k++) {
		double s = clear[k] - sc->ambient_up[k];
		sun[k] = s > 0.0 ? s : 0.0;
	}
}

/* Haze optical depth along a straight ray leaving altitude h0 with vertical
 * direction component dz over distance t, for an aerosol extinction
 * decreasing exponentially with height (flat-Earth approximation). */
CS_HD double cs_haze_depth(const struct cs_scene *sc, double h0, double dz, double t)
{
	double H = sc->haze_scale_height_m;
	if (!(sc->haze_beta0_per_m > 0.0) || !(H > 0.0))
		return 0.0;
	double b = sc->haze_beta0_per_m * exp(-h0 / H);
	if (fabs(dz) * t < 1e-3 * H)
		return b * t;
	double x = -dz * t / H;
	x = x > 50.0 ? 50.0 : x; /* going down a very long way: capped, finite */
	return b * H * -expm1(x) / dz;
}

CS_HD double cs_fog_depth(const struct cs_scene *sc, double h0, double dz, double t)
{
	if (!CS_BUILT(CS_FX_FOG) || !(sc->fog_beta_per_m > 0.0))
		return 0.0;
	double top = sc->fog_top_m, len;
	if (fabs(dz) < 1e-12) {
		len = h0 < top ? t : 0.0;
	} else {
		double tc = (top - h0) / dz; /* where the ray crosses the top */
		tc = tc < 0.0 ? 0.0 : tc > t ? t : tc;
		len = dz > 0.0 ? (h0 < top ? tc : 0.0) : (h0 < top ? t : t - tc);
	}
	return sc->fog_beta_per_m * len;
}

CS_HD double cs_fog_sun_transmittance(const struct cs_scene *sc, double alt_m)
{
	if (!CS_BUILT(CS_FX_FOG) || !(sc->fog_beta_per_m > 0.0) || !(alt_m < sc->fog_top_m))
		return 1.0;
	double mu = sc->sun_dir.z;
	if (!(mu > 0.0))
		return 0.0;
	return exp(-sc->fog_beta_per_m * (sc->fog_top_m - alt_m) / mu);
}

/* The level of a light field (0 at its layer's top, CS_FOG_LEVELS - 1
 * at its bottom) at height fraction h, fractional, clamped: the levels
 * are at heights (1 - k / (CS_FOG_LEVELS - 1))^2 of the layer. */
CS_HD static double field_level(double h)
{
	h = h > 0.0 ? h < 1.0 ? h : 1.0 : 0.0; /* (not a number: the bottom) */
	return (1.0 - sqrt(h)) * (CS_FOG_LEVELS - 1);
}

/* The fog's height fraction at altitude alt_m. */
CS_HD static double fog_height(const struct cs_scene *sc, double alt_m)
{
	double depth = sc->fog_top_m - sc->ground_alt_m;
	return depth > 0.0 ? (alt_m - sc->ground_alt_m) / depth : 0.0;
}

/* The sources of light fields f[0..n-1] (n 1 or 2), weighed by wt,
 * summed: the position in the level and direction tables and the
 * azimuth's factors once for both. */
CS_HD CS_SHARED static void field_mix(const struct cs_fog_field *const *f, const double *wt, int n, double h,
			    double up_out, double cos_phi, double out[3])
{
	double u = field_level(h);
	double v = (up_out + 1.0) * 0.5 * (CS_FOG_DIRS - 1);
	v = v < 0.0 ? 0.0 : v > CS_FOG_DIRS - 1 ? CS_FOG_DIRS - 1 : v;
	int k = (int)u < CS_FOG_LEVELS - 1 ? (int)u : CS_FOG_LEVELS - 2;
	int m = (int)v < CS_FOG_DIRS - 1 ? (int)v : CS_FOG_DIRS - 2;
	double a = u - k, b = v - m;
	double w[4] = {(1.0 - a) * (1.0 - b), (1.0 - a) * b, a * (1.0 - b), a * b};
	/* (n ? 2 : 1) cos(n phi) by the recurrence of Chebyshev's polynomials */
	double cm[CS_FOG_MODES];
	cm[0] = 1.0;
	double c1 = cos_phi < -1.0 ? -1.0 : cos_phi > 1.0 ? 1.0 : cos_phi, prev = 1.0, cur = c1;
	for (int j = 1; j < CS_FOG_MODES; j++) {
		cm[j] = 2.0 * cur;
		double next = 2.0 * c1 * cur - prev;
		prev = cur, cur = next;
	}
	for (int c = 0; c < 3; c++)
		out[c] = 0.0;
	for (int i = 0; i < n; i++)
		for (int q = 0; q < 4; q++) {
			const float(*s)[3] = f[i]->src[k + (q >> 1)][m + (q & 1)];
			double wq = w[q] * wt[i];
			for (int j = 0; j < CS_FOG_MODES; j++)
				for (int c = 0; c < 3; c++)
					out[c] += wq * cm[j] * s[j][c];
		}
}

CS_HD CS_SHARED void cs_field_source(const struct cs_fog_field *f, double h, double up_out, double cos_phi,
			   double out[3])
{
	double one = 1.0;
	field_mix(&f, &one, 1, h, up_out, cos_phi, out);
}

/* The light of a point of a column of optical depth tau_above +
 * tau_below from the plane-parallel fields of a set (fields at depths t,
 * CS_DECK_DEPTHS of them): between two depths the sources are
 * interpolated in log depth, below the first the first is read, at the
 * point's share of the depth from the top.  Beyond the last (at most
 * CS_DECK_FIELD_TAU_MAX) the last is read there and, for the share deep
 * of it, scaled as diffusion scales it: deep in a conservative slab of
 * depth tc the light falls linearly to the base, as (tau_below + z) /
 * (tc + 2 z) with z the extrapolation depth, 2 z = 1.42 / (3 (1 - g) / 4)
 * (the transmittance 1 / (3 (1 - g) (tc + 2 z) / 4), deck.c's
 * slab_extend), so that the base of a column twice the last field's
 * depth is half as bright (read unscaled, the base of a uniform deck of
 * optical depth 256 was 1.76 times the similarity form's light).  In a
 * broken deck the thick cells take light through their sides too, which
 * a column does not count: under the capture's rain hour's nimbostratus
 * (70 % cover, depth fitted 3.53 times) the picture without its rain came
 * out -15.5 % against the path tracer scaled, -7.6 % unscaled
 * (field_deep, the caller's share: none at CS_DECK_FIELD_FULL cover, all
 * at full cover). */
CS_HD static void fields_source(const struct cs_fog_field *fields, const double *t, double z2,
				double deep_share, double tau_above, double tau_below,
				double up_out, double cos_phi, double out[3])
{
	double tc = tau_above + tau_below, f = 0.0;
	int k = 0;
	while (k < CS_DECK_DEPTHS - 2 && tc > t[k + 1])
		k++;
	/* in log depth, in float (a GPU's double logarithm is long); two
	 * depths closer than float's resolution are one */
	float span = log2f((float)(t[k + 1] / t[k]));
	if (tc >= t[k + 1] || !(span > 0.0f)) /* beyond the last */
		f = tc > t[k] ? 1.0 : 0.0;
	else if (tc > t[k])
		f = (double)log2f((float)(tc / t[k])) / (double)span;
	double h = tc > 0.0 ? 1.0 - tau_above / tc : 1.0, wt[2] = {1.0 - f, f};
	const struct cs_fog_field *two[2] = {&fields[k], &fields[k + 1]};
	field_mix(two, wt, 2, h, up_out, cos_phi, out);
	double tm = t[CS_DECK_DEPTHS - 1];
	if (deep_share > 0.0 && tc > tm && tm > 0.0) {
		double z = 0.5 * z2, deep = (h * tc + z) / (h * tm + z) * (tm + z2) / (tc + z2);
		for (int c = 0; c < 3; c++)
			out[c] *= 1.0 + deep_share * (deep - 1.0);
	}
}

/* Broken cloud, column by column (the independent column approximation):
 * the point's column, of optical depth tau_above + tau_below, taken for
 * a plane-parallel slab of that depth, the field read at the point's
 * share of it from the top.  The fields are at depths from tau_in / 16
 * to 2 tau_in (d->field_tau; tau_in the layer's mean in-cloud depth);
 * between two the sources are interpolated in log depth, beyond the
 * first and last the nearest is read (at tau_in / 16 a column is nearly
 * transparent).  Against the path tracer at the high preset
 * (tests/scenes, 96x54): inside stratocumulus of cover 0.75 from -30 % to
 * +1 % in the mean, the 0.7 tops seen from above -32 % -> -4 % (relative
 * MSE 0.18 -> 0.010), 0.8 altocumulus from below -23 % -> -4 %, inside
 * the 0.9 stratocumulus +9 % -> -5 %; one field at the mean depth, read
 * at tau_above / tau_in, left the last two +9 and +15 %, and the 0.7
 * tops seen 45 degrees down +34 % (now -2 %), their thin edges lit as the
 * top of a full-depth slab.  Fields from tau_in / 16 to tau_in only left
 * the tops -9 % and the altocumulus +8 %; three fields from tau_in / 16
 * to 2 tau_in, -4 and -7 %; geometric depths to 2 tau_in without tau_in
 * itself, the overcast +5 % (it reads tau_in's field: -1 %). */
CS_HD CS_SHARED void cs_deck_field_source(const struct cs_deck *d, int fi,
					  double tau_above, double tau_below, double up_out,
					  double cos_phi, double out[3])
{
	fields_source(d->field[fi], d->field_tau[fi], cs_slab_extrapolation_2z(d->g),
		      d->field_deep[fi], tau_above, tau_below, up_out, cos_phi, out);
}

/* Tilted columns (the tilted independent pixel approximation of Varnai
 * and Davies 1999): a point of a cumulonimbus tower taken for a point of a
 * plane-parallel slab that faces the sun, its depth the heap's toward the
 * sun and away from it, its top toward the sun; the sun's beam falls on
 * it square on, so its light is the same at every azimuth about the beam
 * (cos_phi 1).  The towers' walls, which the vertical columns took for
 * the sides of a slab lit from above, and a low sun's light through them,
 * are what the tower's light comes from: see integrator.c's tilt_light. */
CS_HD CS_SHARED void cs_deck_tilt_source(const struct cs_deck *d, double tau_sun, double tau_away,
					 double to_sun, double out[3])
{
	/* unscaled beyond the deepest (share 0): a tower is narrow, and the
	 * light of a long tilted path through it leaks out of its sides, as
	 * a deck's does not (scaled, the study's cumulonimbus lost 2.4 %
	 * of its mean luminance seen from the side and 1.5 % under a low
	 * sun at 96x54, the side view already -4.3 % against the path
	 * tracer at 1280x720) */
	fields_source(d->tilt, d->tilt_tau, 0.0, 0.0, tau_sun, tau_away, to_sun, 1.0, out);
}

CS_HD void cs_fog_source(const struct cs_scene *sc, double alt_m, double up_out, double cos_phi,
			 double out[3])
{
	cs_field_source(&sc->fog, fog_height(sc, alt_m), up_out, cos_phi, out);
}

CS_HD void cs_fog_down(const struct cs_scene *sc, double alt_m, double out[3])
{
	double u = field_level(fog_height(sc, alt_m));
	int k = (int)u < CS_FOG_LEVELS - 1 ? (int)u : CS_FOG_LEVELS - 2;
	double a = u - k;
	for (int c = 0; c < 3; c++)
		out[c] = (1.0 - a) * sc->fog.down[k][c] + a * sc->fog.down[k + 1][c];
}
