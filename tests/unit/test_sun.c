#include "astro/sun.h"

#include "core/err.h"
#include "test.h"

/* arrays of three doubles to and from cs_v3 */
#define V(a) v3((a)[0], (a)[1], (a)[2])
#define V_STORE(a, v) do { cs_v3 v_ = (v); (a)[0] = v_.x, (a)[1] = v_.y, (a)[2] = v_.z; } while (0)
#include "core/time.h"

#define RAD (3.14159265358979323846 / 180.0)

static const double BERN_LAT = 46.95, BERN_LON = 7.44;

static double utc(const char *iso)
{
	double u = NAN;
	CHECK(cs_time_parse(iso, &u) == 0);
	return u;
}

static int sun_is_finite(const struct cs_sun *s)
{
	return isfinite(s->azimuth_deg) && isfinite(s->elevation_deg) &&
	       isfinite(s->apparent_elevation_deg) && isfinite(s->declination_deg) &&
	       isfinite(s->right_ascension_deg) && isfinite(s->apparent_longitude_deg) &&
	       isfinite(s->equation_of_time_min) && isfinite(s->distance_au) &&
	       s->azimuth_deg >= 0.0 && s->azimuth_deg < 360.0 &&
	       fabs(s->elevation_deg) <= 90.0 && fabs(s->apparent_elevation_deg) <= 90.0;
}

/* Local true noon (UTC seconds) of the day starting at day0: 12:00 minus
 * 4 min per degree east minus the equation of time, iterated once. */
static double true_noon(double day0, double lon)
{
	struct cs_sun s;
	double t = day0 + 43200.0 - 240.0 * lon;
	for (int i = 0; i < 2; i++) {
		CHECK(cs_sun_position(t, 0.0, lon, &s) == 0);
		t = day0 + 43200.0 - 240.0 * lon - 60.0 * s.equation_of_time_min;
	}
	return t;
}

/* Meeus, Astronomical Algorithms (2nd ed. 1998), Example 25.a, 1992 October
 * 13.0 TD: true longitude 199.90988, apparent longitude 199.90895, apparent
 * right ascension 198.38083 (13h13m31.4s = -161.61917), apparent
 * declination -7.78507, R = 0.99766 AU.  (Declination and RA as also
 * asserted by R's oce::sunDeclinationRightAscension test of this example.)
 * We take 0h TD as 0h UTC.  Measured: declination -7.785070, RA 198.380825,
 * apparent longitude 199.908942, R 0.997662.  Example 28.b, same instant:
 * equation of time by Smart's formula +0.0598256 rad = 13.71102 min (as
 * in Sonia Keys' Go port of Meeus, eqtime_test.go); measured 13.71089. */
static void sun_matches_meeus_example_25a(void)
{
	struct cs_sun s;
	CHECK(cs_sun_position(utc("1992-10-13T00:00:00Z"), 0.0, 0.0, &s) == 0);
	CHECK_NEAR(s.declination_deg, -7.78507, 0.01);
	CHECK_NEAR(s.right_ascension_deg, 198.38083, 0.01);
}

/* The same example to the book's printed digits: the algorithm is Meeus'
 * own, so only rounding separates them.  This is tight enough to see the
 * nutation/aberration term (-0.00093 degrees here) of the longitude. */
static void sun_reproduces_meeus_example_25a_to_printed_digits(void)
{
	struct cs_sun s;
	CHECK(cs_sun_position(utc("1992-10-13T00:00:00Z"), 0.0, 0.0, &s) == 0);
	CHECK_NEAR(s.declination_deg, -7.78507, 2e-5);
	CHECK_NEAR(s.right_ascension_deg, 198.38083, 2e-5);
	CHECK_NEAR(s.apparent_longitude_deg, 199.90895, 2e-5);
	CHECK_NEAR(s.distance_au, 0.99766, 1e-5);
	CHECK_NEAR(s.equation_of_time_min, 0.0598256 * 4.0 / RAD, 0.0005);
}

/* NREL SPA (Reda & Andreas 2004, rev. 2008) worked example: 2003-10-17
 * 12:30:30 at zone -7, 39.742476 N 105.1786 W, 1830.14 m, 820 mbar, 11 C,
 * delta T 67 s: topocentric zenith 50.11162, azimuth 194.34024.  NOAA's
 * algorithm has no parallax, TT = UT and refraction for standard air, so
 * it cannot match to SPA's 0.0003.  Measured: zenith 50.10864 (-0.0030),
 * azimuth 194.34258 (+0.0023). */
static void sun_matches_nrel_spa_example_within_002_deg(void)
{
	struct cs_sun s;
	CHECK(cs_sun_position(utc("2003-10-17T12:30:30-07:00"), 39.742476, -105.1786, &s) == 0);
	CHECK_NEAR(90.0 - s.apparent_elevation_deg, 50.11162, 0.02);
	CHECK_NEAR(s.azimuth_deg, 194.34024, 0.02);
}

/* On the March equinox the declination is ~0, so at true noon on the
 * equator the sun is overhead; above 85 degrees refraction is zero. */
static void sun_is_overhead_at_equinox_noon_on_equator(void)
{
	struct cs_sun s;
	double noon = true_noon(utc("2021-03-20T00:00:00Z"), 0.0);
	CHECK(cs_sun_position(noon, 0.0, 0.0, &s) == 0);
	CHECK(s.elevation_deg > 89.8);
	CHECK(s.apparent_elevation_deg == s.elevation_deg);
	CHECK_NEAR(s.declination_deg, 0.0, 0.2);
}

/* Bern at the June solstice: noon elevation 90 - 46.95 + 23.44 = 66.49,
 * due south; the sun is at its highest then. */
static void bern_solstice_noon_elevation_is_colatitude_plus_obliquity(void)
{
	struct cs_sun s, before, after;
	double noon = true_noon(utc("2021-06-21T00:00:00Z"), BERN_LON);
	CHECK(cs_sun_position(noon, BERN_LAT, BERN_LON, &s) == 0);
	CHECK(cs_sun_position(noon - 600.0, BERN_LAT, BERN_LON, &before) == 0);
	CHECK(cs_sun_position(noon + 600.0, BERN_LAT, BERN_LON, &after) == 0);
	CHECK_NEAR(s.elevation_deg, 90.0 - 46.95 + 23.44, 0.3);
	CHECK_NEAR(s.azimuth_deg, 180.0, 0.1);
	CHECK(s.elevation_deg > before.elevation_deg && s.elevation_deg > after.elevation_deg);
	CHECK(before.azimuth_deg < 180.0 && after.azimuth_deg > 180.0);
}

/* Bern, 2021-06-21: the sun rises north of east, at about 03:36 UTC
 * (05:36 CEST), and apparent elevation 0 comes a little after that. */
static void bern_june_sunrise_is_north_of_east(void)
{
	double t0 = utc("2021-06-21T02:00:00Z"), t = t0;
	struct cs_sun s;
	do {
		t += 60.0;
		CHECK(cs_sun_position(t, BERN_LAT, BERN_LON, &s) == 0);
	} while (s.apparent_elevation_deg < 0.0 && t < t0 + 6 * 3600.0);
	CHECK(s.azimuth_deg > 45.0 && s.azimuth_deg < 90.0);
	CHECK(t >= utc("2021-06-21T03:30:00Z") && t <= utc("2021-06-21T03:45:00Z"));
}

/* Bern near local midnight: the sun is ~19 degrees below the northern
 * horizon; refraction there is a few arc seconds. */
static void sun_below_horizon_at_night_has_negative_elevation(void)
{
	struct cs_sun s;
	CHECK(cs_sun_position(utc("2021-06-14T23:00:00Z"), BERN_LAT, BERN_LON, &s) == 0);
	CHECK(sun_is_finite(&s));
	CHECK(s.elevation_deg < -15.0 && s.apparent_elevation_deg < 0.0);
	CHECK(s.apparent_elevation_deg - s.elevation_deg < 0.05);
	CHECK(s.azimuth_deg > 315.0);
}

/* At a pole the elevation is the declination (its negative in the south),
 * whatever the hour; the azimuth still comes out finite. */
static void at_poles_elevation_equals_plus_minus_declination(void)
{
	unsigned st = 11;
	for (int i = 0; i < 200; i++) {
		double t = t_uniform(&st, -5.364e9, 7.289e9); /* 1800..2200 */
		double lon = t_uniform(&st, -180.0, 180.0);
		struct cs_sun n, s;
		CHECK(cs_sun_position(t, 90.0, lon, &n) == 0);
		CHECK(cs_sun_position(t, -90.0, lon, &s) == 0);
		CHECK(sun_is_finite(&n) && sun_is_finite(&s));
		CHECK_NEAR(n.elevation_deg, n.declination_deg, 1e-9);
		CHECK_NEAR(s.elevation_deg, -s.declination_deg, 1e-9);
	}
}

/* Refraction follows Saemundsson's formula (Meeus 16.4, true altitude h:
 * R = 1.02' / tan(h + 10.3/(h + 5.11))) within 0.003 degrees from the
 * horizon up; measured over a Bern summer day: at most 0.0021. */
static void refraction_agrees_with_saemundsson_above_horizon(void)
{
	double t0 = utc("2021-06-21T00:00:00Z");
	int n = 0;
	for (double t = t0; t < t0 + 86400.0; t += 60.0) {
		struct cs_sun s;
		CHECK(cs_sun_position(t, BERN_LAT, BERN_LON, &s) == 0);
		double h = s.elevation_deg;
		if (h < 0.0)
			continue;
		double r = 1.02 / tan((h + 10.3 / (h + 5.11)) * RAD) / 60.0;
		CHECK_NEAR(s.apparent_elevation_deg - h, r, 0.003);
		n++;
	}
	CHECK(n > 800); /* the sun is up ~16 h */
}

/* Where the sun stands exactly overhead the azimuth has no meaning but
 * must still be a number. */
static void sun_exactly_overhead_gives_finite_azimuth(void)
{
	struct cs_sun s, o;
	double t = utc("2021-06-21T12:00:00Z");
	CHECK(cs_sun_position(t, 0.0, 0.0, &s) == 0);
	/* hour angle 0 at 12:00 UTC where lon = -EoT/4 */
	CHECK(cs_sun_position(t, s.declination_deg, -s.equation_of_time_min / 4.0, &o) == 0);
	CHECK(sun_is_finite(&o));
	CHECK(o.elevation_deg > 89.9999);
	CHECK(o.apparent_elevation_deg == o.elevation_deg);
}

/* Longitude is taken modulo 360: 540 and -180 are 180. */
static void longitude_wraps_modulo_360(void)
{
	struct cs_sun a, b, c;
	double t = utc("2021-06-14T16:45:00Z");
	CHECK(cs_sun_position(t, 30.0, 180.0, &a) == 0);
	CHECK(cs_sun_position(t, 30.0, 540.0, &b) == 0);
	CHECK(cs_sun_position(t, 30.0, -180.0, &c) == 0);
	CHECK(sun_is_finite(&a) && sun_is_finite(&b) && sun_is_finite(&c));
	CHECK_NEAR(b.elevation_deg, a.elevation_deg, 1e-9);
	CHECK_NEAR(b.azimuth_deg, a.azimuth_deg, 1e-9);
	CHECK_NEAR(c.elevation_deg, a.elevation_deg, 1e-9);
	CHECK_NEAR(c.azimuth_deg, a.azimuth_deg, 1e-9);
}

/* The ends of the valid range, 1800 and 2200, give plausible values. */
static void years_1800_and_2200_give_plausible_values(void)
{
	const char *when[] = {"1800-01-01T00:00:00Z", "1800-07-04T12:00:00Z",
			      "2200-06-21T06:00:00Z", "2200-12-31T23:59:59Z"};
	for (int i = 0; i < 4; i++) {
		struct cs_sun s;
		CHECK(cs_sun_position(utc(when[i]), 45.0, -120.0, &s) == 0);
		CHECK(sun_is_finite(&s));
		CHECK(fabs(s.declination_deg) < 23.5);
		CHECK(s.distance_au > 0.983 && s.distance_au < 1.017);
		CHECK(fabs(s.equation_of_time_min) < 16.5);
	}
}

static void non_finite_input_or_bad_latitude_is_einval(void)
{
	struct cs_sun s;
	CHECK(cs_sun_position(NAN, 0.0, 0.0, &s) == CS_EINVAL);
	CHECK(cs_sun_position(0.0, NAN, 0.0, &s) == CS_EINVAL);
	CHECK(cs_sun_position(0.0, 0.0, INFINITY, &s) == CS_EINVAL);
	CHECK(cs_sun_position(INFINITY, 0.0, 0.0, &s) == CS_EINVAL);
	CHECK(cs_sun_position(0.0, 90.5, 0.0, &s) == CS_EINVAL);
	CHECK_STR_CONTAINS(cs_errmsg(), "latitude");
	CHECK(cs_sun_position(0.0, -91.0, 0.0, &s) == CS_EINVAL);
	CHECK(cs_sun_position(0.0, 0.0, 0.0, NULL) == CS_EINVAL);
}

/* dir is a unit vector, east = +x, north = +y, up = +z, and it points
 * along the azimuth and apparent elevation. */
static void direction_is_unit_enu_vector_along_azimuth(void)
{
	unsigned st = 7;
	for (int i = 0; i < 1000; i++) {
		struct cs_sun s;
		double d[3];
		CHECK(cs_sun_position(t_uniform(&st, 0.0, 2e9), t_uniform(&st, -90.0, 90.0),
				      t_uniform(&st, -180.0, 180.0), &s) == 0);
		V_STORE(d, cs_sun_direction_enu(&s));
		CHECK_NEAR(d[0] * d[0] + d[1] * d[1] + d[2] * d[2], 1.0, 1e-12);
		CHECK_NEAR(asin(d[2]) / RAD, s.apparent_elevation_deg, 1e-9);
		double az = atan2(d[0], d[1]) / RAD;
		if (az < 0.0)
			az += 360.0;
		if (fabs(s.apparent_elevation_deg) < 89.0)
			CHECK_NEAR(fmin(fabs(az - s.azimuth_deg), 360.0 - fabs(az - s.azimuth_deg)), 0.0, 1e-9);
	}
	/* Bern in June: east in the morning, south at noon, below at night */
	struct cs_sun s;
	double d[3];
	CHECK(cs_sun_position(utc("2021-06-21T06:00:00Z"), BERN_LAT, BERN_LON, &s) == 0);
	V_STORE(d, cs_sun_direction_enu(&s));
	CHECK(d[0] > 0.5 && d[2] > 0.0);
	CHECK(cs_sun_position(true_noon(utc("2021-06-21T00:00:00Z"), BERN_LON), BERN_LAT, BERN_LON, &s) == 0);
	V_STORE(d, cs_sun_direction_enu(&s));
	CHECK(d[1] < -0.3 && fabs(d[0]) < 1e-3 && d[2] > 0.9);
	CHECK(cs_sun_position(utc("2021-06-14T23:00:00Z"), BERN_LAT, BERN_LON, &s) == 0);
	V_STORE(d, cs_sun_direction_enu(&s));
	CHECK(d[2] < -0.3 && d[1] > 0.0);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(sun_matches_meeus_example_25a),
	CASE(sun_reproduces_meeus_example_25a_to_printed_digits),
	CASE(sun_matches_nrel_spa_example_within_002_deg),
	CASE(sun_is_overhead_at_equinox_noon_on_equator),
	CASE(bern_solstice_noon_elevation_is_colatitude_plus_obliquity),
	CASE(bern_june_sunrise_is_north_of_east),
	CASE(sun_below_horizon_at_night_has_negative_elevation),
	CASE(at_poles_elevation_equals_plus_minus_declination),
	CASE(refraction_agrees_with_saemundsson_above_horizon),
	CASE(sun_exactly_overhead_gives_finite_azimuth),
	CASE(longitude_wraps_modulo_360),
	CASE(years_1800_and_2200_give_plausible_values),
	CASE(non_finite_input_or_bad_latitude_is_einval),
	CASE(direction_is_unit_enu_vector_along_azimuth),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
