#include "render/scene.h"

#include "core/err.h"
#include "render/sky.h"
#include "astro/sun.h"

#include <math.h>
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

/* The light: sun and sky for the date and place, the Moon and stars at
 * night, then what the clouds make of it (shadows, halo, the light under
 * them). */
static int build_light(struct cs_scene *sc, const struct cs_wx *wx, double time_utc,
		       int nthreads, enum cs_sky_level level)
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
	/* the sky's level: Preetham's own, or a clear-sky model's diffuse
	 * light for the aerosol's optical depth (the turbidity less the air's
	 * own, in units of its Rayleigh depth) */
	double aod550 = (turbidity - 1.0) * CS_RAYLEIGH_DEPTH_550;
	double d_au = sun.distance_au > 0.0 ? sun.distance_au : 1.0;
	sc->sky_level_scale = level == CS_SKY_LEVEL_INEICHEN
				      ? cs_clear_sky_dome_scale(sd, sky_t, turbidity, aod550, wx->site.alt_m,
								CS_SOLAR_CONSTANT_W_M2 / (d_au * d_au))
				      : 1.0;
	cs_sky_scale_dome(&sc->sky, sc->sky_level_scale);
	memcpy(sc->sun_illuminance, sc->sky.sun_illuminance, sizeof sc->sun_illuminance);
	memcpy(sc->ambient_up, sc->sky.ambient_up, sizeof sc->ambient_up);
	memcpy(sc->ambient_down, sc->sky.ambient_down, sizeof sc->ambient_down);
	if (sun.apparent_elevation_deg > -0.8 &&
	    sc->sun_illuminance[1] > 0.0) /* disk still partly above the horizon */
		sc->effects |= CS_FX_SUN;
	cs_scene_night(sc, time_utc, wx->site.lat_deg, wx->site.lon_deg,
		       sun.apparent_elevation_deg, sky_t, level, aod550, wx->site.alt_m);
	if ((sc->effects & CS_FX_KEY) && sc->nlayers > 0)
		sc->effects |= CS_FX_CLOUD_SHADOWS;
	for (int i = 0; i < sc->nlayers && (sc->effects & CS_FX_KEY); i++)
		if (sc->layers[i].genus == CS_CIRROSTRATUS)
			sc->effects |= CS_FX_HALO;
	rc = cs_scene_fit_beam(sc, wx);
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
	return cs_scene_build_opts(sc, wx, time_utc, noise, nthreads, NULL);
}

int cs_scene_build_opts(struct cs_scene *sc, const struct cs_wx *wx, double time_utc,
			const struct cs_volume *noise, int nthreads, const struct cs_scene_opts *opts)
{
	static const struct cs_scene_opts defaults = {CS_SKY_LEVEL_PREETHAM};
	if (opts == NULL)
		opts = &defaults;
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
	build_precipitation(sc, wx); /* (before the deck's light, which sees it) */
	rc = build_light(sc, wx, time_utc, nthreads, opts->sky_level);
	if (rc != CS_OK)
		return rc;
	build_air(sc, wx);
	return cs_scene_fog_light(sc, nthreads);
}
