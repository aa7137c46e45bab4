/* Distances on the sphere against a published value and an independent
 * formula (Vincenty's special case for the sphere, atan2 form). */
#include "test.h"

#include "core/geo.h"

/* The central angle by the atan2 formula, not the haversine. */
static double vincenty_m(double la1, double lo1, double la2, double lo2)
{
	const double k = 3.14159265358979323846 / 180.0;
	double p1 = la1 * k, p2 = la2 * k, dl = (lo2 - lo1) * k;
	double x = cos(p2) * sin(dl);
	double y = cos(p1) * sin(p2) - sin(p1) * cos(p2) * cos(dl);
	double z = sin(p1) * sin(p2) + cos(p1) * cos(p2) * cos(dl);
	return 6371000.0 * atan2(sqrt(x * x + y * y), z);
}

static void great_circle_nashville_to_los_angeles_is_rosetta_codes_value(void)
{
	/* Rosetta Code, "Haversine formula": BNA (36.12, -86.67) to LAX
	 * (33.94, -118.40) is 2886.44444283798 km on a sphere of 6371 km */
	CHECK_NEAR(cs_great_circle_m(36.12, -86.67, 33.94, -118.40),
		   2886444.44283798, 0.01);
}

static void great_circle_agrees_with_the_atan2_formula(void)
{
	static const double pair[][4] = {
		{46.94798, 7.44743, 46.91722, 7.44361},   /* Bern - Gurten */
		{46.94798, 7.44743, 47.20791, 7.53714},   /* Bern - Solothurn */
		{51.5074, -0.1278, 40.7128, -74.0060},    /* London - New York */
		{-33.8688, 151.2093, 35.6762, 139.6503},  /* Sydney - Tokyo */
		{0, 0, 0, 179.5},
	};
	for (size_t i = 0; i < sizeof pair / sizeof pair[0]; i++) {
		const double *p = pair[i];
		CHECK_NEAR(cs_great_circle_m(p[0], p[1], p[2], p[3]),
			   vincenty_m(p[0], p[1], p[2], p[3]), 1e-3);
	}
}

static void great_circle_is_zero_for_one_place_and_half_round_for_antipodes(void)
{
	CHECK(cs_great_circle_m(46.9, 7.4, 46.9, 7.4) == 0.0);
	CHECK_NEAR(cs_great_circle_m(46.9, 7.4, -46.9, -172.6),
		   3.14159265358979323846 * 6371000.0, 1e-3);
	/* one degree of latitude: 2 pi R / 360 */
	CHECK_NEAR(cs_great_circle_m(10, 20, 11, 20), 111194.92664455873, 1e-6);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(great_circle_nashville_to_los_angeles_is_rosetta_codes_value),
	CASE(great_circle_agrees_with_the_atan2_formula),
	CASE(great_circle_is_zero_for_one_place_and_half_round_for_antipodes),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
