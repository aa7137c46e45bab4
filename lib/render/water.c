/* The optics of open water (water.h). */
#include "render/water.h"

#include "core/vec.h"

#include <math.h>

CS_HD double cs_water_fresnel(double cos_i)
{
	const double n = CS_WATER_IOR;
	double c = cos_i < 0.0 ? 0.0 : cos_i > 1.0 ? 1.0 : cos_i;
	if (c > 0.999999) { /* the limit at normal incidence */
		double r = (n - 1.0) / (n + 1.0);
		return r * r;
	}
	/* Fresnel's sine and tangent laws (Born & Wolf 1.5.(21)):
	 * Rs = sin^2(i - t) / sin^2(i + t), Rp = tan^2(i - t) / tan^2(i + t) */
	double i = acos(c), t = asin(sin(i) / n);
	double ss = sin(i - t) / sin(i + t), tt = tan(i - t) / tan(i + t);
	return 0.5 * (ss * ss + tt * tt);
}

double cs_water_slope_variance(double wind_m_s)
{
	double u = wind_m_s > 0.0 ? wind_m_s : 0.0;
	return 0.003 + 0.00512 * u;
}

CS_HD double cs_water_glint(double cos_v, double cos_l, double cos_h,
			    double v_dot_h, double mss)
{
	if (!(cos_v > 0.0) || !(cos_l > 0.0) || !(cos_h > 0.0) || !(mss > 0.0))
		return 0.0;
	double c2 = cos_h * cos_h;
	double tan2 = (1.0 - c2) / c2;
	/* Beckmann: exp(-tan^2 / m^2) / (pi m^2 cos^4), normalised so that the
	 * projected facet area is 1 */
	double D = exp(-tan2 / mss) / (CS_PI * mss * c2 * c2);
	return cs_water_fresnel(v_dot_h) * D / (4.0 * cos_v);
}
