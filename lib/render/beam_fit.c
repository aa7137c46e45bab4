/* beam_fit.c - the clouds' optical depth from the forecast's own beam
 * (cloudrender --cloud-depth and RADIATION; DESIGN.md had the state's
 * observed radiation for comparing only).  A forecast that sends its
 * radiation says how much of the sun's beam its clouds let through:
 * f = its DNI over the clear sky's, here the scene's own beam through the
 * clear atmosphere in W/m2 (cs_irradiance_from_klux's conversion).
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
 * means would count a beam that the far clouds withhold).  The
 * forecast's GHI and DHI stay an independent check of the light
 * transport (cloudrender --stats). */
#include "render/scene.h"

#include "core/color.h"
#include "core/err.h"
#include "render/march.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

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
			double x, y;
			cs_cloud_axes_to_en(ly, a, c, &x, &y);
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

int cs_scene_fit_beam(struct cs_scene *sc, const struct cs_wx *wx)
{
	sc->cloud_depth_scale = 1.0;
	double el_lo = CS_BEAM_FIT_MIN_ELEVATION_DEG - 0.5 * CS_BEAM_FIT_RAMP_DEG;
	if (!wx->observed.has_radiation || sc->nlayers == 0 || wx->nfar > 0 ||
	    wx->visibility_m < CS_FOG_VISIBILITY_M || sc->sun_dir.z <= sin(el_lo * CS_PI / 180.0))
		return CS_OK;
	/* the clear sky's beam in W/m2, as the radiometry converts it */
	struct cs_irradiance clear;
	cs_irradiance_from_klux(sc, v3(0.0, 0.0, 0.0),
				cs_luminance(sc->sun_illuminance[0], sc->sun_illuminance[1],
					     sc->sun_illuminance[2]),
				0.0, &clear);
	if (!(clear.dni_w_m2 > 0.0))
		return CS_OK;
	double f = wx->observed.dni_w_m2 / clear.dni_w_m2;
	double el = asin(sc->sun_dir.z) * 180.0 / CS_PI;
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
	double w = cs_clamp01((f - CS_BEAM_FIT_NONE) / CS_BEAM_FIT_NONE);
	double thin = w > 0.0 ? solve_log_k(t, nsheets, others, f, log(CS_BEAM_FIT_K_MIN), 0.0)
			      : 0.0;
	double none = w < 1.0 ? solve_log_k(t, nsheets, others, CS_BEAM_FIT_NONE, 0.0,
					    log(CS_BEAM_FIT_K_MAX))
			      : 0.0;
	free(t);
	double ramp = cs_clamp01((el - el_lo) / CS_BEAM_FIT_RAMP_DEG);
	double k = exp(ramp * (w * thin + (1.0 - w) * none));
	for (int i = 0; i < nsheets; i++)
		sc->layers[sheet[i]].extinction_per_m *= k;
	sc->cloud_depth_scale = k;
	return CS_OK;
}
