#include "astro/moon.h"
#include "core/time.h"
#include "test.h"

/* Meeus, Astronomical Algorithms (2nd ed.), example 47.a: 1992 April 12,
 * 0h TD: geocentric longitude 133.162655 deg, latitude -3.229126 deg,
 * distance 368409.7 km; the low-precision formulae promise 0.3 deg,
 * 0.2 deg.  Example 48.a: the illuminated fraction then is 0.6786. */
static void moon_matches_meeus_worked_examples(void)
{
	double t;
	CHECK(cs_time_parse("1992-04-12T00:00:00Z", &t) == 0);
	t -= 59.0; /* TD - UT was 59 s in 1992 */
	struct cs_moon m;
	CHECK(cs_moon_position(t, 0.0, 0.0, &m) == 0);
	CHECK_NEAR(m.longitude_deg, 133.162655, 0.3);
	CHECK_NEAR(m.latitude_deg, -3.229126, 0.2);
	CHECK_NEAR(m.distance_km, 368409.7, 400.0);
	CHECK_NEAR(m.illuminated_fraction, 0.6786, 0.01);
}

/* 2024-10-17 11:26 UTC was full moon (illuminated fraction 1, phase angle
 * near 0); a new moon (2024-10-02 18:49 UTC) shows nothing. */
static void full_and_new_moon(void)
{
	double t;
	struct cs_moon m;
	CHECK(cs_time_parse("2024-10-17T11:26:00Z", &t) == 0);
	CHECK(cs_moon_position(t, 46.95, 7.44, &m) == 0);
	CHECK(m.illuminated_fraction > 0.995);
	/* Allen (Astrophysical Quantities): the full moon gives 0.267 lux above
	 * the atmosphere at its mean distance of 384400 km; this one was near
	 * perigee, and a phase angle of a few degrees dims it by under 8 % */
	double full = 0.267 * (384400.0 / m.distance_km) * (384400.0 / m.distance_km);
	CHECK(m.illuminance_lux <= full * 1.001 && m.illuminance_lux > 0.92 * full);
	CHECK(cs_time_parse("2024-10-02T18:49:00Z", &t) == 0);
	CHECK(cs_moon_position(t, 46.95, 7.44, &m) == 0);
	CHECK(m.illuminated_fraction < 0.005);
	CHECK(m.illuminance_lux < 1e-3);
}

/* The local sky: at the full moon of 2024-10-17 the Moon stood opposite
 * the Sun, so as seen from Bern at 22:00 UTC it was up in the south-east
 * to south (azimuth 130..200 deg) and the sun down; the direction is a
 * unit vector that agrees with elevation and azimuth. */
static void moon_stands_opposite_the_sun(void)
{
	double t;
	struct cs_moon m;
	CHECK(cs_time_parse("2024-10-17T22:00:00Z", &t) == 0);
	CHECK(cs_moon_position(t, 46.95, 7.44, &m) == 0);
	CHECK(m.elevation_deg > 20.0);
	CHECK(m.azimuth_deg > 130.0 && m.azimuth_deg < 200.0);
	cs_v3 d = cs_moon_direction_enu(&m);
	CHECK_NEAR(v3_len(d), 1.0, 1e-12);
	CHECK_NEAR(asin(d.z) * 180.0 / CS_PI, m.elevation_deg, 1e-9);
	CHECK(cs_moon_position(NAN, 0, 0, &m) != 0);
	CHECK(cs_moon_position(0, 91, 0, &m) != 0);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(moon_matches_meeus_worked_examples),
	CASE(full_and_new_moon),
	CASE(moon_stands_opposite_the_sun),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
