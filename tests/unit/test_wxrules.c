/* Each genus rule of man 1 wxinterp (GENUS RULES) on a crafted
 * observation, with the thresholds on both sides. */
#include "render/cloud.h"
#include "test.h"
#include "weather/genus_rules.h"

/* A clear, dry night with good visibility. */
static struct cs_wx_obs night(void)
{
	struct cs_wx_obs o;
	memset(&o, 0, sizeof o);
	o.wind_speed_m_s = 3;
	o.visibility_m = 30000;
	o.temperature_c = o.humidity_pct = NAN;
	o.sun_elevation_deg = -20;
	return o;
}

static struct cs_wx_layer one[CS_WX_MAX_LAYERS];
static enum cs_wx_rule why[CS_WX_MAX_LAYERS];

static int layers(const struct cs_wx_obs *o)
{
	int n = -1;
	cs_wx_layers(o, 540, one, &n, why);
	return n;
}

/* Layer i has genus g from rule r, coverage c, at the genus's altitudes. */
static void expect_layer(int i, enum cs_genus g, enum cs_wx_rule r, double c)
{
	if (one[i].genus != g || why[i] != r) {
		printf("  layer %d: %s by rule %d, expected %s by rule %d\n", i,
		       cs_genus_name(one[i].genus), (int)why[i], cs_genus_name(g), (int)r);
		t_case_failed = 1;
	}
	CHECK_NEAR(one[i].coverage, c, 1e-12);
}

static void rule_l1_convective_rain_makes_cumulonimbus(void)
{
	struct cs_wx_obs o = night();
	o.low = 0.1;
	o.precipitation_mm_h = 3;
	o.convective_mm_h = 1;
	CHECK(layers(&o) == 1);
	expect_layer(0, CS_CUMULONIMBUS, CS_RULE_L1_CB, 0.3); /* at least 0.3 */
	const struct cs_genus_alt a_p = cs_genus_typical(CS_CUMULONIMBUS), *p = &a_p;
	CHECK_NEAR(one[0].base_m, 540 + p->base_m, 0);
	CHECK_NEAR(one[0].top_m, 540 + p->top_m, 0);
	o.low = 0.8;
	o.convective_mm_h = 0.99; /* below the threshold: showers */
	layers(&o);
	expect_layer(0, CS_CUMULUS, CS_RULE_L3_SHOWERS, 0.8);
}

static void rule_l2_fog_probability_or_low_visibility_makes_ground_stratus(void)
{
	struct cs_wx_obs o = night();
	o.low = 0.2;
	o.fog_probability = 0.6;
	CHECK(layers(&o) == 1);
	expect_layer(0, CS_STRATUS, CS_RULE_L2_FOG, 0.6);
	CHECK_NEAR(one[0].base_m, 540, 0);
	CHECK_NEAR(one[0].top_m, 540 + CS_WX_FOG_DEPTH_M, 0);
	o = night();
	o.fog_probability = NAN; /* Open-Meteo: visibility alone */
	o.visibility_m = 400;
	CHECK(layers(&o) == 1);
	expect_layer(0, CS_STRATUS, CS_RULE_L2_FOG, 1);
	o.fog_probability = 0.49;
	o.visibility_m = 1000;
	CHECK(layers(&o) == 0);
	/* poor visibility in steady rain is rain, not fog */
	o.low = 0.9;
	o.visibility_m = 800;
	o.precipitation_mm_h = 2;
	layers(&o);
	expect_layer(0, CS_NIMBOSTRATUS, CS_RULE_L4_NS, 0.9);
}

static void rule_l3_showers_make_cumulus_by_night_too(void)
{
	struct cs_wx_obs o = night();
	o.precipitation_mm_h = 0.3;
	o.convective_mm_h = 0.1;
	CHECK(layers(&o) == 1);
	expect_layer(0, CS_CUMULUS, CS_RULE_L3_SHOWERS, 0.2); /* at least 0.2 */
	const struct cs_genus_alt a_p = cs_genus_typical(CS_CUMULUS), *p = &a_p;
	CHECK_NEAR(one[0].base_m, 540 + p->base_m, 0);
}

static void rule_l4_high_cover_and_steady_rain_make_nimbostratus(void)
{
	struct cs_wx_obs o = night();
	o.low = 0.9;
	o.mid = 0.95;
	o.high = 0.2;
	o.precipitation_mm_h = 2.5;
	o.convective_mm_h = 0.05;
	CHECK(layers(&o) == 2); /* the mid cover is in the nimbostratus */
	expect_layer(0, CS_NIMBOSTRATUS, CS_RULE_L4_NS, 0.95);
	expect_layer(1, CS_CIRRUS, CS_RULE_H3_CI, 0.2);
	enum cs_wx_rule r[3];
	cs_wx_rules(&o, r);
	CHECK(r[1] == CS_RULE_M0_IN_NS);
	o.low = 0;
	o.mid = 0.8; /* rain from a thick mid sheet */
	o.precipitation_mm_h = 0.55;
	layers(&o);
	expect_layer(0, CS_NIMBOSTRATUS, CS_RULE_L4_NS, 0.8);
	o.precipitation_mm_h = 0.45; /* too little: altostratus */
	CHECK(layers(&o) == 2);
	expect_layer(0, CS_ALTOSTRATUS, CS_RULE_M1_AS, 0.8);
}

static void rule_l5_overcast_low_with_drizzle_or_mist_is_stratus(void)
{
	struct cs_wx_obs o = night();
	o.low = 0.9;
	o.precipitation_mm_h = 0.2;
	CHECK(layers(&o) == 1);
	expect_layer(0, CS_STRATUS, CS_RULE_L5_ST, 0.9);
	CHECK_NEAR(one[0].base_m, 540 + cs_genus_typical(CS_STRATUS).base_m, 0);
	o.precipitation_mm_h = 0;
	o.visibility_m = 3000;
	layers(&o);
	expect_layer(0, CS_STRATUS, CS_RULE_L5_ST, 0.9);
}

static void rule_l6_scattered_low_cover_under_a_high_sun_is_cumulus(void)
{
	struct cs_wx_obs o = night();
	o.low = 0.4;
	o.sun_elevation_deg = 45;
	CHECK(layers(&o) == 1);
	expect_layer(0, CS_CUMULUS, CS_RULE_L6_CU, 0.4);
	const struct cs_genus_alt a_p = cs_genus_typical(CS_CUMULUS), *p = &a_p;
	CHECK_NEAR(one[0].base_m, 540 + p->base_m, 0);
	/* base at the condensation level: 25 C, 50 % -> dew point 13.85 C */
	o.temperature_c = 25;
	o.humidity_pct = 50;
	layers(&o);
	CHECK_NEAR(one[0].base_m, 540 + 125 * (25 - 13.8546), 1);
	CHECK_NEAR(one[0].top_m - one[0].base_m, p->top_m - p->base_m, 1e-9);
	o.humidity_pct = 99; /* saturated: the lowest base, 200 m */
	layers(&o);
	CHECK_NEAR(one[0].base_m, 740, 1e-9);
	o.sun_elevation_deg = 29.9;
	layers(&o);
	expect_layer(0, CS_STRATOCUMULUS, CS_RULE_L7_SC, 0.4);
	o.sun_elevation_deg = 60;
	o.low = 0.7;
	layers(&o);
	expect_layer(0, CS_STRATOCUMULUS, CS_RULE_L7_SC, 0.7);
}

static void rule_l7_other_low_cover_is_stratocumulus_and_none_is_clear(void)
{
	struct cs_wx_obs o = night();
	o.low = 0.5;
	CHECK(layers(&o) == 1);
	expect_layer(0, CS_STRATOCUMULUS, CS_RULE_L7_SC, 0.5);
	CHECK_NEAR(one[0].base_m, 540 + cs_genus_typical(CS_STRATOCUMULUS).base_m, 0);
	o.low = 0.9; /* overcast, dry, clear air */
	layers(&o);
	expect_layer(0, CS_STRATOCUMULUS, CS_RULE_L7_SC, 0.9);
	o.low = 0.0099;
	CHECK(layers(&o) == 0);
}

static void rules_m1_m2_mid_cover_is_altostratus_or_altocumulus(void)
{
	struct cs_wx_obs o = night();
	o.mid = 0.7;
	CHECK(layers(&o) == 1);
	expect_layer(0, CS_ALTOSTRATUS, CS_RULE_M1_AS, 0.7);
	const struct cs_genus_alt a_p = cs_genus_typical(CS_ALTOSTRATUS), *p = &a_p;
	CHECK_NEAR(one[0].base_m, p->base_m, 0); /* above sea level */
	o.mid = 0.69;
	layers(&o);
	expect_layer(0, CS_ALTOCUMULUS, CS_RULE_M2_AC, 0.69);
	o.mid = 0.01;
	CHECK(layers(&o) == 1);
	o.mid = 0.005;
	CHECK(layers(&o) == 0);
}

static void rules_h1_h2_h3_high_cover_is_cirrostratus_cirrocumulus_or_cirrus(void)
{
	struct cs_wx_obs o = night();
	o.high = 0.7;
	CHECK(layers(&o) == 1);
	expect_layer(0, CS_CIRROSTRATUS, CS_RULE_H1_CS, 0.7);
	o.high = 0.5;
	o.mid = 0.5; /* a mackerel sky: patchy high over patchy mid */
	CHECK(layers(&o) == 2);
	expect_layer(0, CS_ALTOCUMULUS, CS_RULE_M2_AC, 0.5);
	expect_layer(1, CS_CIRROCUMULUS, CS_RULE_H2_CC, 0.5);
	o.mid = 0.2;
	layers(&o);
	expect_layer(1, CS_CIRRUS, CS_RULE_H3_CI, 0.5);
	o.mid = 0.8; /* over altostratus */
	layers(&o);
	expect_layer(1, CS_CIRRUS, CS_RULE_H3_CI, 0.5);
	o.mid = 0;
	o.high = 0.29;
	CHECK(layers(&o) == 1);
	expect_layer(0, CS_CIRRUS, CS_RULE_H3_CI, 0.29);
	const struct cs_genus_alt a_p = cs_genus_typical(CS_CIRRUS), *p = &a_p;
	CHECK_NEAR(one[0].base_m, p->base_m, 0);
}

static void all_three_etages_come_low_to_high(void)
{
	struct cs_wx_obs o = night();
	o.low = 0.3;
	o.mid = 0.3;
	o.high = 0.9;
	CHECK(layers(&o) == 3);
	CHECK(one[0].genus == CS_STRATOCUMULUS && one[1].genus == CS_ALTOCUMULUS &&
	      one[2].genus == CS_CIRROSTRATUS);
	CHECK(one[0].base_m < one[1].base_m && one[1].base_m < one[2].base_m);
	for (int r = 0; r < CS_RULE_COUNT; r++)
		CHECK(strcmp(cs_wx_rule_text((enum cs_wx_rule)r), "unknown rule") != 0);
}

static void high_ground_lifts_mid_and_high_layers(void)
{
	double b, t;
	const struct cs_genus_alt a_as = cs_genus_typical(CS_ALTOSTRATUS), *as = &a_as;
	cs_genus_place(CS_ALTOSTRATUS, 3500, &b, &t);
	CHECK_NEAR(b, 5500, 0);
	CHECK_NEAR(t - b, as->top_m - as->base_m, 1e-9);
	cs_genus_place(CS_ALTOSTRATUS, 540, &b, &t);
	CHECK_NEAR(b, as->base_m, 0);
	cs_genus_place(CS_CIRRUS, 6000, &b, &t);
	CHECK_NEAR(b, 11000, 0);
	cs_genus_place(CS_STRATUS, 1000, &b, &t);
	CHECK_NEAR(b, 1000 + cs_genus_typical(CS_STRATUS).base_m, 0);
	CHECK(cs_genus_etage(CS_NIMBOSTRATUS) == 0 && cs_genus_etage(CS_ALTOCUMULUS) == 1 &&
	      cs_genus_etage(CS_CIRROCUMULUS) == 2);
}

/* The temperature rule: all snow at or below 0.5 C, all rain at or above
 * 2.5 C, linear between; and Open-Meteo's "7 cm snow = 10 mm water". */
static void snow_fraction_by_temperature_and_by_open_meteo_snowfall(void)
{
	CHECK(cs_snow_fraction_rule(-10) == 1);
	CHECK(cs_snow_fraction_rule(0.5) == 1);
	CHECK_NEAR(cs_snow_fraction_rule(1.0), 0.75, 1e-12);
	CHECK_NEAR(cs_snow_fraction_rule(1.5), 0.5, 1e-12);
	CHECK(cs_snow_fraction_rule(2.5) == 0);
	CHECK(cs_snow_fraction_rule(20) == 0);
	CHECK(isnan(cs_snow_fraction_rule(NAN)));
	CHECK_NEAR(cs_snow_fraction_of(7, 10), 1, 1e-12);    /* 7 cm = 10 mm */
	CHECK_NEAR(cs_snow_fraction_of(3.5, 10), 0.5, 1e-12);
	CHECK_NEAR(cs_snow_fraction_of(0.7, 4), 0.25, 1e-12); /* 1 mm of 4 */
	CHECK(cs_snow_fraction_of(0, 2) == 0);
	CHECK(cs_snow_fraction_of(14, 10) == 1);              /* at most all */
	CHECK(isnan(cs_snow_fraction_of(1, 0)));              /* no precipitation */
	CHECK(isnan(cs_snow_fraction_of(NAN, 1)));
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(rule_l1_convective_rain_makes_cumulonimbus),
	CASE(snow_fraction_by_temperature_and_by_open_meteo_snowfall),
	CASE(rule_l2_fog_probability_or_low_visibility_makes_ground_stratus),
	CASE(rule_l3_showers_make_cumulus_by_night_too),
	CASE(rule_l4_high_cover_and_steady_rain_make_nimbostratus),
	CASE(rule_l5_overcast_low_with_drizzle_or_mist_is_stratus),
	CASE(rule_l6_scattered_low_cover_under_a_high_sun_is_cumulus),
	CASE(rule_l7_other_low_cover_is_stratocumulus_and_none_is_clear),
	CASE(rules_m1_m2_mid_cover_is_altostratus_or_altocumulus),
	CASE(rules_h1_h2_h3_high_cover_is_cirrostratus_cirrocumulus_or_cirrus),
	CASE(all_three_etages_come_low_to_high),
	CASE(high_ground_lifts_mid_and_high_layers),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
