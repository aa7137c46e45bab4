/* phase.h - phase functions: how much light a scattering event sends from
 * one direction into another (1/sr; each integrates to 1 over the sphere). */
#ifndef CS_PHASE_H
#define CS_PHASE_H

#include "core/hd.h"
#include "core/vec.h"

/* Henyey-Greenstein phase function (1/sr) for the cosine of the angle
 * between the light's and the view's directions of travel. */
CS_HD static inline double cs_phase_hg(double cos_theta, double g)
{
	double denom = 1.0 + g * g - 2.0 * g * cos_theta;
	denom = denom > 1e-12 ? denom : 1e-12;
	return (1.0 - g * g) / (4.0 * CS_PI * denom * sqrt(denom));
}

/* The cloud's two-lobe Henyey-Greenstein: weight w_forward on a forward
 * lobe g_forward, the rest on a back lobe g_back, both eccentricities
 * scaled by c (the multiple-scattering octaves flatten the lobes). */
CS_HD static inline double cs_phase_two_lobe(double cos_theta, double g_forward,
					     double g_back, double w_forward,
					     double c)
{
	return w_forward * cs_phase_hg(cos_theta, g_forward * c) +
	       (1.0 - w_forward) * cs_phase_hg(cos_theta, g_back * c);
}

/* The 22-degree halo of hexagonal ice crystals: light refracted through
 * two faces at 60 degrees leaves at least the minimum deviation
 * D = 2 asin(n / 2) - 60 deg, piling up there; n of ice is 1.3079, 1.3110
 * and 1.3148 at 650, 550 and 450 nm, so the ring is red inside (21.7 deg)
 * and bluish outside (22.2 deg).  The profile: a sharp inner edge
 * (Gaussian, 0.25 deg) and a tail outward (exponential, 1.5 deg), scaled so
 * that it integrates to 1 over the sphere.  channel 0..2 = R, G, B. */
#define CS_HALO_INNER_DEG 0.25
#define CS_HALO_OUTER_DEG 1.5
CS_HD static inline double cs_halo_deviation_deg(double n)
{
	return 2.0 * asin(n / 2.0) * (180.0 / CS_PI) - 60.0;
}

CS_HD static inline double cs_phase_halo(double cos_theta, int channel)
{
	const double n[3] = {1.3079, 1.3110, 1.3148};
	double d = cs_halo_deviation_deg(n[channel]);
	double c = cos_theta < -1.0 ? -1.0 : cos_theta > 1.0 ? 1.0 : cos_theta;
	double th = acos(c) * (180.0 / CS_PI), x = th - d, f;
	if (x < 0.0)
		f = exp(-0.5 * (x / CS_HALO_INNER_DEG) * (x / CS_HALO_INNER_DEG));
	else
		f = exp(-x / CS_HALO_OUTER_DEG);
	/* the integral of f over the sphere, with the ring narrow against d */
	double rad = CS_PI / 180.0;
	double area = 2.0 * CS_PI * sin(d * rad) * rad *
		      (CS_HALO_OUTER_DEG + CS_HALO_INNER_DEG * sqrt(CS_PI / 2.0));
	return f / area;
}

#endif
