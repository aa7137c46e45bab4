/* water.h - open water (terrainprep --water-level, --water-mask): a
 * surface that reflects the sky by Fresnel's law and glints in the sun,
 * with a dark body under it. */
#ifndef CS_WATER_H
#define CS_WATER_H

#include "core/hd.h"

/* Refractive index of water in visible light (20 C, 589 nm: 1.333). */
#define CS_WATER_IOR 1.333

/* Fresnel reflectance of unpolarised light from air on water at an angle of
 * incidence with cosine cos_i: the mean of Fresnel's s and p laws, 0.0204
 * at normal incidence ((n - 1)/(n + 1))^2, 1 at grazing.  (Schlick's
 * approximation is 0.05 too high around 80 degrees for water.) */
CS_HD double cs_water_fresnel(double cos_i);

/* Mean square slope of a wind-roughened sea surface, Cox & Munk (1954),
 * clean surface: 0.003 + 0.00512 U (U: wind speed at 12.5 m, m/s). */
double cs_water_slope_variance(double wind_m_s);

/* The sun's glint: the radiance reflected toward the eye per unit of the
 * sun's irradiance (on a plane facing it), 1/sr, for a surface of mean
 * square slope mss (Beckmann facet distribution, the Gaussian slopes of
 * Cox & Munk), with cosines cos_v (view to normal), cos_l (sun to
 * normal), cos_h (half vector to normal), v_dot_h:
 * F(v.h) D(h) / (4 cos_v), no masking. */
CS_HD double cs_water_glint(double cos_v, double cos_l, double cos_h,
			    double v_dot_h, double mss);

/* The water body's diffuse albedo beneath the surface (clear lake water:
 * the light coming back up from it, Morel & Prieur 1977 order, linear
 * sRGB). */
#define CS_WATER_BODY_R 0.010
#define CS_WATER_BODY_G 0.020
#define CS_WATER_BODY_B 0.030
/* level water's reflectance for diffuse light (Fresnel, n 1.333, over the
 * hemisphere), what the rain over it sees under it */
#define CS_WATER_DIFFUSE_ALBEDO 0.066

#endif
