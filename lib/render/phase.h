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

#endif
