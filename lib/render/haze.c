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
	if (!(sc->effects & CS_FX_SKY))
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
	if (!(sc->fog_beta_per_m > 0.0))
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
	if (!(sc->fog_beta_per_m > 0.0) || !(alt_m < sc->fog_top_m))
		return 1.0;
	double mu = sc->sun_dir.z;
	if (!(mu > 0.0))
		return 0.0;
	return exp(-sc->fog_beta_per_m * (sc->fog_top_m - alt_m) / mu);
}
