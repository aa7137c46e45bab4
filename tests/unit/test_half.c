#include "core/half.h"
#include "test.h"

#include <stdint.h>

static void half_known_encodings(void)
{
	CHECK(cs_float_to_half(0.0f) == 0x0000);
	CHECK(cs_float_to_half(-0.0f) == 0x8000);
	CHECK(cs_float_to_half(1.0f) == 0x3c00);
	CHECK(cs_float_to_half(-2.0f) == 0xc000);
	CHECK(cs_float_to_half(0.5f) == 0x3800);
	CHECK(cs_float_to_half(0.1f) == 0x2e66);
	CHECK(cs_float_to_half(65504.0f) == 0x7bff);
	CHECK(cs_float_to_half(65519.0f) == 0x7bff);  /* rounds down */
	CHECK(cs_float_to_half(65520.0f) == 0x7c00);  /* rounds to inf */
	CHECK(cs_float_to_half(1e10f) == 0x7c00);
	CHECK(cs_float_to_half(-INFINITY) == 0xfc00);
	CHECK((cs_float_to_half(NAN) & 0x7c00) == 0x7c00 &&
	      (cs_float_to_half(NAN) & 0x3ff) != 0);
	CHECK(cs_float_to_half(5.9604645e-8f) == 0x0001); /* 2^-24 */
	CHECK(cs_float_to_half(3.0e-8f) == 0x0001);       /* above half of it */
	CHECK(cs_float_to_half(2.9e-8f) == 0x0000);       /* below: zero */
	CHECK(cs_float_to_half(6.1035156e-5f) == 0x0400); /* 2^-14 */
}

/* Every finite half widens to a float that converts back to itself. */
static void half_round_trips_all_values(void)
{
	int bad = 0;
	for (uint32_t h = 0; h < 0x10000u; h++) {
		if ((h & 0x7c00u) == 0x7c00u && (h & 0x3ffu) != 0)
			continue; /* NaN */
		if (cs_float_to_half(cs_half_to_float((uint16_t)h)) != h)
			bad++;
	}
	CHECK(bad == 0);
}

/* Rounding is to the nearest half, ties to even. */
static void half_rounds_to_nearest_even(void)
{
	/* 1 + 2^-11 is halfway between 1 and 1 + 2^-10: even is 1 */
	CHECK(cs_float_to_half(1.0f + 0x1p-11f) == 0x3c00);
	/* 1 + 3*2^-11 is halfway between 1+2^-10 and 1+2^-9: even is 1+2^-9 */
	CHECK(cs_float_to_half(1.0f + 3 * 0x1p-11f) == 0x3c02);
	CHECK(cs_float_to_half(1.0f + 0x1p-11f + 0x1p-20f) == 0x3c01);
	unsigned st = 5;
	double worst = 0.0;
	for (int i = 0; i < 100000; i++) {
		float f = (float)t_uniform(&st, -1000.0, 1000.0);
		float g = cs_half_to_float(cs_float_to_half(f));
		double rel = fabs(g - f) / fabs(f);
		if (fabs(f) > 1e-3 && rel > worst)
			worst = rel;
	}
	CHECK(worst <= 0x1p-11 * 1.0000001);
}

/* The saturating form: a finite value past the largest half (65504,
 * 0x7bff) is that half, of its sign; inf and NaN stay; every other value
 * is cs_float_to_half's. */
static void half_saturating_keeps_finite_values_finite(void)
{
	CHECK(cs_float_to_half_sat(65520.0f) == 0x7bff);
	CHECK(cs_float_to_half_sat(1.6e6f) == 0x7bff);
	CHECK(cs_float_to_half_sat(-1e30f) == 0xfbff);
	CHECK(cs_float_to_half_sat(3.4e38f) == 0x7bff);
	CHECK(cs_float_to_half_sat(INFINITY) == 0x7c00);
	CHECK(cs_float_to_half_sat(-INFINITY) == 0xfc00);
	CHECK((cs_float_to_half_sat(NAN) & 0x7c00) == 0x7c00 &&
	      (cs_float_to_half_sat(NAN) & 0x3ff) != 0);
	int bad = 0;
	for (uint32_t h = 0; h < 0x7c00u; h++) {
		float f = cs_half_to_float((uint16_t)h);
		if (cs_float_to_half_sat(f) != h || cs_float_to_half_sat(-f) != (h | 0x8000u))
			bad++;
	}
	CHECK(bad == 0);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(half_known_encodings),
	CASE(half_round_trips_all_values),
	CASE(half_rounds_to_nearest_even),
	CASE(half_saturating_keeps_finite_values_finite),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
