/* haze.c - aerial perspective: the haze between the eye and what it sees,
 * from the visibility (an aerosol layer thinning exponentially with
 * height), lit by the sky. */
#include "render/march.h"

#include <math.h>

/* The light the haze scatters toward the eye along d: the clear sky's radiance at
 * the same azimuth and the same angle from the horizon, looking up (for a
 * plane-parallel haze layer the path looking down at an angle sees what the
 * path looking up at it sees), at least 1 degree up. */
CS_HD void cs_haze_light(const struct cs_scene *sc, cs_v3 d, double rgb[3])
{
	if (!(sc->effects & CS_FX_SKY)) {
		rgb[0] = rgb[1] = rgb[2] = 0.0;
		return;
	}
	double up = fabs(d.z) > 0.0175 ? fabs(d.z) : 0.0175;
	double flat = sqrt(d.x * d.x + d.y * d.y);
	cs_v3 dir = v3(1.0, 0.0, up);
	if (flat > 1e-9) {
		double k = sqrt(1.0 - up * up) / flat;
		dir.x = d.x * k, dir.y = d.y * k;
	} else {
		dir.x = sqrt(1.0 - up * up);
	}
	cs_sky_radiance(&sc->sky, dir, rgb);
	/* Under clouds the haze sees the sun only where their shadows are not
	 * (the area mean of the beam's transmittance) and otherwise the grey
	 * dome of the light they let through, which an isotropic dome of
	 * radiance L scatters back as L. */
	const struct cs_deck *dk = &sc->deck;
	if (dk->on)
		for (int k = 0; k < 3; k++)
			rgb[k] = rgb[k] * dk->direct_below +
				 dk->sky_below[k] * (1.0 - dk->direct_below);
}

/* Haze optical depth along a straight ray leaving altitude h0 with vertical
 * direction component dz over distance t, for an aerosol extinction
 * decreasing exponentially with height (flat-Earth approximation). */
CS_HD double cs_haze_depth(const struct cs_scene *sc, double h0, double dz, double t)
{
	double H = sc->haze_scale_height_m, b = sc->haze_beta0_per_m * exp(-h0 / H);
	if (fabs(dz) * t < 1e-3 * H)
		return b * t;
	double x = -dz * t / H;
	x = x > 50.0 ? 50.0 : x; /* going down a very long way: capped, finite */
	return b * H * -expm1(x) / dz;
}
