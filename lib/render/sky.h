/* sky.h - daylight sky: Preetham, Shirley & Smits, "A Practical Analytic
 * Model for Daylight" (SIGGRAPH 1999), plus a sun disk seen through the
 * atmosphere and a twilight/night extension.
 *
 * Frame: local east-north-up (x east, y north, z up); directions are unit
 * vectors.  Radiance is in kcd/m² per linear-sRGB channel (Rec. 709
 * primaries, D65 white), so an RGB value's luminance is
 * 0.2126 R + 0.7152 G + 0.0722 B; illuminance is in klux.
 *
 * cs_sky_radiance() and cs_sky_sun_disk() are pure functions of the struct:
 * no allocation, no globals, safe to call from many threads. */
#ifndef CS_SKY_H
#define CS_SKY_H

#include "core/hd.h"

#include "core/vec.h"

struct cs_sky {
	cs_v3 sun_dir;             /* unit, toward the sun (may be below the horizon) */
	double turbidity;          /* Preetham turbidity actually used, 1.7..10 */
	double sun_radiance[3];    /* mean radiance of the sun disk at the ground, after the atmosphere, kcd/m²; 0 once the whole disk has set */
	double sun_illuminance[3]; /* sun_radiance x solid angle of the disk x fraction of its light above the horizon (1 once risen): irradiance on a plane facing the sun, klux */
	double ambient_up[3];      /* cosine-weighted mean sky radiance over the upper hemisphere (irradiance on an upward plane / pi), sun disk excluded */
	double ambient_down[3];    /* same for a downward-facing plane: ground of albedo 0.2 lit by sun + sky on a horizontal plane, / pi */

	/* Private to sky.c. */
	double shape_sun[3];  /* sun_dir with elevation raised to >= 2 deg: the Perez shape's sun */
	double perez[3][5];   /* Perez A..E for Y, x, y */
	double scale[3];      /* Yz (times cs_sky_scale_dome's f), x_z, y_z divided by F(0, theta_s) */
	double depression;    /* degrees of sun below 2 deg elevation; 0 in daylight */
	double twilight;      /* luminance factor at the zenith, 1 in daylight */
	double glow_tint;     /* strength of the warm tint near the sun's horizon */
	double night[3];      /* moonless night sky, kcd/m² */
	double cos_sun_radius, sin2_sun_radius;
};

/* Turbidity from meteorological visibility (m) via Koschmieder: aerosol
 * extinction 3.912/V minus Rayleigh 1.16e-5 /m at 550 nm, times an aerosol
 * scale height of 1.2 km, as a ratio to the Rayleigh optical depth 0.0973,
 * plus 1; clamped to 1.7..10.  V = +inf gives 1.7; V <= 0 or NaN gives 10. */
double cs_turbidity_from_visibility(double visibility_m);
/* Rayleigh optical depth of the atmosphere at 550 nm, sea level: a
 * turbidity T is an aerosol optical depth (T - 1) times it. */
#define CS_RAYLEIGH_DEPTH_550 0.0973

/* Precomputes the sky for a sun direction and turbidity.  Any finite sun
 * direction works, including below the horizon (twilight and night); it
 * need not be unit (a zero or non-finite one is taken as the zenith).
 * Turbidity is clamped to 1.7..10 (NaN gives 1.7). */
void cs_sky_init(struct cs_sky *sky, cs_v3 sun_dir, double turbidity);
/* The same with the sun's beam attenuated by another turbidity (the
 * aerosol's true one, where the sky's pattern uses a capped one). */
void cs_sky_init_beam(struct cs_sky *sky, cs_v3 sun_dir, double turbidity,
		      double beam_turbidity);

/* Scales the sky's radiance (the sun's beam stays) by f > 0, and its
 * ambient terms with it; 1 or any other f changes nothing.  The Preetham
 * model gives the sky's pattern and colour; its level in absolute units
 * puts 1.3 to 2.1 times a clear-sky model's diffuse light on the ground at
 * turbidities 2 to 4, more in hazier air (Zotti, Wilkie & Purgathofer 2007
 * found its luminance off too), and with CS_SKY_LEVEL_INEICHEN the scene
 * sets the level from that model (render.h: cs_clear_sky_dome_scale). */
void cs_sky_scale_dome(struct cs_sky *sky, double f);

/* The unit direction d if it is elevation_rad or more above the horizon,
 * else the direction of the same azimuth elevation_rad up (due east where
 * d has none, or is NaN). */
cs_v3 cs_sky_raise(cs_v3 d, double elevation_rad);

/* Relative optical air mass, Kasten & Young (1989), at a sun elevation in
 * radians clamped to >= 0 (38 at the horizon). */
double cs_relative_air_mass(double elevation_rad);

/* Sky radiance seen along dir (unit), kcd/m², without the sun disk; finite
 * and >= 0.  For dir below the horizon, the value at the horizon in that
 * azimuth (straight down: the horizon due east). */
CS_HD void cs_sky_radiance(const struct cs_sky *sky, cs_v3 dir, double rgb[3]);

/* Radiance of the sun disk (angular radius 0.2666 deg, limb darkened) along
 * dir, kcd/m²; zero outside the disk and below the horizon (so a setting sun
 * is cut by the horizon and a set one draws nothing).  Integrates over the
 * disk to sun_illuminance, also while the horizon cuts it. */
CS_HD void cs_sky_sun_disk(const struct cs_sky *sky, cs_v3 dir, double rgb[3]);

#endif
