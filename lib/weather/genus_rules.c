#include "weather/genus_rules.h"


#include <math.h>
#include <stddef.h>

static const char *const rule_text[CS_RULE_COUNT] = {
	[CS_RULE_NONE] = "no cover: no layer",
	[CS_RULE_L1_CB] = "L1 convective rain >= 1 mm/h: cumulonimbus",
	[CS_RULE_L2_FOG] = "L2 fog probability >= 50 % or visibility < 1 km "
			   "without rain: stratus at the ground (fog)",
	[CS_RULE_L3_SHOWERS] = "L3 convective rain >= 0.1 mm/h: cumulus "
			       "(showers)",
	[CS_RULE_L4_NS] = "L4 low or mid cover >= 70 % and steady rain "
			  ">= 0.5 mm/h: nimbostratus",
	[CS_RULE_L5_ST] = "L5 low cover >= 70 % with drizzle or mist: stratus",
	[CS_RULE_L6_CU] = "L6 low cover < 70 % and sun >= 30 deg: cumulus",
	[CS_RULE_L7_SC] = "L7 other low cover: stratocumulus",
	[CS_RULE_L8_BELOW] = "L8 Open-Meteo low cover at ground >= 1000 m, "
			     "no fog: dropped (it counts pressure levels below "
			     "the ground)",
	[CS_RULE_M0_IN_NS] = "M0 mid cover is part of the nimbostratus",
	[CS_RULE_M1_AS] = "M1 mid cover >= 70 %: altostratus",
	[CS_RULE_M2_AC] = "M2 mid cover < 70 %: altocumulus",
	[CS_RULE_H1_CS] = "H1 high cover >= 70 %: cirrostratus",
	[CS_RULE_H2_CC] = "H2 high and mid cover 30..70 %: cirrocumulus",
	[CS_RULE_H3_CI] = "H3 other high cover: cirrus",
};

const char *cs_wx_rule_text(enum cs_wx_rule r)
{
	return (unsigned)r < CS_RULE_COUNT ? rule_text[r] : "unknown rule";
}

int cs_genus_etage(enum cs_genus g)
{
	switch (g) {
	case CS_ALTOCUMULUS:
	case CS_ALTOSTRATUS: return 1;
	case CS_CIRRUS:
	case CS_CIRROCUMULUS:
	case CS_CIRROSTRATUS: return 2;
	default: return 0;
	}
}

/* Typical base and top of each genus, m: above the ground for the low
 * étage, above sea level (at least the étage's floor) for the others. */
static const struct typical_alt {
	double base_m, top_m;
} typical[CS_GENUS_COUNT] = {
	[CS_CIRRUS] = {8000, 10000},
	[CS_CIRROCUMULUS] = {7000, 7600},
	[CS_CIRROSTRATUS] = {7500, 9000},
	[CS_ALTOCUMULUS] = {3000, 3800},
	[CS_ALTOSTRATUS] = {3000, 5000},
	[CS_NIMBOSTRATUS] = {800, 4000},
	[CS_STRATOCUMULUS] = {800, 1500},
	[CS_STRATUS] = {300, 800},
	[CS_CUMULUS] = {1500, 2700},
	[CS_CUMULONIMBUS] = {1000, 11000},
};

struct cs_genus_alt cs_genus_typical(enum cs_genus g)
{
	const struct typical_alt *p = &typical[(unsigned)g < CS_GENUS_COUNT ? g : CS_CUMULUS];
	return (struct cs_genus_alt){p->base_m, p->top_m};
}

void cs_genus_place(enum cs_genus g, double ground_alt_m, double *base_m,
		    double *top_m)
{
	/* WMO étages of temperate regions: low from the ground to 2 km, mid
	 * from 2 km, high from 5 km (International Cloud Atlas, 2017). */
	static const double floor_m[3] = {0, 2000, 5000};
	const struct typical_alt *p = &typical[(unsigned)g < CS_GENUS_COUNT ? g : CS_CUMULUS];
	int e = cs_genus_etage(g);
	double thick = p->top_m - p->base_m;
	if (e == 0) {
		*base_m = ground_alt_m + p->base_m;
	} else {
		double lowest = ground_alt_m + floor_m[e];
		*base_m = p->base_m > lowest ? p->base_m : lowest;
	}
	*top_m = *base_m + thick;
}

/* Dew point (C) by the Magnus formula with the constants of Alduchov and
 * Eskridge (1996, J. Appl. Meteor. 35, eq. 21): 0.4 % from -40 to 50 C. */
static double dew_point_c(double t_c, double rh_pct)
{
	const double b = 17.625, c = 243.04;
	double rh = rh_pct < 1 ? 1 : rh_pct > 100 ? 100 : rh_pct;
	double g = log(rh / 100) + b * t_c / (c + t_c);
	return c * g / (b - g);
}

/* Base of surface-based cumulus above the ground: the lifting condensation
 * level, about 125 m per kelvin of dew-point depression (Espy's rule). */
static int cumulus_base_agl(const struct cs_wx_obs *o, double *agl)
{
	if (!isfinite(o->temperature_c) || !isfinite(o->humidity_pct) ||
	    o->temperature_c <= -100)
		return 0;
	double h = 125.0 * (o->temperature_c -
			    dew_point_c(o->temperature_c, o->humidity_pct));
	*agl = h < 200 ? 200 : h > 3000 ? 3000 : h;
	return 1;
}

double cs_snow_fraction_rule(double t_c)
{
	if (isnan(t_c))
		return NAN;
	if (t_c <= CS_WX_SNOW_T_C)
		return 1;
	if (t_c >= CS_WX_RAIN_T_C)
		return 0;
	return (CS_WX_RAIN_T_C - t_c) / (CS_WX_RAIN_T_C - CS_WX_SNOW_T_C);
}

double cs_snow_fraction_of(double snowfall_cm, double precipitation_mm)
{
	if (!(precipitation_mm > 0) || !(snowfall_cm >= 0))
		return NAN;
	double f = snowfall_cm / CS_WX_SNOW_CM_PER_MM / precipitation_mm;
	return f > 1 ? 1 : f;
}

static double max2(double a, double b)
{
	return a > b ? a : b;
}

/* The observation the rules after L2 see: a low cover that counts levels
 * below the ground is none (it was fog, taken by L2, or nothing). */
static struct cs_wx_obs above_ground(const struct cs_wx_obs *o)
{
	struct cs_wx_obs e = *o;
	if (e.low_below_ground)
		e.low = 0;
	return e;
}

static enum cs_wx_rule low_rule(const struct cs_wx_obs *raw)
{
	struct cs_wx_obs e = above_ground(raw);
	const struct cs_wx_obs *o = &e;
	double conv = o->convective_mm_h;
	double strat = o->precipitation_mm_h - conv;
	double vis = o->visibility_m; /* NaN compares false: no fog, no mist */
	double fog = o->fog_probability;
	if (conv >= CS_WX_CB_MM_H)
		return CS_RULE_L1_CB;
	if (fog >= CS_WX_FOG_PROB ||
	    (vis < CS_WX_FOG_VIS_M && o->precipitation_mm_h < CS_WX_STEADY_MM_H))
		return CS_RULE_L2_FOG;
	if (conv >= CS_WX_SHOWER_MM_H)
		return CS_RULE_L3_SHOWERS;
	if (max2(o->low, o->mid) >= CS_WX_SHEET && strat >= CS_WX_STEADY_MM_H)
		return CS_RULE_L4_NS;
	if (o->low < CS_WX_MIN_COVER)
		return raw->low_below_ground && raw->low >= CS_WX_MIN_COVER ?
		       CS_RULE_L8_BELOW : CS_RULE_NONE;
	if (o->low >= CS_WX_SHEET &&
	    (strat >= CS_WX_DRIZZLE_MM_H || vis < CS_WX_MIST_VIS_M))
		return CS_RULE_L5_ST;
	if (o->low < CS_WX_SHEET && o->sun_elevation_deg >= CS_WX_CU_SUN_DEG)
		return CS_RULE_L6_CU;
	return CS_RULE_L7_SC;
}

void cs_wx_rules(const struct cs_wx_obs *o, enum cs_wx_rule rules[3])
{
	rules[0] = low_rule(o);
	if (rules[0] == CS_RULE_L4_NS)
		rules[1] = CS_RULE_M0_IN_NS;
	else if (o->mid >= CS_WX_SHEET)
		rules[1] = CS_RULE_M1_AS;
	else if (o->mid >= CS_WX_MIN_COVER)
		rules[1] = CS_RULE_M2_AC;
	else
		rules[1] = CS_RULE_NONE;
	if (o->high >= CS_WX_SHEET)
		rules[2] = CS_RULE_H1_CS;
	else if (o->high >= 0.3 && rules[1] == CS_RULE_M2_AC && o->mid >= 0.3)
		rules[2] = CS_RULE_H2_CC;
	else if (o->high >= CS_WX_MIN_COVER)
		rules[2] = CS_RULE_H3_CI;
	else
		rules[2] = CS_RULE_NONE;
}

static const enum cs_genus rule_genus[CS_RULE_COUNT] = {
	[CS_RULE_L1_CB] = CS_CUMULONIMBUS, [CS_RULE_L2_FOG] = CS_STRATUS,
	[CS_RULE_L3_SHOWERS] = CS_CUMULUS, [CS_RULE_L4_NS] = CS_NIMBOSTRATUS,
	[CS_RULE_L5_ST] = CS_STRATUS, [CS_RULE_L6_CU] = CS_CUMULUS,
	[CS_RULE_L7_SC] = CS_STRATOCUMULUS, [CS_RULE_M1_AS] = CS_ALTOSTRATUS,
	[CS_RULE_M2_AC] = CS_ALTOCUMULUS, [CS_RULE_H1_CS] = CS_CIRROSTRATUS,
	[CS_RULE_H2_CC] = CS_CIRROCUMULUS, [CS_RULE_H3_CI] = CS_CIRRUS,
};

int cs_wx_rule_layer(const struct cs_wx_obs *o, enum cs_wx_rule r,
		     double ground_alt_m, struct cs_wx_layer *l)
{
	if ((unsigned)r >= CS_RULE_COUNT || r == CS_RULE_NONE ||
	    r == CS_RULE_M0_IN_NS || r == CS_RULE_L8_BELOW)
		return 0;
	struct cs_wx_obs eff = above_ground(o);
	o = &eff;
	int e = r >= CS_RULE_H1_CS ? 2 : r >= CS_RULE_M0_IN_NS ? 1 : 0;
	const double cover[3] = {o->low, o->mid, o->high};
	l->genus = rule_genus[r];
	l->coverage = cover[e];
	cs_genus_place(l->genus, ground_alt_m, &l->base_m, &l->top_m);
	double agl;
	switch (r) {
	case CS_RULE_L1_CB: /* rain falls from a cloud: some cover */
		l->coverage = max2(o->low, 0.3);
		break;
	case CS_RULE_L2_FOG:
		l->coverage = max2(o->low, o->fog_probability >= 0 ?
				   o->fog_probability : 0);
		if (o->visibility_m < CS_WX_FOG_VIS_M)
			l->coverage = 1;
		l->base_m = ground_alt_m;
		l->top_m = ground_alt_m + CS_WX_FOG_DEPTH_M;
		break;
	case CS_RULE_L3_SHOWERS:
		l->coverage = max2(o->low, 0.2);
		/* fall through */
	case CS_RULE_L6_CU:
		if (cumulus_base_agl(o, &agl)) {
			l->top_m += ground_alt_m + agl - l->base_m;
			l->base_m = ground_alt_m + agl;
		}
		break;
	case CS_RULE_L4_NS:
		l->coverage = max2(o->low, o->mid);
		break;
	default:
		break;
	}
	if (l->coverage > 1)
		l->coverage = 1;
	return 1;
}

void cs_wx_layers(const struct cs_wx_obs *o, double ground_alt_m,
		  struct cs_wx_layer *layers, int *nlayers,
		  enum cs_wx_rule *rules)
{
	enum cs_wx_rule r[3];
	cs_wx_rules(o, r);
	*nlayers = 0;
	for (int e = 0; e < 3; e++) {
		if (!cs_wx_rule_layer(o, r[e], ground_alt_m, &layers[*nlayers]))
			continue;
		if (rules != NULL)
			rules[*nlayers] = r[e];
		(*nlayers)++;
	}
}
