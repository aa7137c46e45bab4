/* wxrules.h - from a provider's hourly values to the cloud layers of the
 * weather state: a genus per étage by documented rules (man 1 wxinterp,
 * GENUS RULES), and the altitudes of each genus. */
#ifndef CS_WXRULES_H
#define CS_WXRULES_H

#include "weather/wx.h"

/* What the providers say about one time and place, in state units.  The
 * optional values are NaN when the file lacks them. */
struct cs_wx_obs {
	double low, mid, high;       /* cloud cover of each étage, 0..1 */
	double precipitation_mm_h;   /* total, >= 0 */
	double convective_mm_h;      /* convective part, 0..total */
	double wind_speed_m_s;
	double wind_from_deg;        /* 0..360 */
	double visibility_m;         /* optional */
	double fog_probability;      /* 0..1, optional */
	double temperature_c;        /* 2 m, optional */
	double humidity_pct;         /* 2 m relative humidity, optional */
	double sun_elevation_deg;    /* optional (NaN: unknown, no daytime rule) */
	double snow_fraction;        /* 0..1 of the precipitation (always set by
					cs_series_obs: see cs_snow_fraction_of) */
	struct cs_wx_observed observed; /* radiation and total cover, when the
					   file has them (not used by the rules) */
	int low_below_ground;        /* the low cover counts levels below the
					ground (Open-Meteo at an elevated site):
					fog if L2 says so, else dropped (L8) */
	int visibility_default;      /* the file's visibility was a model's
					default, taken as unknown (NaN) */
};

/* The rules, in the order they are tried within each étage. */
enum cs_wx_rule {
	CS_RULE_NONE,        /* no layer in this étage */
	CS_RULE_L1_CB,       /* convective rain >= 1 mm/h: cumulonimbus */
	CS_RULE_L2_FOG,      /* fog probability >= 50 %, or visibility < 1 km
				without rain: stratus at the ground */
	CS_RULE_L3_SHOWERS,  /* convective rain >= 0.1 mm/h: cumulus */
	CS_RULE_L4_NS,       /* low or mid cover >= 70 % and steady rain
				>= 0.5 mm/h: nimbostratus */
	CS_RULE_L5_ST,       /* low cover >= 70 % with drizzle or mist:
				stratus */
	CS_RULE_L6_CU,       /* low cover < 70 % with the sun >= 30 deg up:
				cumulus */
	CS_RULE_L7_SC,       /* any other low cover: stratocumulus */
	CS_RULE_L8_BELOW,    /* low cover that counts levels below the ground
				and is no fog: dropped, no layer */
	CS_RULE_M0_IN_NS,    /* mid cover taken into the nimbostratus */
	CS_RULE_M1_AS,       /* mid cover >= 70 %: altostratus */
	CS_RULE_M2_AC,       /* mid cover < 70 %: altocumulus */
	CS_RULE_H1_CS,       /* high cover >= 70 %: cirrostratus */
	CS_RULE_H2_CC,       /* high and mid cover both 30..70 %:
				cirrocumulus */
	CS_RULE_H3_CI,       /* any other high cover: cirrus */
	CS_RULE_COUNT
};

/* Thresholds of the rules. */
#define CS_WX_MIN_COVER 0.01     /* a layer needs this much cover */
#define CS_WX_SHEET 0.7          /* cover of a sheet (overcast étage) */
#define CS_WX_CB_MM_H 1.0        /* convective rain of a cumulonimbus */
#define CS_WX_SHOWER_MM_H 0.1    /* convective rain of showers */
#define CS_WX_STEADY_MM_H 0.5    /* stratiform rain of a nimbostratus */
#define CS_WX_DRIZZLE_MM_H 0.1   /* stratiform rain of drizzle */
#define CS_WX_FOG_PROB 0.5       /* fog probability that makes fog */
#define CS_WX_FOG_VIS_M 1000.0   /* visibility in fog */
#define CS_WX_MIST_VIS_M 5000.0  /* visibility in mist */
#define CS_WX_CU_SUN_DEG 30.0    /* sun elevation of daytime convection */
#define CS_WX_FOG_DEPTH_M 300.0  /* thickness of ground fog */
#define CS_WX_DEFAULT_VIS_M 30000.0 /* visibility when the file has none */
#define CS_WX_OM_ELEVATED_M 1000.0 /* Open-Meteo ground this high: its low
				    cover counts levels below the ground */
#define CS_WX_OM_VIS_CAP_LO 24000.0 /* Open-Meteo's visibility ceiling, */
#define CS_WX_OM_VIS_CAP_HI 24200.0 /* "approximately 24 km": unknown */
#define CS_WX_SNOW_T_C 0.5       /* all snow at or below this 2 m temperature */
#define CS_WX_RAIN_T_C 2.5       /* all rain at or above it (linear between) */
#define CS_WX_SNOW_CM_PER_MM 0.7 /* Open-Meteo: "7 cm snow = 10 mm
				    precipitation water equivalent" */

/* The fraction of precipitation falling as snow at a 2 m temperature:
 * 1 at or below CS_WX_SNOW_T_C, 0 at or above CS_WX_RAIN_T_C, linear
 * between; NaN for NaN. */
double cs_snow_fraction_rule(double temperature_c);

/* The snow fraction from Open-Meteo's snowfall (cm) and precipitation (mm)
 * of one hour: snowfall / CS_WX_SNOW_CM_PER_MM mm of water over the
 * precipitation, at most 1; NaN when there is no precipitation (the
 * caller falls back to the temperature rule). */
double cs_snow_fraction_of(double snowfall_cm, double precipitation_mm);

/* "L6 low cover < 70 % and sun >= 30 deg: cumulus". */
const char *cs_wx_rule_text(enum cs_wx_rule r);

/* The étage of a genus: 0 low (stratus, stratocumulus, cumulus,
 * cumulonimbus, nimbostratus: their bases are low), 1 mid (altocumulus,
 * altostratus), 2 high (cirrus, cirrocumulus, cirrostratus). */
int cs_genus_etage(enum cs_genus g);

/* Places a layer of genus g over ground at ground_alt_m (m above sea
 * level): low-étage genera at their typical height above the ground (the
 * genus presets of cloudrender); mid and high genera at their typical
 * altitude above sea level, raised where needed to stay 2000 m (mid) or
 * 5000 m (high) above the ground. */
/* A genus's typical base and top, m: above the ground for the low étage,
 * above sea level for the others (cs_genus_place applies them). */
struct cs_genus_alt {
	double base_m, top_m;
};
struct cs_genus_alt cs_genus_typical(enum cs_genus g);

void cs_genus_place(enum cs_genus g, double ground_alt_m, double *base_m,
		    double *top_m);

/* The layers of an observation, low to high (at most 3), with the rule
 * that made each (rules may be NULL).  Cumulus bases come from the lifting
 * condensation level, 125 m per kelvin of dew-point depression, when the
 * temperature and humidity are known (200..3000 m above the ground). */
void cs_wx_layers(const struct cs_wx_obs *o, double ground_alt_m,
		  struct cs_wx_layer *layers, int *nlayers,
		  enum cs_wx_rule *rules);

/* The layer rule r makes of an observation (its genus, coverage, base and
 * top, as cs_wx_layers places it), whether or not the rules would pick r
 * for it: 1, or 0 for a rule that makes no layer (none, M0, L8). */
int cs_wx_rule_layer(const struct cs_wx_obs *o, enum cs_wx_rule r,
		     double ground_alt_m, struct cs_wx_layer *l);

/* The rule of each étage (low, mid, high) for an observation. */
void cs_wx_rules(const struct cs_wx_obs *o, enum cs_wx_rule rules[3]);

#endif
