/* night.c - the sky when the sun is down: the Moon as the key light
 * (lighting clouds, ground and haze as the sun would, by its phase and
 * distance), the moonlit sky (the daylight sky's pattern for the Moon's
 * place, scaled by its light: the same scattering, so a moonlit sky is
 * blue), and stars where the sky is clear.  Each only when it is called
 * for: the Moon when it is up and the sun below -6 deg (civil twilight's
 * end), stars when the sun is below -12 deg (nautical). */
#include "render/march.h"

#include "astro/moon.h"
#include "core/hash.h"

#include <math.h>
#include <string.h>

#define SUN_TOA_KLUX 128.0 /* the sun's illuminance above the atmosphere */

void cs_scene_night(struct cs_scene *sc, double time_utc, double lat_deg, double lon_deg,
		    double sun_elevation_deg, double turbidity, enum cs_sky_level level,
		    double aod550, double altitude_m)
{
	sc->moon_scale = 0.0;
	if (sun_elevation_deg < -12.0) {
		/* local east-north-up to equatorial: the columns are the local
		 * axes in (x to RA 0h, y to RA 6h, z to the pole) */
		double gmst = fmod(280.46061837 + 360.98564736629 * (time_utc / 86400.0 - 10957.5), 360.0);
		double lst = (gmst + lon_deg) * CS_PI / 180.0, phi = lat_deg * CS_PI / 180.0;
		cs_v3 zen = v3(cos(phi) * cos(lst), cos(phi) * sin(lst), sin(phi));
		cs_v3 east = v3(-sin(lst), cos(lst), 0.0);
		cs_v3 north = v3_cross(zen, east);
		sc->star_frame[0] = east, sc->star_frame[1] = north, sc->star_frame[2] = zen;
		sc->effects |= CS_FX_STARS;
	}
	struct cs_moon m;
	if (!(sun_elevation_deg < -6.0) || cs_moon_position(time_utc, lat_deg, lon_deg, &m) != 0 ||
	    m.elevation_deg < -0.5 || m.illuminance_lux < 1e-4)
		return;
	cs_v3 dir = cs_moon_direction_enu(&m);
	cs_sky_init(&sc->moon_sky, dir, turbidity);
	if (level == CS_SKY_LEVEL_INEICHEN)
		cs_sky_scale_dome(&sc->moon_sky, cs_clear_sky_dome_scale(dir, turbidity, turbidity, aod550,
									 altitude_m, CS_SOLAR_CONSTANT_W_M2));
	sc->moon_scale = m.illuminance_lux * 1e-3 / SUN_TOA_KLUX;
	sc->sun_dir = v3_norm(dir);
	for (int k = 0; k < 3; k++) {
		sc->sun_illuminance[k] = sc->moon_sky.sun_illuminance[k] * sc->moon_scale;
		sc->ambient_up[k] += sc->moon_sky.ambient_up[k] * sc->moon_scale;
		sc->ambient_down[k] += sc->moon_sky.ambient_down[k] * sc->moon_scale;
	}
	sc->effects |= CS_FX_MOON;
}

CS_HD CS_COLD void cs_scene_sky(const struct cs_scene *sc, cs_v3 d, double rgb[3])
{
	cs_sky_radiance(&sc->sky, d, rgb);
	if (CS_FX_IS(sc, CS_FX_MOON)) {
		double m[3];
		cs_sky_radiance(&sc->moon_sky, d, m);
		for (int k = 0; k < 3; k++)
			rgb[k] += m[k] * sc->moon_scale;
	}
}

CS_HD CS_COLD void cs_scene_disk(const struct cs_scene *sc, cs_v3 d, double rgb[3])
{
	cs_sky_sun_disk(&sc->sky, d, rgb);
	if (CS_FX_IS(sc, CS_FX_MOON)) {
		double m[3];
		cs_sky_sun_disk(&sc->moon_sky, d, m);
		for (int k = 0; k < 3; k++)
			rgb[k] += m[k] * sc->moon_scale;
	}
}

/* Stars: the celestial sphere in equal-area cells (right ascension x sine
 * of declination), a star in a cell with the probability that gives about
 * 4800 stars to magnitude 6 over the sky, their number growing as
 * 10^(0.48 m) (the counts of the Yale Bright Star Catalogue), each a disc
 * of 0.05 deg radius of illuminance 10^(-0.4 (m + 14.18)) lux (Vega, m = 0:
 * 2.1 microlux).  Points smaller than a pixel may fall between pixel
 * centres: a wide view shows fewer of the faint ones. */
enum { STAR_RA = 2048, STAR_DEC = 1024 };
#define STAR_RADIUS_RAD (0.05 * CS_PI / 180.0)

CS_HD CS_COLD void cs_scene_stars(const struct cs_scene *sc, cs_v3 d, double rgb[3])
{
	rgb[0] = rgb[1] = rgb[2] = 0.0;
	if (!CS_FX_IS(sc, CS_FX_STARS) || d.z <= 0.0)
		return;
	const cs_v3 *f = sc->star_frame;
	cs_v3 q = v3_add(v3_add(v3_scale(f[0], d.x), v3_scale(f[1], d.y)), v3_scale(f[2], d.z));
	double ra = atan2(q.y, q.x), sd = q.z;
	int i = (int)floor((ra / (2.0 * CS_PI) + 0.5) * STAR_RA);
	int j = (int)floor((sd + 1.0) * 0.5 * STAR_DEC);
	for (int dj = -1; dj <= 1; dj++)
		for (int di = -1; di <= 1; di++) {
			int ci = ((i + di) % STAR_RA + STAR_RA) % STAR_RA, cj = j + dj;
			if (cj < 0 || cj >= STAR_DEC)
				continue;
			uint32_t h = cs_hash3i(ci, cj, 0x73746172, 7u);
			double p = 4800.0 / ((double)STAR_RA * STAR_DEC);
			double u = cs_hash_unit(h);
			if (u >= p)
				continue;
			double mag = 6.0 + log10((u + 1e-12) / p) / 0.48;
			double sra = ((ci + cs_hash_unit(cs_hash_u32(h ^ 1u))) / STAR_RA - 0.5) * 2.0 * CS_PI;
			double ssd = (cj + cs_hash_unit(cs_hash_u32(h ^ 2u))) / STAR_DEC * 2.0 - 1.0;
			double cd = sqrt(1.0 - ssd * ssd);
			cs_v3 s = v3(cd * cos(sra), cd * sin(sra), ssd);
			if (v3_dot(s, q) < cos(STAR_RADIUS_RAD))
				continue;
			double e = pow(10.0, -0.4 * (mag + 14.18)) * 1e-3; /* klux */
			double L = e / (CS_PI * STAR_RADIUS_RAD * STAR_RADIUS_RAD);
			rgb[0] += L * 0.95, rgb[1] += L * 1.0, rgb[2] += L * 1.08;
		}
}
