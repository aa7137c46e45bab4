#include "render/scene.h"

#include "core/color.h"
#include "core/err.h"
#include "render/march.h"
#include "render/sky.h"
#include "astro/sun.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

cs_v3 cs_geo_to_world(double origin_lat_deg, double origin_lon_deg,
		      double earth_radius_m, double lat_deg, double lon_deg,
		      double alt_m)
{
	double k = CS_PI / 180.0;
	double la0 = origin_lat_deg * k;
	double la = lat_deg * k, dlo = (lon_deg - origin_lon_deg) * k;
	double r = earth_radius_m + alt_m;
	/* the point in an Earth-centred frame whose x axis is the origin's
	 * meridian, then rotated into east-north-up at the origin */
	double px = r * cos(la) * cos(dlo), py = r * cos(la) * sin(dlo), pz = r * sin(la);
	double e = py;
	double n = -sin(la0) * px + cos(la0) * pz;
	double u = cos(la0) * px + sin(la0) * pz;
	return v3(e, n, u - earth_radius_m);
}

double cs_rain_extinction(double rate_mm_h)
{
	if (!(rate_mm_h > 0.0))
		return 0.0;
	double lambda_per_mm = 4.1 * pow(rate_mm_h, -0.21), n0 = 8000.0; /* /m^3/mm */
	/* 2 (pi/4) N0 * 2 / L^3 in mm^2/m^3 = 1e-6 m^2/m^3 */
	return CS_PI * n0 / (lambda_per_mm * lambda_per_mm * lambda_per_mm) * 1e-6;
}

double cs_snow_extinction(double rate_mm_h)
{
	return rate_mm_h > 0.0 ? 3.9e-3 * rate_mm_h : 0.0;
}

/* Genera that rain (and drizzle), when the weather says it rains. */
static int rains(enum cs_genus g, int convective)
{
	switch (g) {
	case CS_NIMBOSTRATUS:
	case CS_CUMULONIMBUS:
	case CS_ALTOSTRATUS:
	case CS_STRATOCUMULUS:
	case CS_STRATUS:
		return 1;
	case CS_CUMULUS:
		return convective;
	default:
		return 0;
	}
}

/* The visibility of the air above a fog: fog is a shallow layer and
 * neither reddens the sun above it nor hazes the distance above it. */
static double air_visibility_m(const struct cs_wx *wx)
{
	int fog = wx->visibility_m < CS_FOG_VISIBILITY_M;
	return fog && wx->visibility_m < CS_FOG_AIR_VISIBILITY_M ? CS_FOG_AIR_VISIBILITY_M
								 : wx->visibility_m;
}

/* The wind's move of a layer: a state's drift (cloudwx/2) carried on to
 * time_utc by its wind; without one, the wind times the time since
 * 2000-01-01 (cs_cloud_layer_init), as cloudwx/1 states always moved. */
static void drift_layer(struct cs_cloud_layer *l, const struct cs_wx *wx,
			double time_utc, double ground_alt_m)
{
	double e, n;
	if (!wx->drift.known)
		return;
	cs_wx_drift_at(wx, time_utc, &e, &n);
	cs_cloud_layer_drift(l, e, n, wx->drift.axis_deg, ground_alt_m);
}

/* The cloud layers: only those that have any cover; in fog a layer resting
 * on the ground is the fog, not a cloud.  The wind moves them: by the
 * state's drift, or with time counted from 2000-01-01 without one.  Far
 * sites' layers join, every layer's coverage weighted by how far along the
 * line to each far site a point is. */
static void build_layers(struct cs_scene *sc, const struct cs_wx *wx, double time_utc,
			 const struct cs_volume *noise)
{
	double t_wind = time_utc - 946684800.0;
	int fog = wx->visibility_m < CS_FOG_VISIBILITY_M;
	sc->fog_top_m = wx->site.alt_m + CS_FOG_DEPTH_M;
	for (int i = 0; i < wx->nlayers; i++) {
		if (wx->layers[i].coverage <= 0.0)
			continue;
		if (fog && wx->layers[i].base_m <= wx->site.alt_m + 1.0) {
			sc->fog_top_m = wx->layers[i].top_m;
			continue;
		}
		cs_cloud_layer_init(&sc->layers[sc->nlayers], &wx->layers[i], noise,
				    wx->wind_speed_m_s, wx->wind_from_deg,
				    wx->site.alt_m, t_wind);
		drift_layer(&sc->layers[sc->nlayers++], wx, time_utc, wx->site.alt_m);
	}
	if (wx->nfar > 0) {
		double fx[CS_WX_MAX_FAR], fy[CS_WX_MAX_FAR];
		int near = sc->nlayers;
		for (int f = 0; f < wx->nfar; f++) {
			cs_v3 p = cs_geo_to_world(wx->site.lat_deg, wx->site.lon_deg,
						  sc->earth_radius_m, wx->far[f].site.lat_deg,
						  wx->far[f].site.lon_deg, 0.0);
			fx[f] = p.x, fy[f] = p.y;
		}
		for (int i = 0; i < near; i++)
			cs_cloud_layer_blend(&sc->layers[i], noise, -1, wx->nfar, fx, fy);
		for (int f = 0; f < wx->nfar; f++)
			for (int i = 0; i < wx->far[f].nlayers && sc->nlayers < CS_SCENE_MAX_LAYERS; i++) {
				if (wx->far[f].layers[i].coverage <= 0.0)
					continue;
				struct cs_cloud_layer *l = &sc->layers[sc->nlayers++];
				cs_cloud_layer_init(l, &wx->far[f].layers[i], noise,
						    wx->wind_speed_m_s, wx->wind_from_deg,
						    wx->far[f].site.alt_m, t_wind);
				drift_layer(l, wx, time_utc, wx->far[f].site.alt_m);
				cs_cloud_layer_blend(l, noise, f, wx->nfar, fx, fy);
			}
	}
	if (sc->nlayers > 0)
		sc->effects |= CS_FX_CLOUDS;
}

/* The clouds' optical depth from the forecast's own beam (cloudrender
 * --cloud-depth and RADIATION; DESIGN.md had the state's observed
 * radiation for comparing only).  A forecast that
 * sends its radiation says how much of the sun's beam its clouds let
 * through: f = its DNI over the clear sky's, here the scene's own beam
 * through the clear atmosphere in W/m2 (cs_irradiance_at's conversion).
 * The genera's depths (cloud.c) are climatological, and an hour's sheets
 * may be far thinner or thicker: the shared capture's overcast afternoon
 * lets 15 % of the beam through (DNI 122.6 of 798 W/m2 at 13 UTC), where
 * the climatology's altostratus over cumulus let none, and the ground
 * came out at 179 W/m2 against the forecast's 403.  A forecast's
 * radiation scheme counts its beam as a delta-Eddington solver does
 * (Joseph, Wiscombe & Weinman 1976): the share g^2 of the scattering
 * that goes into the forward peak stays in the beam, whose depth is then
 * (1 - g^2) tau (g: the clouds' asymmetry, 0.852 for the scene's two
 * lobes).  So the site's sheets (fitted(): every genus but the heaped
 * ones, whose look is their contrast and whose beam comes through their
 * gaps) take one factor k on their extinction such that the beam's mean,
 * the product over the layers of the mean of exp(-(1 - g^2) k tau) over
 * CS_BEAM_FIT_N^2 points of the layer's base tile (k = 1 for the heaps;
 * tau: the layer's depth toward the sun from the ground under the point,
 * a geometric light march of 32 steps), is f.  Over whole tiles the mean
 * does not depend on where the wind has carried the clouds (the base
 * shape repeats with its tile), and layers at different heights are
 * independent fields (random overlap): the factor follows the forecast
 * smoothly through a series.  Sampled over the stats' 10 km square, where
 * 5 km of drift in 15 minutes brings other cumulus over it, the factor of
 * the capture's overcast afternoon jumped from 0.13 to 0.44 and back to
 * 0.20 in 45 minutes while the DNI changed by a quarter.  Over the capture's
 * 90 hours with the sun 10 deg up or more this took the area GHI's mean
 * log error against the forecast's from -0.14 to -0.03 and its rms from
 * 0.35 to 0.23 (radiation-study's median GHI error 22.5 -> 12.1 %); over
 * the 10 km square, fitting the beam undivided (tau not scaled) gave
 * 0.05 and 0.28, fitting every layer 0.11 and 0.23, but the thinned
 * cumulus washed out into a white veil (cloudrender(1), RADIATION).  The mean
 * falls with k: bisection in log k, within [CS_BEAM_FIT_K_MIN,
 * CS_BEAM_FIT_K_MAX].  The sheets only thin, to let through a beam that
 * the genera's depths withhold, and thicken only where the forecast's
 * beam is below CS_BEAM_FIT_NONE of the clear sky's (none), until theirs
 * is that too: a DNI of 0 bounds the depth from below.  Not
 * fitted: a sun under CS_BEAM_FIT_MIN_ELEVATION_DEG (long slant paths
 * through layers whose extent the forecast does not know), fog (its
 * depth is the forecast's visibility, and it takes the beam first), and
 * a state with far sites (their layers take over from the site's across
 * the area, where the layers are not independent: the product of the
 * means would count a beam that the far clouds withhold).  The forecast's GHI and DHI stay an independent
 * check of the light transport (cloudrender --stats). */
/* The genera whose depth the fit scales: the sheets. */
static int fitted(enum cs_genus g)
{
	switch (g) {
	case CS_CUMULUS:
	case CS_CUMULONIMBUS:
	case CS_ALTOCUMULUS:
	case CS_STRATOCUMULUS:
		return 0;
	default:
		return 1;
	}
}

/* The delta-scaled depth toward the sun of layer l alone from the ground
 * under the points of a CS_BEAM_FIT_N x CS_BEAM_FIT_N grid over the
 * layer's base tile (along and across its wind axis, centred at the
 * origin), into t. */
static void tile_depths(const struct cs_scene *sc, int l, double scale, double *t)
{
	const struct cs_cloud_layer *ly = &sc->layers[l];
	struct cs_render_settings s;
	cs_render_quality("reference", &s);
	s.light_steps = 32;
	s.light_march = CS_LIGHT_GEOMETRIC;
	struct cs_render_stats st;
	memset(&st, 0, sizeof st);
	double across_m = 1.0 / ly->inv_tile, along_m = ly->stretch * across_m;
	double R = sc->earth_radius_m, h = sc->ground_alt_m + 2.0;
	for (int j = 0; j < CS_BEAM_FIT_N; j++)
		for (int i = 0; i < CS_BEAM_FIT_N; i++) {
			double a = ((i + 0.5) / CS_BEAM_FIT_N - 0.5) * along_m;
			double c = ((j + 0.5) / CS_BEAM_FIT_N - 0.5) * across_m;
			double x = a * ly->wind_x - c * ly->wind_y, y = a * ly->wind_y + c * ly->wind_x;
			cs_v3 p = v3(x, y, sqrt((R + h) * (R + h) - x * x - y * y) - R);
			double d = cs_layer_depth(sc, &s, l, p, sc->sun_dir, &st) * scale;
			t[j * CS_BEAM_FIT_N + i] = d > 0.0 ? d : 0.0; /* NaN: none; +inf stays */
		}
}

/* The mean of exp(-k t) over a tile's points. */
static double tile_mean(const double *t, double k)
{
	double sum = 0.0;
	for (int i = 0; i < CS_BEAM_FIT_N * CS_BEAM_FIT_N; i++)
		sum += exp(-k * t[i]);
	return sum / (CS_BEAM_FIT_N * CS_BEAM_FIT_N);
}

/* The beam through every layer, the sheets' depth times k: the product of
 * the layers' means (independent fields at different heights: random
 * overlap), the other layers' product given. */
static double beam_mean(const double *t, int nsheets, double others, double k)
{
	double m = others;
	for (int i = 0; i < nsheets; i++)
		m *= tile_mean(t + (size_t)i * CS_BEAM_FIT_N * CS_BEAM_FIT_N, k);
	return m;
}

/* log k in [lo, hi] whose beam is f (bisection: the beam falls with k). */
static double solve_log_k(const double *t, int nsheets, double others, double f, double lo,
			  double hi)
{
	if (beam_mean(t, nsheets, others, exp(lo)) <= f)
		return lo; /* even the thinnest lets less through */
	if (beam_mean(t, nsheets, others, exp(hi)) >= f)
		return hi; /* even the thickest lets more through */
	for (int it = 0; it < 64 && hi - lo > 1e-9; it++) {
		double mid = 0.5 * (lo + hi);
		if (beam_mean(t, nsheets, others, exp(mid)) > f)
			lo = mid;
		else
			hi = mid;
	}
	return 0.5 * (lo + hi);
}

static double clamp01(double x)
{
	return x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x;
}

static int fit_beam(struct cs_scene *sc, const struct cs_wx *wx)
{
	sc->cloud_depth_scale = 1.0;
	double el_lo = CS_BEAM_FIT_MIN_ELEVATION_DEG - 0.5 * CS_BEAM_FIT_RAMP_DEG;
	if (!wx->observed.has_radiation || sc->nlayers == 0 || wx->nfar > 0 ||
	    wx->visibility_m < CS_FOG_VISIBILITY_M || sc->sun_dir.z <= sin(el_lo * CS_PI / 180.0))
		return CS_OK;
	double el = asin(sc->sun_dir.z) * 180.0 / CS_PI;
	double clear_w_m2 = cs_luminance(sc->sun_illuminance[0], sc->sun_illuminance[1],
					 sc->sun_illuminance[2]) *
			    1000.0 / cs_beam_efficacy_lm_w(el);
	if (!(clear_w_m2 > 0.0))
		return CS_OK;
	double f = wx->observed.dni_w_m2 / clear_w_m2;
	double g = sc->w_forward * sc->g_forward + (1.0 - sc->w_forward) * sc->g_back;
	/* the sheets take the factor, the heaps keep their depth */
	int sheet[CS_SCENE_MAX_LAYERS], nsheets = 0, nothers = 0, other[CS_SCENE_MAX_LAYERS];
	for (int i = 0; i < sc->nlayers; i++) {
		const struct cs_cloud_layer *l = &sc->layers[i];
		if (l->kind != CS_LAYER_CLOUD || !(l->inv_tile > 0.0))
			continue;
		if (fitted(l->genus))
			sheet[nsheets++] = i;
		else
			other[nothers++] = i;
	}
	if (nsheets == 0)
		return CS_OK;
	enum { NP = CS_BEAM_FIT_N * CS_BEAM_FIT_N };
	double *t = malloc((size_t)nsheets * NP * sizeof *t), others = 1.0;
	if (t == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	for (int i = 0; i < nothers; i++) {
		tile_depths(sc, other[i], 1.0 - g * g, t);
		others *= tile_mean(t, 1.0);
	}
	for (int i = 0; i < nsheets; i++)
		tile_depths(sc, sheet[i], 1.0 - g * g, t + (size_t)i * NP);
	/* The sheets thin to let the forecast's beam through, and thicken
	 * only where it has none: a beam weaker than the scene's may be its
	 * clear sky's, not its clouds' (2024-10-06T15Z, a total cover of
	 * 0.09: 671 W/m2 against the scene's 786; its cirrus of 0.32 had
	 * thickened to 3.1 times and whitened the sky, the GHI no nearer).
	 * Between a beam of CS_BEAM_FIT_NONE and twice that the two rules
	 * blend, in log k, and the fit fades out below the elevation
	 * CS_BEAM_FIT_MIN_ELEVATION_DEG over CS_BEAM_FIT_RAMP_DEG: a series
	 * crosses both without a jump (a beam of 7.9 W/m2 under nimbostratus
	 * had kept it, 8.1 thinned it 3.4 times; the sun at 10.07 deg had
	 * thinned the sheets 64 times, at 9.06 not at all). */
	double w = clamp01((f - CS_BEAM_FIT_NONE) / CS_BEAM_FIT_NONE);
	double thin = w > 0.0 ? solve_log_k(t, nsheets, others, f, log(CS_BEAM_FIT_K_MIN), 0.0)
			      : 0.0;
	double none = w < 1.0 ? solve_log_k(t, nsheets, others, CS_BEAM_FIT_NONE, 0.0,
					    log(CS_BEAM_FIT_K_MAX))
			      : 0.0;
	free(t);
	double ramp = clamp01((el - el_lo) / CS_BEAM_FIT_RAMP_DEG);
	double k = exp(ramp * (w * thin + (1.0 - w) * none));
	for (int i = 0; i < nsheets; i++)
		sc->layers[sheet[i]].extinction_per_m *= k;
	sc->cloud_depth_scale = k;
	return CS_OK;
}

/* The light: sun and sky for the date and place, the Moon and stars at
 * night, then what the clouds make of it (shadows, halo, the light under
 * them). */
static int build_light(struct cs_scene *sc, const struct cs_wx *wx, double time_utc,
		       int nthreads)
{
	struct cs_sun sun;
	int rc = cs_sun_position(time_utc, wx->site.lat_deg, wx->site.lon_deg, &sun);
	if (rc != CS_OK)
		return rc;
	cs_v3 sd = cs_sun_direction_enu(&sun);
	sc->sun_dir = v3_norm(sd);
	double turbidity = cs_turbidity_from_visibility(air_visibility_m(wx));
	double sky_t = turbidity < CS_SKY_MIN_TURBIDITY   ? CS_SKY_MIN_TURBIDITY
		       : turbidity < CS_SKY_MAX_TURBIDITY ? turbidity
							  : CS_SKY_MAX_TURBIDITY;
	cs_sky_init_beam(&sc->sky, sd, sky_t, turbidity);
	memcpy(sc->sun_illuminance, sc->sky.sun_illuminance, sizeof sc->sun_illuminance);
	memcpy(sc->ambient_up, sc->sky.ambient_up, sizeof sc->ambient_up);
	memcpy(sc->ambient_down, sc->sky.ambient_down, sizeof sc->ambient_down);
	if (sun.apparent_elevation_deg > -0.8 &&
	    sc->sun_illuminance[1] > 0.0) /* disk still partly above the horizon */
		sc->effects |= CS_FX_SUN;
	cs_scene_night(sc, time_utc, wx->site.lat_deg, wx->site.lon_deg,
		       sun.apparent_elevation_deg, sky_t);
	if ((sc->effects & CS_FX_KEY) && sc->nlayers > 0)
		sc->effects |= CS_FX_CLOUD_SHADOWS;
	for (int i = 0; i < sc->nlayers && (sc->effects & CS_FX_KEY); i++)
		if (sc->layers[i].genus == CS_CIRROSTRATUS)
			sc->effects |= CS_FX_HALO;
	rc = fit_beam(sc, wx);
	if (rc != CS_OK)
		return rc;
	cs_scene_deck_light(sc, nthreads);
	return CS_OK;
}

/* Haze: Koschmieder's extinction 3.912 / visibility at the ground, falling
 * off with a 1.2 km scale height; in fog the haze is that of the air above
 * it, and the fog, from the ground to its top, makes up the rest of 3.912
 * / visibility. */
static void build_air(struct cs_scene *sc, const struct cs_wx *wx)
{
	double vis_air = air_visibility_m(wx);
	sc->haze_scale_height_m = 1200.0;
	sc->haze_beta0_per_m = 3.912 / vis_air * exp(wx->site.alt_m / 1200.0);
	sc->effects |= CS_FX_HAZE;
	if ((sc->effects & CS_FX_KEY) && sc->nlayers > 0 &&
	    sc->sun_dir.z < sin(CS_SHAFTS_MAX_ELEVATION_DEG * CS_PI / 180.0))
		sc->effects |= CS_FX_SHAFTS;
	if (wx->visibility_m < CS_FOG_VISIBILITY_M) {
		sc->fog_beta_per_m = 3.912 / wx->visibility_m - 3.912 / vis_air;
		sc->effects |= CS_FX_FOG;
	}
}

/* Rain and snow: in shafts under the cells of the lowest raining layer, at
 * the rate where it rains (the forecast's mean over the cover); the wet
 * ground darker (water fills the pores and the light scattered inside is
 * absorbed more: Lekner & Dorf 1988, soil and sand at about half their dry
 * reflectance, grass less). */
static void build_precipitation(struct cs_scene *sc, const struct cs_wx *wx)
{
	sc->ground_wet = 1.0;
	if (!(wx->precipitation_mm_h > 0.0))
		return;
	int convective = wx->convective_mm_h > 0.5 * wx->precipitation_mm_h;
	double top = INFINITY, cover = 0.0;
	/* the site's own layers (rain comes from the weather site alone),
	 * not one resting on the ground */
	for (int i = 0; i < sc->nlayers; i++)
		if (sc->layers[i].site < 0 && sc->layers[i].base_m > sc->ground_alt_m + 1.0 &&
		    rains(sc->layers[i].genus, convective) && sc->layers[i].base_m < top) {
			top = sc->layers[i].base_m;
			cover = sc->layers[i].coverage;
			sc->rain_layer = i;
		}
	if (isfinite(top) && top > sc->ground_alt_m && cover > 0.0) {
		sc->rain_top_m = top;
		double f = wx->snow_fraction, rate = wx->precipitation_mm_h / cover;
		sc->rain_extinction_per_m = cs_rain_extinction((1.0 - f) * rate) +
					    cs_snow_extinction(f * rate);
		sc->precip_albedo = 0.9 * (1.0 - f) + 1.0 * f;
		sc->effects |= (f < 1.0 ? CS_FX_RAIN : 0) | (f > 0.0 ? CS_FX_SNOW : 0);
	}
	if (wx->precipitation_mm_h >= 0.1)
		sc->ground_wet = 0.7;
}

int cs_scene_build(struct cs_scene *sc, const struct cs_wx *wx, double time_utc,
		   const struct cs_volume *noise)
{
	return cs_scene_build_threads(sc, wx, time_utc, noise, 1);
}

int cs_scene_build_threads(struct cs_scene *sc, const struct cs_wx *wx, double time_utc,
			   const struct cs_volume *noise, int nthreads)
{
	int rc = cs_wx_validate(wx);
	if (rc != CS_OK)
		return rc;
	memset(sc, 0, sizeof *sc);
	sc->earth_radius_m = CS_EARTH_RADIUS_M;
	sc->ground_alt_m = wx->site.alt_m;
	sc->ground_albedo[0] = 0.10, sc->ground_albedo[1] = 0.14, sc->ground_albedo[2] = 0.07;
	sc->noise = noise;
	/* Water droplets absorb next to nothing in the visible: the imaginary
	 * part of water's refractive index at 550 nm is 2e-9 (Hale & Querry
	 * 1973), which for 10-um droplets (size parameter ~115) gives an
	 * absorption efficiency of ~1e-6 against an extinction efficiency of
	 * 2.  0.99 (a common graphics value) absorbs 86 % of the light a
	 * stratus of optical depth 30 would transmit (the reference
	 * integrator and the adding-doubling table agree: 0.014 instead of
	 * 0.10). */
	sc->albedo = 0.99999;
	sc->g_forward = 0.9, sc->g_back = -0.3, sc->w_forward = 0.96;
	sc->effects = CS_FX_SKY | CS_FX_GROUND;
	build_layers(sc, wx, time_utc, noise);
	rc = build_light(sc, wx, time_utc, nthreads);
	if (rc != CS_OK)
		return rc;
	build_air(sc, wx);
	build_precipitation(sc, wx);
	return cs_scene_fog_light(sc, nthreads);
}
