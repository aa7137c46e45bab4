/* integrator.c - one ray through the scene: where it meets the ground, the
 * intervals it spends in each cloud layer and in the rain, the march
 * through them (single scattering of sun and sky light, multiple-scattering
 * octaves), then the aerial perspective and the background (ground, sky,
 * sun disk) behind what the clouds let through. */
#include "render/march.h"

#include "core/color.h"
#include "core/sphere.h"
#include "terrain/heightfield.h"

#include <math.h>

struct interval {
	double t0, t1;
	unsigned mask; /* layers; 0 = the rain shaft */
};

/* What the ray has gathered so far. */
struct path {
	double L[3];     /* radiance toward the eye of clouds, rain, haze and
			    fog, each seen through what lies in front of it
			    (one sum: the light's parts are never read
			    apart, and a GPU thread holds nine fewer
			    numbers) */
	double T;        /* transmittance to the eye of clouds and rain */
	double Tcloud;   /* through the clouds only */
	double depth;    /* first cloud sample with density, or CS_SKY_DEPTH_M */
	int terminated;  /* T and Tsky fell below the settings' minimum */
	double th;       /* the haze's transmittance to the last haze point */
	double tau_f;    /* the fog's optical depth to it */
	double t_haze;   /* its distance */
	double thh;      /* the haze's transmittance alone to the last haze
			    point: the clear sky's haze light over the
			    stretches so far, in clear air (what the sky's
			    radiance holds of them), is hclear (1 - thh) */
	double Tsky;     /* the sky behind's transmittance: T with the share
			    of the scattering that the forward lobe keeps
			    in the sky's direction left in the beam
			    (cloud_ambient's fwd) */
	/* --source-every 2 */
	double src[4];   /* the last light found, per unit of ss: S and fwd */
	double src_t;    /* its distance */
	int src_layer;   /* its layer */
	int have_src;    /* src may lend to the next sample */
	int pending;     /* a sample waits for the next one's light */
	double pend_w, pend_ss, pend_t; /* its weight T th integ, ss, distance */
};

/* A waiting sample (--source-every 2) without a next neighbour within
 * its layer, or whose ray ended before the next light: its neighbour's
 * before it (at the ray's end its weight is near the ray's least
 * transmittance). */
CS_HD static void pending_prev(struct path *P)
{
	if (P->pending) {
		for (int k = 0; k < 3; k++)
			P->L[k] += P->pend_w * P->pend_ss * P->src[k];
		P->pending = 0;
	}
	P->have_src = 0;
}

/* The path is done: nothing behind it can show, neither through the
 * clouds' transmittance nor through the sky's beam. */
CS_HD static int path_done(const struct path *P, const struct cs_render_settings *s)
{
	return P->T < s->min_transmittance && P->Tsky < s->min_transmittance;
}

/* The per-ray constants of the march. */
struct ray_ctx {
	const struct cs_scene *sc;
	const struct cs_render_settings *s;
	cs_v3 o, d;
	double jitter_u;
	double phase[4]; /* the phase of each multiple-scattering octave */
	double halo[3];  /* the 22-degree halo's phase, per channel, or 0 */
	struct cs_render_stats *st;
	int haze;        /* the scene has haze */
	double h0, dz;   /* the eye's altitude, the ray's vertical component */
	double hclear[3]; /* the haze's light under a clear sky */
	double hsun[3];  /* of the haze's light, the sun's part (clear sky) */
	double hdome[3]; /* and the dome's (under clouds: cs_ground_sky) */
	double fsun[3];  /* the fog's single scattering of the sun's beam
			    above the fog and clouds (albedo x phase x beam) */
	double cphi_sun; /* the azimuth between d and the sun (cosine) */
	double cos_sun;  /* the angle between d and the sun (cosine) */
	double fog_cross; /* where the ray crosses the fog's top, or -1 */
	double tsun;     /* the sun's transmittance through the clouds, area mean */
	double shaft_dt; /* > 0: sample the clouds' shadows this often, m */
	double below_share; /* of the diffuse light in the clouds that scatters
			       toward the eye, the share from below */
	int sky_on;        /* the ray looks up: the sky behind the clouds */
	double eye_alt_m;  /* the eye's altitude */
	/* cs_slab_escape toward the eye through a layer's base or top, and
	 * through a tower's walls (escape_toward_eye) */
	double escape_sheet, escape_wall;
};

/* deck.below_share at the ray's direction of travel toward the eye, whose
 * vertical component is up_out (linear between the table's entries). */
CS_HD static double below_share(const struct cs_deck *d, double up_out)
{
	double u = (up_out + 1.0) * 0.5 * (CS_DECK_SHARES - 1);
	u = u < 0.0 ? 0.0 : u > CS_DECK_SHARES - 1 ? CS_DECK_SHARES - 1 : u;
	int i = (int)u < CS_DECK_SHARES - 1 ? (int)u : CS_DECK_SHARES - 2;
	return d->below_share[i] + (u - i) * (d->below_share[i + 1] - d->below_share[i]);
}

/* One stretch of haze and fog, from the last haze point to distance t,
 * with the sun's transmittance tsun through the clouds over it: their
 * light, seen through the clouds and rain in front of it, and their
 * transmittance.  Where the stretch has fog, haze and fog are lit alike,
 * by the fog's light. */
CS_HD static void haze_step(const struct ray_ctx *c, struct path *P, double t, double tsun)
{
	double th = cs_haze_depth(c->sc, c->h0, c->dz, t);
	double tf = cs_fog_depth(c->sc, c->h0, c->dz, t);
	int fog = tf - P->tau_f > 0.0;
	double tr = exp(-(th + tf));
	/* the sun's beam inside the fog where most of the stretch's fog light
	 * comes from: its middle, or one mean free path into it when it is
	 * longer than two */
	double fog_sun = 1.0, fsrc[3] = {0.0, 0.0, 0.0};
	if (fog) {
		double half = 0.5 * (t - P->t_haze), mfp = 1.0 / c->sc->fog_beta_per_m;
		double tc = P->t_haze + (half < mfp ? half : mfp), alt = c->h0 + c->dz * tc;
		fog_sun = cs_fog_sun_transmittance(c->sc, alt);
		cs_fog_source(c->sc, alt, -c->dz, c->cphi_sun, fsrc);
	}
	/* the haze's transmittance alone, as the clear sky's radiance knows it */
	double trh = tf > 0.0 ? exp(-th) : tr;
	/* under clouds the diffuse light where the stretch is (its middle):
	 * under a thick part of a broken deck it is a third of the area's
	 * mean, which lit the haze there as if through the gaps */
	double dome[3] = {c->hdome[0], c->hdome[1], c->hdome[2]};
	if (!fog && c->sc->deck.on)
		cs_ground_sky(c->sc, v3_mad(c->o, c->d, 0.5 * (P->t_haze + t)), dome);
	for (int k = 0; k < 3; k++) {
		double hz = fog ? c->fsun[k] * tsun * fog_sun + fsrc[k]
				: c->hsun[k] * tsun + dome[k];
		P->L[k] += P->T * hz * (P->th - tr);
	}
	P->th = tr, P->thh = trh, P->tau_f = tf, P->t_haze = t;
}

/* The haze and fog up to distance t: within CS_SHAFTS_RANGE_M in steps of
 * shaft_dt, each lit by the sun as far as the clouds let it through at its
 * middle (crepuscular rays), beyond with the area mean.  The steps are not
 * jittered: neighbouring pixels see the same slices of a shaft, which
 * bands a little where per-pixel jitter would speckle a lot. */
CS_HD static void haze_part(const struct ray_ctx *c, struct path *P, double t)
{
	while (c->shaft_dt > 0.0 && P->t_haze < CS_SHAFTS_RANGE_M && P->t_haze < t) {
		double t1 = P->t_haze + c->shaft_dt;
		t1 = t1 < t ? t1 : t;
		cs_v3 p = v3_mad(c->o, c->d, 0.5 * (P->t_haze + t1));
		/* the full light march: a coarse one (a third of the steps)
		 * drew false shadows through thick stratocumulus */
		double ts = CS_FX_IS(c->sc, CS_FX_KEY) ? exp(-cs_light_depth(c->sc, c->s, p, ~0u, c->st))
							 : 1.0;
		haze_step(c, P, t1, ts);
	}
	if (t > P->t_haze)
		haze_step(c, P, t, c->tsun);
}

/* The haze and fog up to distance t, a stretch ending where the ray
 * crosses the fog's top: a stretch with fog is lit as the fog is
 * (haze_step), one without as the haze, and the haze above a fog
 * is seen through all of it (one stretch from the eye in fog to a cloud
 * far above showed the haze's light, bright toward a low sun, unveiled
 * where the ray met the cloud: the clouds' pattern printed on the fog). */
CS_HD static void haze_to(const struct ray_ctx *c, struct path *P, double t)
{
	if (!c->haze || !(t > P->t_haze))
		return;
	if (CS_BUILT(CS_FX_FOG) && c->fog_cross > P->t_haze && c->fog_cross < t)
		haze_part(c, P, c->fog_cross);
	haze_part(c, P, t);
}

/* The ground is solid: from an eye on it (a camera at exactly ground
 * height, or a hair inside it by rounding, g0 < 0 <= g1) a ray that points
 * down meets it at once, and one that points up leaves it and never meets
 * it. */
CS_HD CS_COLD double cs_find_ground(const struct cs_scene *sc, cs_v3 o, cs_v3 d,
			    int *on_terrain, struct cs_render_stats *st)
{
	double tg = INFINITY, g0, g1;
	cs_v3 up = v3(o.x, o.y, o.z + sc->earth_radius_m);
	*on_terrain = 0;
	if (CS_FX_IS(sc, CS_FX_GROUND) &&
	    cs_sphere_hit(o, d, sc->earth_radius_m, sc->earth_radius_m + sc->ground_alt_m,
			  &g0, &g1) &&
	    g1 >= 0.0 && (g0 >= 0.0 || v3_dot(up, d) < 0.0)) {
		tg = g0 > 0.0 ? g0 : 0.0;
		double hh;
		cs_v3 p = v3_mad(o, d, tg);
		if (CS_BUILT(CS_FX_TERRAIN) && sc->terrain && cs_hfield_height(sc->terrain, p.x, p.y, &hh))
			tg = INFINITY; /* inside the grid the terrain is the ground */
	}
	if (CS_BUILT(CS_FX_TERRAIN) && sc->terrain) {
		double tt;
		unsigned long cells = 0;
		if (cs_hfield_intersect(sc->terrain, o, d, isfinite(tg) ? tg : 1e7, &tt, &cells)) {
			tg = tt;
			*on_terrain = 1;
		}
		st->terrain_cells += cells;
	}
	return tg;
}

/* The intervals of [0, tmax] the ray spends in each layer and in the rain,
 * in order along the ray. */
CS_HD CS_COLD static int gather_intervals(const struct cs_scene *sc, cs_v3 o, cs_v3 d,
				  double tmax, struct interval *iv)
{
	double R = sc->earth_radius_m;
	int n = 0;
	for (int i = 0; i < sc->nlayers; i++) {
		double a[2][2];
		int k = cs_shell_intervals(sc, o, d, R + sc->layers[i].base_m,
					   R + sc->layers[i].top_m, tmax, a);
		for (int j = 0; j < k; j++)
			iv[n++] = (struct interval){a[j][0], a[j][1], 1u << i};
	}
	if (CS_FX_IS(sc, CS_FX_RAIN | CS_FX_SNOW)) {
		double a[2][2];
		int k = cs_shell_intervals(sc, o, d, R + sc->ground_alt_m - 1.0,
					   R + sc->rain_top_m, tmax, a);
		for (int j = 0; j < k; j++)
			iv[n++] = (struct interval){a[j][0], a[j][1], 0u};
	}
	/* insertion sort: n is tiny */
	for (int i = 1; i < n; i++)
		for (int j = i; j > 0 && iv[j].t0 < iv[j - 1].t0; j--) {
			struct interval tmp = iv[j];
			iv[j] = iv[j - 1];
			iv[j - 1] = tmp;
		}
	return n;
}

CS_HD double cs_rain_shaft(const struct cs_scene *sc, double x, double y)
{
	const struct cs_cloud_layer *l = &sc->layers[sc->rain_layer];
	double alt = l->base_m + 0.3 * (l->top_m - l->base_m);
	double e = cs_cloud_extinction(l, sc->noise, x, y, alt) / (0.3 * l->extinction_per_m);
	return e < 1.0 ? e : 1.0;
}

CS_HD void cs_rain_column(double w, double tau_m, double tau_above, const double a[3],
			  double mean[3], double down[3])
{
	/* Eddington's coefficients for isotropic scattering, gamma1 = (7 -
	 * 4 w) / 4 and gamma2 = (4 w - 1) / 4; with u the optical height over
	 * the ground, S = F_up + F_down and D = F_down - F_up:
	 * dS/du = (gamma1 + gamma2) D = p D and dD/du = (gamma1 - gamma2) S
	 * = q S, so S'' = k^2 S with k^2 = p q; at the ground F_up = a
	 * F_down = a f, and at the top F_down = 1 fixes f:
	 * S(u) = f ((1 + a) cosh(k u) + p (1 - a) sinh(k u) / k), and f =
	 * 2 / (2 cosh(k tau) + (p (1 - a) + q (1 + a)) sinh(k tau) / k) */
	w = fmin(fmax(w, 0.0), 1.0); /* (NaN: 0) */
	const double p = 1.5, q = 2.0 * (1.0 - w);
	double k = sqrt(p * q), alb[3];
	for (int c = 0; c < 3; c++) /* (a bright ground's noise takes it past 1) */
		alb[c] = fmin(fmax(a[c], 0.0), 1.0);
	a = alb;
	tau_m = fmin(fmax(tau_m, 0.0), 1e6); /* (NaN: 0; deeper is as dark) */
	double u = fmin(fmax(tau_m - tau_above, 0.0), tau_m);
	if (k * tau_m < 1e-4) { /* (snow, w = 1: k = 0) */
		for (int c = 0; c < 3; c++) {
			double f = 2.0 / (2.0 + (p * (1.0 - a[c]) + q * (1.0 + a[c])) * tau_m);
			mean[c] = 0.5 * f * ((1.0 + a[c]) + p * (1.0 - a[c]) * u);
			down[c] = f;
		}
		return;
	}
	/* with e^(-k tau) factored out of both, so that a deep column
	 * neither overflows nor loses its light to inf / inf */
	double E = exp(-k * tau_m), sh_t = -expm1(-2.0 * k * tau_m) / (2.0 * k);
	double ch_u = 1.0 + exp(-2.0 * k * u), sh_u = -expm1(-2.0 * k * u) / k;
	double d = exp(-k * (tau_m - u));
	for (int c = 0; c < 3; c++) {
		double den = (1.0 + E * E) + (p * (1.0 - a[c]) + q * (1.0 + a[c])) * sh_t;
		down[c] = 2.0 * E / den;
		mean[c] = d * ((1.0 + a[c]) * ch_u + p * (1.0 - a[c]) * sh_u) / (2.0 * den);
	}
}

/* Rain and snow: grey shafts under the raining cells, marched in steps of
 * at most 250 m (at most 48).  The drops scatter isotropically (as the
 * path tracer's do) the mean radiance around them, albedo times it: the
 * light of their column (cs_rain_column, the two-stream solution of the
 * rain at the point's depth in it, over the wet ground), lit at its top
 * by the diffuse light under the clouds where they fall (cs_rain_top_sky:
 * under the thick cells that rain, not the area's mean with its gaps),
 * and toward the ground by the ground's (the field's two planes).
 * Lit by the area's mean, and by all of the light from above, the real
 * hour of rain was 4.0 times the path tracer's picture; by single
 * scattering of the light that reaches the ground, 16 mm/h under
 * nimbostratus was 25 % under it (test_reference). */
CS_HD CS_COLD static void march_rain(const struct ray_ctx *c, const struct interval *iv,
			     struct path *P)
{
	const struct cs_scene *sc = c->sc;
	double len = iv->t1 - iv->t0;
	int ns = (int)ceil(len / 250.0);
	ns = ns < 1 ? 1 : ns > 48 ? 48 : ns;
	double dt = len / ns;
	/* the column's height and the wet ground under it, the ray's own
	 * (its albedo in [0, 1], as cs_rain_column takes it) */
	double top = sc->rain_top_m - sc->ground_alt_m, alb[3], floor_mean[3];
	for (int k = 0; k < 3; k++) {
		alb[k] = sc->ground_albedo[k] * (sc->ground_wet > 0.0 ? sc->ground_wet : 1.0);
		alb[k] = fmin(fmax(alb[k], 0.0), 1.0); /* (NaN: 0) */
		/* the column's mean radiance at the ground per unit of light
		 * coming down there, (1 + a) / 2 */
		floor_mean[k] = 0.5 * (1.0 + alb[k]);
	}
	for (int j = 0; j < ns && !P->terminated; j++) {
		double t = iv->t0 + (j + c->jitter_u) * dt;
		cs_v3 p = v3_mad(c->o, c->d, t);
		double sigma = sc->rain_extinction_per_m * cs_rain_shaft(sc, p.x, p.y);
		c->st->density_samples++;
		if (sigma <= 0.0)
			continue;
		haze_to(c, P, t);
		double sky[3] = {sc->ambient_up[0], sc->ambient_up[1], sc->ambient_up[2]};
		if (sc->deck.on)
			cs_rain_top_sky(sc, p, sky);
		double tr = exp(-sigma * dt), mean[3], down[3];
		double alt = cs_scene_altitude(sc, p);
		cs_rain_column(sc->precip_albedo, sigma * top,
			       sigma * (sc->rain_top_m - alt), alb, mean, down);
		/* with the field's ground plane, the drops' light is their
		 * column's plus, linearly in height from all of it at the
		 * ground to none at the top, what the ground plane's light
		 * (its rays crossed the rain, and saw the gaps around it) adds
		 * to the column's at the ground, (1 + a) / 2 (G - down sky)
		 * (cs_rain_column's mean there is (1 + a) / 2 down): the drops
		 * take the light of the gaps from the side, which a column lit
		 * at its top alone does not count (at high, with the ground
		 * plane, without this and with it: the study's rain-deck-below
		 * -16.6 and -9.1 %, relative MSE 0.032 and 0.017; the capture's
		 * rain hour -0.5 and +2.0 %, with 8 mm/h +21.6 and +24.9 %,
		 * whose deck, not its rain, is too bright: cloudrender(1)).
		 * Bounded: a share of the ground's light, not a factor on the
		 * column's, which grows up a deep column as its mean over its
		 * transmittance does */
		double g[3], add[3] = {0.0, 0.0, 0.0};
		if (sc->deck.on && cs_rain_ground_sky(sc, p, g)) {
			double below = 1.0 - cs_rain_height(sc, alt);
			for (int k = 0; k < 3; k++)
				add[k] = below * floor_mean[k] * (g[k] - down[k] * sky[k]);
		}
		for (int k = 0; k < 3; k++) {
			double J = mean[k] * sky[k] + add[k];
			P->L[k] += P->T * P->th * (1.0 - tr) * sc->precip_albedo * (J > 0.0 ? J : 0.0);
		}
		P->T *= tr;
		P->Tsky *= tr;
		P->terminated = path_done(P, c->s);
	}
}

/* The diffuse light inside layer li at relative height hb (0 base, 1 top)
 * that scatters toward the eye, radiance: clear-sky ambient brightening
 * toward the top without the deck model; with it, the light from above
 * (what reaches the layer's top through the layers above, then through the
 * column tau above the point, by the slab transmittance: deck.c) and from
 * below (the ground's), each hemisphere weighted by how much of it the
 * clouds' forward-peaked phase sends along the ray toward the eye: w_up
 * for the light from below (below_share), the rest for the light from
 * above.  tau_sun is the light march's depth toward the sun.  In a thin
 * layer under the open sky the light from above that the eye gets is
 * mostly the sky behind the layer along the ray, kept in its direction by
 * the phase's forward lobe: with sky_behind (the ray looks up), a share
 * deck.sky_through of the sky's part is not the dome's mean but the sky
 * along the ray (cirrus at dusk before the bright sky near the sun: -15 %
 * -> +6 % against the path tracer), and that light is not added here: the
 * share fwd of the scattering (per unit of it) that
 * keeps it in its direction is left in the sky's beam, whose
 * transmittance Tsky falls by the rest only, so that on a long slant path
 * through the veil the light the lobe carries dims as the beam does (added
 * at full strength at every depth, cirrus at dusk low over the horizon
 * was 11 to 29 % too bright, the study's scene +5.7 %, relative MSE 0.068;
 * now -0.6 %, 0.032).  The dome's mean loses the unscattered share
 * sky_through, the beam keeps the larger, similarity-scaled sky_forward:
 * the lobe, some 25 degrees wide, also brings the sky from above a
 * grazing ray, through shorter paths (losing sky_forward from the dome
 * too left the long view through altocumulus -9 % instead of -6 %, the
 * view from inside stratocumulus +7 % instead of +9 %).  The reference
 * integrator showed the light from above at full weight 1.5 times too
 * bright on cumulus seen from the side.  Over the ground, the light from
 * above holds the ground's return that the cloud reflects back down
 * (deck.ground_gain at the base), fading into the cloud as the diffuse
 * transmittance of the layer's column below the point (its mean in-cloud
 * depth less the depth above).  The sun's diffuse light leaves the cloud
 * toward the eye with the escape function's share for the angle it leaves
 * at, escape (cs_slab_escape; 1 where the eye is inside the layer, which
 * inside says; dz is the ray's vertical component, cos_sun the cosine of
 * its angle to the sun): seen
 * from below at 12 degrees, fair cumulus against the path tracer went from
 * +13 % to -5 %, terrain under broken stratocumulus from +23 % to +2 %.
 * With the light from below comes the cloud's own reflection: the sun's
 * light that reaches the point, sent back up by the column under it (the
 * cumulonimbus's side -21 % -> -11 %, the long view through altocumulus
 * -11 % -> +5 %; from inside stratocumulus the lower half of the view,
 * 43 % too dark, now within 5 %, which leaves its upper half's 35 % too
 * bright in the mean: +2 % -> +22 %).  sun_share: the share of the
 * sun's diffuse light kept (a tower's tilted columns give the rest);
 * sky_td >= 0: the share of the sky's light that reaches the point,
 * instead of the column above's diffuse transmittance; ground_td: the
 * share of the ground's that reaches it by a way other than up through
 * the column under it (a tower's face toward the eye, which sees the
 * ground: 0 else), taken for the towers' share 1 - sun_share where it
 * is more.
 * Through the face the eye sees, the cumulonimbus scenes of the accuracy
 * study against the path tracer at high (the tests/scenes side and low
 * sun views, 128^3 noise; held out, 64^3: the side view at 11:00 UTC,
 * at 15:00 toward the sun, and at 15:00 with 12 % cover), with
 * tilt_light's face toward the eye:
 * relative MSE 0.162, 0.097, 0.066, 0.047, 0.206 -> 0.156, 0.098,
 * 0.060, 0.041, 0.196; mean luminance -20.3, -7.9, -5.0, -10.0, -12.2
 * % -> -18.9, -5.6, -2.9, -8.3, -9.2 %; the sky's face alone: 0.157,
 * 0.099, 0.062, 0.042, 0.198; the ground's light through it without
 * the face's share of the ground (1 - n_z) / 2, 0.153, 0.097, 0.059,
 * 0.039, 0.192, but a face looking up would then take the light of a
 * ground it does not see. */
CS_HD CS_SHARED static void cloud_ambient(const struct cs_scene *sc, int li, double hb,
				double tau, double tau_sun, double w_up, int sky_behind,
				double escape, int inside, double dz, double cos_sun,
				double sun_share, double sky_td, double ground_td,
				const double sun_top[3], const double dif_top[3], double A[3],
				double *fwd)
{
	const struct cs_deck *d = &sc->deck;
	*fwd = 0.0;
	if (!d->on) {
		for (int k = 0; k < 3; k++)
			A[k] = sc->ambient_up[k] * (0.4 + 0.6 * hb) +
			       sc->ambient_down[k] * (1.0 - hb) * 0.5;
		return;
	}
	/* the sun's part through the depth its light has come: the column
	 * above, or the light march's depth as a vertical column (times mu0)
	 * where that is less (light entering a cloud's sunlit side: the
	 * cumulonimbus's side -30 % -> -24 % against the path tracer) */
	double ts = d->mu0 > 0.0 && tau_sun * d->mu0 < tau ? tau_sun * d->mu0 : tau;
	double T = cs_slab_beam_transmittance(ts, d->mu0);
	double Td = sky_td >= 0.0 ? sky_td : cs_slab_diffuse_transmittance(tau);
	double beam = d->mu0 > 0.0 ? exp(-ts / d->mu0) : 0.0;
	double scat = T - beam > 0.0 ? T - beam : 0.0;
	/* a heap of cumulus takes the sun's beam over its cross-section
	 * across the beam, through whichever face the beam meets, not over
	 * its footprint: the sun's light diffused along the light march's
	 * path as through a slab the beam enters square on, the full beam
	 * (1 / mu0 of the horizontal irradiance sun_top), where that is more.
	 * That light leaves by the face away from the sun, toward the eye
	 * with the escape function's share at the angle between the ray and
	 * the beam (cos_sun), at most the share the face toward the eye
	 * gives.  Under a low sun the heaps' walls take most of it: against
	 * the path tracer the silver lining (sun 9 deg up) -10.2 % -> -5.1 %
	 * with the octaves' eccentricity of sample_source, fair cumulus at
	 * noon -3.8 % -> +2.9 %; the silver lining's GHI +22 % with the
	 * face's share alone (the bases seen from below lit as the walls
	 * toward the sun), +8 % (-9 % before).  The cumulonimbus, whose anvil
	 * seen from below was already too bright, went from -13 % to +6 % in
	 * the mean with its relative MSE 0.35 -> 0.45: it keeps the
	 * footprint. */
	double sun_out = scat * escape;
	if (sc->layers[li].genus == CS_CUMULUS && d->mu0 > 0.0 && isfinite(tau_sun)) {
		double side = (cs_slab_beam_transmittance(tau_sun, 1.0) - exp(-tau_sun)) / d->mu0;
		double kd = cs_slab_escape(cos_sun > 0.0 ? cos_sun : 0.0);
		side *= kd < escape ? kd : escape;
		sun_out = side > sun_out ? side : sun_out;
	}
	/* how much of the ground's return reaches the point (none to fetch
	 * in a layer over another, whose gain is 1) */
	const double *gg = d->ground_gain[li];
	double reach = 0.0;
	if (gg[0] > 1.0 || gg[1] > 1.0 || gg[2] > 1.0) {
		double below = d->tau_in[li] - tau;
		reach = cs_slab_diffuse_transmittance(below > 0.0 ? below : 0.0);
	}
	/* the cloud's own reflection from below: of the sun's light that
	 * reaches the point (T), the column under it (the layer's mean
	 * in-cloud depth times the relative height) sends back up
	 * R = 1 - Td, light from below for the phase's share w_up.  The
	 * column under the point is estimated two ways here, measured
	 * against the path tracer: the ground's return through the mean
	 * depth less the local one above, the reflection from the mean
	 * depth's share below; either one for both was worse (for both the
	 * former: inside a deck +23 -> +30 %, the long view +5 -> +8 %; the
	 * latter: terrain under broken cloud +4.8 -> +5.1 %, relative MSE up
	 * on five scenes) */
	double refl = T * (1.0 - cs_slab_diffuse_transmittance(d->tau_in[li] * hb)) * sun_share;
	sun_out *= sun_share;
	/* With the eye inside the layer it sees the cloud's inner light
	 * field, which diffusion makes nearly isotropic, L(mu) = L0 + L1 mu
	 * (mu the cosine of the direction of travel with the downward
	 * vertical): the hemispheres' means are L0 +- 2 L1 / 3, and the
	 * phase function, whose first moment is its asymmetry g, sends
	 * L0 + g L1 mu toward the eye, travelling down by dz (the ray's
	 * vertical component).  The hemispheres' means weighted by the
	 * phase's share of each (w_up), right at a boundary, where the eye
	 * outside sees the light leaving the cloud, made the upper half of
	 * the view from inside a 90 % stratocumulus 20 to 30 % too bright and
	 * the lower half 5 to 15 % too dark against the path tracer (with
	 * this: both within 4 to 19 %, +8.5 % in the mean from +17.5 %; a
	 * horizontal view through altocumulus relative MSE 0.069 -> 0.047) */
	double f = sky_behind ? d->sky_through[li] : 0.0;
	/* the weight of the light from above toward the eye, the rest from
	 * below's: the phase's shares outside, the diffusion form inside,
	 * L0 + g L1 mu = 0.5 (above + below) + 0.75 g (above - below) dz */
	double w_above = inside ? 0.5 + 0.75 * d->g * dz : 1.0 - w_up;
	if (sky_behind) { /* at most all of it: the beam never grows */
		double w = d->sky_forward[li] * (w_above > 0.0 ? w_above : 0.0);
		*fwd = w < 1.0 ? w : 1.0;
	}
	/* the ground's light: up through the column under the point, or in
	 * a tower through the face the eye sees (ground_td) where more, for
	 * the towers' share 1 - sun_share as the sky's (tilt_light) */
	double reach_up = 1.0 - hb;
	reach_up += ground_td > reach_up ? (1.0 - sun_share) * (ground_td - reach_up) : 0.0;
	for (int k = 0; k < 3; k++) {
		double gain = 1.0 + (gg[k] - 1.0) * reach;
		double skyl = (1.0 - f) * dif_top[k] * Td / CS_PI;
		double from_above = (sun_top[k] * sun_out / CS_PI + skyl) * gain;
		double from_below = d->ground_below[k] * reach_up + sun_top[k] * refl * escape / CS_PI;
		double v = w_above * from_above + (1.0 - w_above) * from_below;
		A[k] = v > 0.0 ? v : 0.0;
	}
}

/* The eye is inside layer l. */
CS_HD static int eye_in_layer(const struct ray_ctx *c, const struct cs_cloud_layer *l)
{
	return c->eye_alt_m >= l->base_m && c->eye_alt_m <= l->top_m;
}

/* The escape function's share (cs_slab_escape) of the diffuse light that
 * leaves layer l toward the eye: through its base or top, at the ray's
 * angle to the vertical, or through the walls of a cumulonimbus tower,
 * whose visible half faces the eye at a mean cosine of pi/4 of the ray's
 * horizontal part; 1 with the eye inside the layer, where the light of the
 * points it sees has not yet reached a boundary (nearly isotropic there).
 * The slab transmittance gives the mean over directions: without the
 * factor, cloud bases seen 12 degrees up were 13 to 27 % too bright
 * against the path tracer (those seen 40 degrees up within 5 %, then and
 * now).  The sky's diffuse part keeps the mean: with the factor on it too,
 * fair cumulus came out -11 % and terrain under broken cloud -16 %. */
CS_HD static double escape_toward_eye(const struct ray_ctx *c, const struct cs_cloud_layer *l)
{
	if (eye_in_layer(c, l))
		return 1.0;
	return l->genus == CS_CUMULONIMBUS ? c->escape_wall : c->escape_sheet;
}

/* The share of its tilted columns' light (cs_deck_tilt_source) that a
 * cumulonimbus's point gives.  The columns are slabs without sides; the
 * eye sees a tower's walls, within an optical depth or two of them, where
 * the diffuse light has only the inner hemisphere's (two-stream: none
 * comes in through a free face, so the mean intensity there is about half
 * the inside's).  It is one share for every point, the eye's view from
 * inside a tower too, where no measurement asked for another.  Against the path tracer at high on five cumulonimbus
 * scenes of the 64^3 noise (tests/scenes' two; held out: noon, backlit
 * and 12 % cover) the geometric mean relative MSE was 0.126 with all of
 * the columns' light, 0.089 with 0.75, 0.085 with 0.6, 0.091 with 0.5
 * (0.148 with the octaves and vertical columns before); on three views of
 * the 32^3 noise the mean luminance was +34/+22/+64 % with all of it,
 * -3/-3/+15 % with 0.6, -12/-9/+3 % with 0.5. */
#define TILT_WALL 0.6
/* The same share for the heaps of cumulus, a few tens of optical depths
 * across where a tower is hundreds: chosen with the heaps' share by cover
 * (fog.c, tilt_fields, which has the figures).  On the five cumulus
 * scenes of the study at high, with the share ending at 80 % cover, the
 * mean luminance of the sun behind the eye was -5.0, -3.4 and -1.7 % at
 * 0.6, 0.65 and 0.7, of thin cumulus +2.7, +3.9 and +5.2 %. */
#define HEAP_WALL 0.65

/* The vertical part of the outward normal of layer li's cloud at p: the
 * way its extinction falls, by central differences at p +- HEAP_NORMAL_M
 * (a tower's walls are smooth over that; at +-50 and +-150 m the study's
 * five cumulonimbus scenes measured the same to 2 % in relative MSE;
 * within that of the layer's base or top its height profile tilts it);
 * where it does not change, the face toward the eye (-d).  Its six
 * lookups count as light samples. */
#define HEAP_NORMAL_M 150.0
CS_HD static double heap_normal_z(const struct cs_scene *sc, int li, cs_v3 p, cs_v3 d,
				  struct cs_render_stats *st)
{
	st->light_samples += 6;
	const struct cs_cloud_layer *l = &sc->layers[li];
	const double h = HEAP_NORMAL_M;
	double alt = cs_scene_altitude(sc, p);
	double gx = cs_cloud_extinction(l, sc->noise, p.x + h, p.y, alt) -
		    cs_cloud_extinction(l, sc->noise, p.x - h, p.y, alt);
	double gy = cs_cloud_extinction(l, sc->noise, p.x, p.y + h, alt) -
		    cs_cloud_extinction(l, sc->noise, p.x, p.y - h, alt);
	double gz = cs_cloud_extinction(l, sc->noise, p.x, p.y, alt + h) -
		    cs_cloud_extinction(l, sc->noise, p.x, p.y, alt - h);
	double g = sqrt(gx * gx + gy * gy + gz * gz);
	return g > 0.0 ? -gz / g : -d.z;
}

/* A tower's point p in layer li (a cumulonimbus, or a cumulus whose heaps
 * are lit as towers: cs_tower_share), tau_above under the top and
 * tau_sun from the sun, whose tilted columns give the share ts of its
 * diffuse light (deck.tilt_weight): their light for the eye, into L (ts
 * TILT_WALL of it, HEAP_WALL of a heap's), and the share of the sky's
 * light that reaches it, returned (ts of it by the faces below, the rest
 * through the column above, as cloud_ambient's).  The tower behind the point, away from the
 * sun, is a march of its own (cs_heap_depth).  The sky's light comes in
 * through whichever face lets in the most of it: the top, through the
 * column above, or the face toward the sun or away from it, each through
 * its depth and seeing the share (1 + n_z) / 2 of the sky that a face of
 * outward normal n sees (through the column above alone, the towers were
 * a warm yellow against the path tracer's white: r/g 1.10 against 1.01
 * under a low sun; through the thinnest face whichever way it faced, an
 * anvil's underside, which faces the ground, came out the sky's blue:
 * test_reference), or the face the eye sees, through the tower's depth
 * back toward the eye, its normal the way the extinction falls
 * (heap_normal_z); the ground's share (1 - n_z) / 2 through that face
 * goes to cloud_ambient (*ground_face).  Without that face, the walls
 * away from the sun had only the face away from it, which looks down
 * along the beam (a sun 42 deg up: 16 % of the sky), and the study's
 * tower 16 deg up in the shade was 2.4 kcd/m^2 against the path
 * tracer's 6.2, its light the sky's blue.  The face is an empirical
 * stand-in for the light field near the surface the eye sees, and so
 * depends on where the eye is: for the points it sees, within an
 * optical depth or two of that surface, the face lets in nearly all the
 * light its share of sky and ground sends.  Out of line: the rays that
 * meet no tower do not carry its registers. */
CS_HD CS_SHARED static double tilt_light(const struct ray_ctx *c, cs_v3 p, int li,
					 double tau_above, double tau_sun, double ts, double hb,
					 double L[3], double *ground_face)
{
	const struct cs_scene *sc = c->sc;
	double tau_away = cs_heap_depth(sc, c->s, li, p, v3_scale(sc->sun_dir, -1.0), c->st);
	cs_deck_tilt_source(&sc->deck, tau_sun, tau_away, -c->cos_sun, L);
	double wall = sc->layers[li].genus == CS_CUMULUS ? HEAP_WALL : TILT_WALL;
	for (int k = 0; k < 3; k++)
		L[k] = ts * (L[k] * wall);
	double sz = sc->sun_dir.z;
	double up = cs_slab_diffuse_transmittance(tau_above);
	double sun_face = cs_face_sky_share(sz) * cs_slab_diffuse_transmittance(tau_sun);
	double away_face = cs_face_sky_share(-sz) * cs_slab_diffuse_transmittance(tau_away);
	double td = up > sun_face ? up : sun_face;
	td = away_face > td ? away_face : td;
	/* the face the eye sees, the sky in its upper share and the ground in
	 * its lower (the normal only where the face could let in more than
	 * the other faces, or the column under the point, 1 - hb); a tower's
	 * only: the heaps of cumulus, a few optical depths through, measured
	 * the same without it against the path tracer (the study's five
	 * cumulus scenes at high, 320x180: geometric mean relative MSE
	 * 0.03597 against 0.03591, each bias within 0.1 %), and its march
	 * cost fair cumulus at 1280x720 0.9 s of 3.3 */
	*ground_face = 0.0;
	if (sc->layers[li].genus != CS_CUMULONIMBUS)
		return ts * td + (1.0 - ts) * up;
	double tau_eye = cs_heap_depth(sc, c->s, li, p, v3_scale(c->d, -1.0), c->st);
	double eye_td = cs_slab_diffuse_transmittance(tau_eye);
	if (eye_td > td || eye_td > 1.0 - hb) {
		double sky = cs_face_sky_share(heap_normal_z(sc, li, p, c->d, c->st));
		td = sky * eye_td > td ? sky * eye_td : td;
		*ground_face = (1.0 - sky) * eye_td;
	}
	return ts * td + (1.0 - ts) * up;
}

/* A tower's diffuse light A at p (layer li, as tilt_light's) raised to the
 * towers' diffused light (tower_light.c) where that is more, for the
 * towers' share ts: in luminance, in A's colour (the march's mix of the
 * sky's, the ground's and the sun's light; the field is solved in the
 * green channel).  The light is the diffusion's (P1): the radiance
 * phi / (4 pi) + 3 F.w / (4 pi) in direction w, F = -D grad phi the flux
 * (Fick's law, D = 1 / (3 (1 - g) sigma) of the sample's own extinction
 * sigma = ss, not the lattice's cell mean: a thin sample's flux comes out
 * large and is clamped, on 1 % of the side view's cloud samples, almost
 * none weighted by their extinction), whose scattering toward the eye,
 * along -d, is
 * (phi + 3 g F.(-d)) / (4 pi) (the phase function's first moment g),
 * kept within 0 and 2 phi.  Near a face the flux leaves by, the light
 * that leaves toward the eye is the brighter: a tower's base seen from
 * below.  The gradient: central differences half a lattice cell apart
 * (six lookups, counted as light samples), the vertical one kept within
 * the layer.  Against the path tracer at
 * high (tests/scenes' side view and low sun; held out, 64^3 noise: noon,
 * backlit and 12 % cover) the mean luminance was -18.9, -5.6, -2.9, -8.3
 * and -9.2 % without the field, -11.9, -3.1, -1.3, -6.7 and -5.3 % with
 * its fluence alone, -6.4, 0.0, +0.8, -4.8 and +0.3 % with the flux
 * (relative MSE 0.156, 0.098, 0.060, 0.041, 0.196; 0.111, 0.081, 0.051,
 * 0.035, 0.151; 0.083, 0.070, 0.042, 0.031, 0.110).  For a share ts
 * below 1 (20 to 50 % cover) the light is raised toward the field's by
 * that share: A already mixes the march's model and the towers' columns,
 * so the blend is not a swap of the towers' part alone. */
CS_HD static void tower_diffused(const struct cs_scene *sc, int li, cs_v3 p, double alt, double ts,
				 double ss, double shade, cs_v3 d, double A[3],
				 struct cs_render_stats *st)
{
	const struct cs_cloud_layer *l = &sc->layers[li];
	const struct cs_light_cache *tl = &sc->tower_light[li];
	double phi = cs_cached_depth(l, tl, p.x, p.y, alt);
	double hu = 0.5 * tl->du_m, hv = 0.5 * tl->dv_m, hh = 0.5 * tl->dh_m, ex, ey;
	/* the gradient along the wind's axes (the lattice's), back to east
	 * and north */
	cs_cloud_axes_to_en(l, hu, 0.0, &ex, &ey);
	double ua = (cs_cached_depth(l, tl, p.x + ex, p.y + ey, alt) -
		     cs_cached_depth(l, tl, p.x - ex, p.y - ey, alt)) /
		    (2.0 * hu);
	cs_cloud_axes_to_en(l, 0.0, hv, &ex, &ey);
	double va = (cs_cached_depth(l, tl, p.x + ex, p.y + ey, alt) -
		     cs_cached_depth(l, tl, p.x - ex, p.y - ey, alt)) /
		    (2.0 * hv);
	/* (up and down within the layer: above its top the lookup reads 0,
	 * below its base the base's value) */
	double hi = alt + hh < l->top_m - 1e-3 * hh ? alt + hh : l->top_m - 1e-3 * hh;
	double lo = alt - hh > l->base_m ? alt - hh : l->base_m;
	double gz = hi > lo ? (cs_cached_depth(l, tl, p.x, p.y, hi) -
			       cs_cached_depth(l, tl, p.x, p.y, lo)) /
				      (hi - lo)
			    : 0.0;
	st->light_samples += 6;
	double gx, gy, g = sc->deck.g;
	cs_cloud_axes_to_en(l, ua, va, &gx, &gy);
	double D = 1.0 / (3.0 * (1.0 - g) * (ss > 1e-9 ? ss : 1e-9));
	/* F.(-d) = D grad phi . d */
	double toward = 3.0 * g * D * (gx * d.x + gy * d.y + gz * d.z);
	phi += toward > phi ? phi : toward < -phi ? -phi : toward;
	const double *E = sc->sun_illuminance;
	double y = shade * cs_luminance(E[0], E[1], E[2]) * phi / (4.0 * CS_PI);
	double ya = cs_luminance(A[0], A[1], A[2]);
	if (!(y > ya))
		return;
	y = ya + ts * (y - ya);
	for (int k = 0; k < 3; k++)
		A[k] = ya > 0.0 ? A[k] * (y / ya) : ts * E[k] * phi / (4.0 * CS_PI);
}

/* The light scattered toward the eye per unit length at a cloud sample of
 * scattering coefficient ss: the sun through the light march, with the
 * multiple-scattering octaves (Wrenninge 2013: scattering a^k, extinction
 * b^k, eccentricity c^k, a = b = 0.5), and the diffuse light inside
 * layer li, the one with the most extinction at the sample.  The
 * eccentricity falls as the forward lobe's own convolutions do: light
 * scattered k + 1 times by Henyey-Greenstein lobes of asymmetry g has
 * the lobe of g^(k + 1) (their Legendre moments are g^l, and multiply),
 * so c = g_forward (0.9), not Wrenninge's 0.5, which spread the forward
 * light of the higher orders over the sky: with it the silver lining was
 * -10 % against the path tracer, the view from inside stratocumulus
 * +16 %, with g -5 % and +8.5 %.  *fwd: the part of ss, per metre, that
 * keeps the sky behind the layer in its direction (cloud_ambient), which
 * the sky's beam does not lose. */
CS_HD static void sample_source(const struct ray_ctx *c, cs_v3 p, double alt,
				unsigned mask, int li, double ss, double S[3], double *fwd)
{
	const struct cs_scene *sc = c->sc;
	S[0] = S[1] = S[2] = 0.0;
	*fwd = 0.0;
	double tau_sun = INFINITY, tau_key = -1.0;
	/* a layer with light fields (of more than half cover, or thin for
	 * the beam): its diffuse light, the sun's multiply scattered light
	 * with it, from its light fields, for the
	 * share wf (deck.field_weight), the rest from the octaves and
	 * cloud_ambient (all of it in layers without fields); beside the
	 * fields' share the octaves add the light the beam brings in
	 * through a cell's nearer side (below) */
	int field = sc->deck.on ? sc->deck.field_of[li] : -1;
	double wf = field >= 0 ? sc->deck.field_weight[li] : 0.0;
	/* a cumulonimbus's towers (or a cumulus's heaps, heap_towers): the
	 * sun's multiply scattered light from their tilted columns for the
	 * share ts (cs_tower_share), from the octaves and cloud_ambient for
	 * the rest */
	double ts = CS_BUILT(CS_BUILT_TOWERS) && c->s->ambient ? cs_tower_share(sc, c->s, li) : 0.0;
	/* the optical depth of the layer's column above the point (the
	 * fields' depth, the octaves' share beside them and the model's
	 * shade), with the sky's light (the column cache is built for it):
	 * its volume (--light-march cache), or n samples */
	const struct cs_cloud_layer *l = &sc->layers[li];
	double tau_above = 0.0;
	int n = c->s->light_steps / 2 > 2 ? c->s->light_steps / 2 : 2;
	const struct cs_light_cache *vc = !CS_BUILT(CS_BUILT_LIGHT_MARCH) ||
							  (CS_LIGHT_CACHED(c->s->light_march) &&
							   sc->column_cache[li].depth != NULL)
						  ? &sc->column_cache[li]
						  : NULL;
	if (sc->deck.on && c->s->ambient) {
		if (vc != NULL) {
			tau_above = cs_cached_depth(l, vc, p.x, p.y, alt);
		} else {
			tau_above = cs_cloud_column(l, sc->noise, p.x, p.y, alt, l->top_m, n);
			c->st->light_samples += alt < l->top_m ? (uint64_t)n : 0u;
		}
	}
	if (CS_FX_IS(sc, CS_FX_KEY)) {
		/* (and its part through the layers over li's top) */
		unsigned over = sc->deck.on ? sc->deck.over_mask[li] : 0u;
		double tau = cs_light_depth_over(sc, c->s, p, mask, over, &tau_key, c->st);
		tau_sun = tau;
		/* The octaves: the sun's light scattered a few times near where
		 * it came in.  Beside light fields (the share wf) only what
		 * they lack: the fields' columns take the beam in at their
		 * tops, through the column above the point, tau_above / mu0
		 * (and the layers over li's, tau_key); where the beam comes in
		 * through a nearer side (a cell's wall by a gap: tau less than
		 * that), the octaves add what the shorter way brings more,
		 * e^(-b tau) - e^(-b tau_col), and where it does not, nothing
		 * (a deck's tops, a uniform deck).  The glow of forward
		 * scattered light around the sun seen from under a broken
		 * deck: without it the study's rain-deck-below was -9.1 % at
		 * high against the path tracer, relative MSE 0.0170; with it
		 * -4.1 %, 0.0130 (cloudrender(1), QUALITY).  Without the
		 * sky's light (--no-ambient) the fields are not added, and
		 * tau_above is 0: tau_col is tau_key, under tau, and nothing
		 * is added */
		double tau_col = sc->deck.mu0 > 1e-3 ? tau_above / sc->deck.mu0 + tau_key : INFINITY;
		double w = 0.0, a = 1.0, b = 1.0;
		for (int k = 0; k < (ts < 1.0 ? c->s->ms_octaves : 1); k++) {
			double e = exp(-b * tau), share = e;
			if (k > 0) {
				double more = wf > 0.0 ? e - exp(-b * tau_col) : 0.0;
				share = (1.0 - ts) * ((1.0 - wf) * e + wf * (more > 0.0 ? more : 0.0));
			}
			w += a * share * c->phase[k];
			a *= 0.5;
			b *= 0.5;
		}
		/* in cirrostratus a share of the single scattering goes into
		 * the halo instead of the two lobes */
		int halo = CS_FX_IS(sc, CS_FX_HALO) && sc->layers[li].genus == CS_CIRROSTRATUS;
		for (int k = 0; k < 3; k++) {
			double single = c->phase[0] * exp(-tau);
			double wk = halo ? w - CS_HALO_SHARE * single +
						   CS_HALO_SHARE * c->halo[k] * exp(-tau)
					 : w;
			S[k] += ss * sc->sun_illuminance[k] * wk;
		}
	}
	if (c->s->ambient) {
		double hb = (alt - l->base_m) / (l->top_m - l->base_m), A[3];
		hb = hb < 0.0 ? 0.0 : hb > 1.0 ? 1.0 : hb;
		/* (the local column above the point, tau_above, shades the
		 * light from above, so a base is darker under thick parts) */
		A[0] = A[1] = A[2] = 0.0;
		/* (a tau_sun not finite: a light march lost; no tower's light) */
		ts = isfinite(tau_sun) ? ts : 0.0;
		int towers = ts > 0.0 && sc->tower_light[li].depth != NULL;
		/* Under or inside other layers: the light at the layer's top
		 * over the point, not the area's mean (cs_deck_top_shade), for
		 * the model and the towers' light (r_top, the lattice being
		 * lit by the mean), its key light's part having come through
		 * the layers over it: for the model, the depth through this
		 * one only, tau_own.  A layer's light fields keep the mean: a
		 * deep deck spreads the light that comes in at its top sideways
		 * over about its thickness, and the rain hour's nimbostratus,
		 * shaded by the columns of the altostratus of 30 % over it,
		 * came out 0.32 to 0.59 times the path tracer's light in the
		 * upper blocks of the picture (0.55 to 0.97 with the mean), the
		 * picture's mean -37 % (-19 %). */
		const double *sun_top = sc->deck.sun_top[li], *dif_top = sc->deck.dif_top[li];
		double top_sun[3], top_dif[3], r_top = 1.0, tau_own = tau_sun;
		if (sc->deck.on && sc->deck.over_mask[li] != 0u && (wf < 1.0 || towers)) {
			int cached = !CS_BUILT(CS_BUILT_LIGHT_MARCH) ||
				     CS_LIGHT_CACHED(c->s->light_march);
			r_top = cs_deck_top_shade(sc, li, p.x, p.y, n, cached, tau_key, top_sun,
						  top_dif, &c->st->light_samples);
			sun_top = top_sun, dif_top = top_dif;
			if (tau_key >= 0.0 && isfinite(tau_key))
				tau_own = tau_sun - tau_key > 0.0 ? tau_sun - tau_key : 0.0;
		}
		double L[3], ground_td = 0.0;
		double sky_td = ts > 0.0 ? tilt_light(c, p, li, tau_above, tau_sun, ts, hb, L, &ground_td) : -1.0;
		if (wf < 1.0)
			cloud_ambient(sc, li, hb, tau_above, tau_own, c->below_share,
				      c->sky_on, escape_toward_eye(c, l), eye_in_layer(c, l),
				      c->d.z, c->cos_sun, 1.0 - ts, sky_td, ground_td, sun_top,
				      dif_top, A, fwd);
		if (ts > 0.0)
			for (int k = 0; k < 3; k++)
				A[k] += L[k];
		if (towers)
			tower_diffused(sc, li, p, alt, ts, ss, r_top, c->d, A, c->st);
		if (field >= 0) { /* and the column under it, for its fields */
			double tau_below, F[3];
			if (vc != NULL) { /* the whole column less the part above */
				tau_below = cs_cached_depth(l, vc, p.x, p.y, l->base_m) - tau_above;
				tau_below = tau_below > 0.0 ? tau_below : 0.0;
			} else {
				tau_below = cs_cloud_column(l, sc->noise, p.x, p.y, l->base_m, alt, n);
				c->st->light_samples += alt > l->base_m ? (uint64_t)n : 0u;
			}
			cs_deck_field_source(&sc->deck, field, tau_above, tau_below, -c->d.z,
					     c->cphi_sun, F);
			/* a deck's light that diffuses sideways between its
			 * columns, which the fields' columns lack: the lattice's
			 * ratio (tower_light.c, deck_ratio) scales their light,
			 * not the model's share (1 - wf), whose broken cells
			 * lose light through their sides already: with it
			 * scaled too, nimbostratus of 60 % cover seen 15 deg
			 * up measured +22.1 % against the path tracer, with the
			 * fields' alone -3.6 % (test_reference's views) */
			if (ts == 0.0 && sc->tower_light[li].depth != NULL && cs_deck_lattice(sc, li)) {
				double r = cs_cached_depth(l, &sc->tower_light[li], p.x, p.y, alt);
				c->st->light_samples++;
				for (int k = 0; k < 3; k++)
					F[k] *= r;
			}
			for (int k = 0; k < 3; k++)
				A[k] += wf * (F[k] - A[k]);
			*fwd *= 1.0 - wf;
		}
		for (int k = 0; k < 3; k++)
			S[k] += ss * A[k];
		*fwd *= ss;
	}
}

/* The step of a crossing of the layers in mask: a layer's thickness over
 * the steps, with thick layers (towering cumulonimbus) sampled as if 2.5 km
 * thick so that their dense cores are not undersampled. */
CS_HD static double crossing_step(const struct cs_scene *sc,
				  const struct cs_render_settings *s, unsigned mask)
{
	double dt0 = INFINITY;
	for (int l = 0; l < sc->nlayers; l++)
		if (mask & (1u << l)) {
			double th = sc->layers[l].top_m - sc->layers[l].base_m;
			th = (th < 2500.0 ? th : 2500.0) / s->steps;
			dt0 = th < dt0 ? th : dt0;
		}
	return dt0;
}

/* The growth ratio r of steps dt0, dt0 r, dt0 r^2 ... that cover len in n
 * steps, dt0 (r^n - 1) / (r - 1) = len (len > n dt0, so r > 1), to about
 * 1e-13: Newton's method on the logarithm of that sum in x = r - 1,
 * log(expm1(n log1p(x))) - log(x), which is smooth and nearly straight
 * (the sum itself rises like r^n: Newton on it creeps down by 1/n a step,
 * and r^n - 1 formed directly loses the digits of a small x), kept inside
 * a bracket that each step narrows; a step that leaves it bisects.  About
 * 5 steps a crossing; the bisection took 60 powers (8 % of a render). */
CS_HD static double step_growth(double dt0, double len, int n)
{
	double target = log(len / dt0), lo = 0.0, hi = 1.0;
	while (log(expm1(n * log1p(hi)) / hi) < target && hi < 1e6)
		lo = hi, hi *= 2.0;
	double x = lo > 0.0 ? 0.5 * (lo + hi) : 2.0 * (len / dt0 - n) / ((double)n * n);
	x = x > lo && x < hi ? x : 0.5 * (lo + hi);
	for (int k = 0; k < 100; k++) {
		double l1 = log1p(x), em = expm1(n * l1);
		double f = log(em) - log(x) - target;
		if (f == 0.0)
			return 1.0 + x;
		if (f < 0.0)
			lo = x;
		else
			hi = x;
		/* d/dx: n / (1 + x) e^(n l1) / em - 1 / x */
		double df = n / (1.0 + x) * (em + 1.0) / em - 1.0 / x;
		double next = df > 0.0 ? x - f / df : 0.5 * (lo + hi);
		if (!(next > lo && next < hi))
			next = 0.5 * (lo + hi);
		if (fabs(next - x) <= 1e-13 * x || hi - lo <= 1e-13 * hi)
			return 1.0 + next;
		x = next;
	}
	return 1.0 + hi;
}

/* A waiting sample (--source-every 2) whose crossing of the layers of
 * mask ended before the next light finds its own, after the crossing's
 * march (its point again from its distance): the far edge of a cloud
 * seen against the sun, the brightest part of a silver lining, is often
 * the crossing's last cloudy sample, and the light of the sample before,
 * deeper in, left it up to 17 times too dark.  Found there, where a GPU's
 * rays have left the march's loop together, it costs a GPU nothing that
 * shows (found inside the loop, where each ray takes it at its own step
 * and the others wait, an H200 rendered medium at 46.8 frames/s with it
 * where the next cloudy sample is far, at 40.3 with that and at the
 * ray's end, against 51.4 with this alone).  P->src_layer is still the
 * waiting sample's layer: it waited only in the layer of the light
 * before, and src_layer changes only with a new light, which ends the
 * wait. */
CS_HD static void flush_pending(const struct ray_ctx *c, struct path *P, unsigned mask)
{
	if (P->pending) {
		double S[3], fw;
		cs_v3 p = v3_mad(c->o, c->d, P->pend_t);
		sample_source(c, p, cs_scene_altitude(c->sc, p), mask, P->src_layer, P->pend_ss,
			      S, &fw);
		for (int k = 0; k < 3; k++)
			P->L[k] += P->pend_w * S[k];
		P->pending = 0;
	}
	P->have_src = 0;
}

/* The light of a sample at distance t in a step dt with ss = albedo
 * sigma and weight integ, for --source-every 2, into S and fwd as
 * sample_source gives them: a sample at an odd step of its crossing
 * (odd) right after one whose light was found, in the same layer, waits
 * for the next one's (S = 0 now, its light added then as the mean of the
 * two, per unit of ss; the one before's where the next is far or in
 * another layer or the ray ends first; its own where the crossing does,
 * flush_pending), its fwd the one before's; the light varies slowly along
 * a step, and the density, which draws the cloud's edge, is still looked
 * up at every sample.  The steps' parity, not the count of cloudy
 * samples, decides which samples wait, so that on a GPU the rays of a
 * warp, which take their steps together, find their light at the same
 * steps (counted from each ray's first cloudy sample, their light
 * marches fell on every step of the warp's, and the kernel was slower
 * with it than without). */
CS_HD static void source_every_other(const struct ray_ctx *c, struct path *P, cs_v3 p,
				     double alt, unsigned mask, int amb, int odd, double t,
				     double dt, double ss, double integ, double S[3], double *fwd)
{
	if (odd && P->have_src && !P->pending && P->src_layer == amb && t - P->src_t < 2.5 * dt) {
		P->pending = 1;
		P->pend_w = P->T * P->th * integ;
		P->pend_ss = ss;
		P->pend_t = t;
		P->have_src = 0;
		S[0] = S[1] = S[2] = 0.0;
		*fwd = P->src[3] * ss;
		return;
	}
	/* a waiting sample whose next is far or in another layer: the light
	 * before it */
	if (P->pending && !(amb == P->src_layer && t - P->pend_t < 2.5 * dt))
		pending_prev(P);
	sample_source(c, p, alt, mask, amb, ss, S, fwd);
	for (int k = 0; k < 3; k++) {
		double now = S[k] / ss;
		if (P->pending) /* the mean of its neighbours' */
			P->L[k] += P->pend_w * P->pend_ss * (0.5 * P->src[k] + 0.5 * now);
		P->src[k] = now;
	}
	P->src[3] = *fwd / ss;
	P->pending = 0;
	P->have_src = 1, P->src_t = t, P->src_layer = amb;
}

/* One view sample of a crossing through the layers of mask, at distance
 * t in a step of length dt that starts at ts (an odd step of the
 * crossing: odd), with the extinction sigma there (amb: the layer with
 * the most of it): its light and its transmittance into the path.  1
 * when the ray is then done. */
CS_HD static int march_sample(const struct ray_ctx *c, struct path *P, unsigned mask, int odd,
			      double ts, double t, double dt, cs_v3 p, double alt, double sigma,
			      int amb)
{
	const struct cs_scene *sc = c->sc;
	int naive = c->s->march == CS_MARCH_NAIVE;
	if (P->depth == CS_SKY_DEPTH_M)
		P->depth = ts;
	haze_to(c, P, t);
	double S[3], fwd;
	double tr = exp(-sigma * dt);
	double integ = naive ? dt : -expm1(-sigma * dt) / sigma;
	double ss = sc->albedo * sigma;
	if (CS_BUILT(CS_BUILT_SOURCE_EVERY2) && c->s->source_every == 2 && ss > 0.0)
		source_every_other(c, P, p, alt, mask, amb, odd, t, dt, ss, integ, S, &fwd);
	else
		sample_source(c, p, alt, mask, amb, ss, S, &fwd);
	/* Energy-conserving step (Hillaire 2015): the source is integrated
	 * against the transmittance over the step, S (1 - exp(-sigma dt)) /
	 * sigma, not S dt (which the naive baseline keeps). */
	for (int k = 0; k < 3; k++)
		P->L[k] += P->T * P->th * S[k] * integ;
	P->T *= tr;
	P->Tcloud *= tr;
	P->Tsky *= fwd > 0.0 ? exp(-(sigma - fwd) * dt) : tr;
	if (path_done(P, c->s)) {
		pending_prev(P);
		P->terminated = 1;
		return 1;
	}
	return 0;
}

/* The adaptive march (CS_MARCH_ADAPTIVE): a step [ts, ts + dt] whose
 * sample's optical depth sigma dt exceeds CS_ADAPTIVE_TAU marched again
 * in ceil(sigma dt / TAU) equal parts, at most CS_ADAPTIVE_PARTS, each
 * with its own sample at the ray's jitter within it (the step's sample is
 * not kept): finer where the cloud is dense, where one sample's
 * extinction stands for a step that the eye's light mostly leaves.  Its
 * parts are never coarser than the standard march's steps, but a sheet
 * thinner than a part that the step's sample met can fall between the
 * parts' samples.  1 when the ray is then done.  On the CPU only, in the
 * batches' march: a GPU takes samples one at a time, in the skip march's
 * loop, whose code is as it was (cs_render_settings_gpu_check refuses
 * the adaptive march). */
CS_HD CS_COLD static int march_parts(const struct ray_ctx *c, struct path *P, unsigned mask,
				     double ts, double dt, double sigma)
{
	double m = ceil(sigma * dt / CS_ADAPTIVE_TAU);
	int parts = m < CS_ADAPTIVE_PARTS ? (int)m : CS_ADAPTIVE_PARTS, amb = 0;
	double pdt = dt / parts;
	for (int k = 0; k < parts; k++) {
		double pts = ts + k * pdt, t = pts + c->jitter_u * pdt;
		cs_v3 p = v3_mad(c->o, c->d, t);
		double alt = cs_scene_altitude(c->sc, p);
		double e = cs_extinction_at(c->sc, mask, p, alt, &amb);
		c->st->density_samples++;
		if (e > 0.0 && march_sample(c, P, mask, k & 1, pts, t, pdt, p, alt, e, amb))
			return 1;
	}
	return 0;
}

/* One crossing of [t0, t1] through the layers of mask (overlapping layers
 * are marched together) in steps of the layers' thickness over the
 * settings' steps.  A crossing that would need more than max_steps of
 * them (a long, nearly horizontal one) keeps that step where it starts
 * and lets the steps grow geometrically along the ray to cover it in
 * max_steps: a small cloud around the eye is sampled as finely as a
 * vertical crossing, the distant parts of the layer more coarsely.  The
 * densities of CS_MARCH_BATCH samples at a time are looked up together
 * (a ray that ends inside a batch has looked up a few samples it does not
 * use: they count in the statistics, which count lookups). */
CS_HD static void march_crossing(const struct ray_ctx *c, double t0, double t1,
				 unsigned mask, struct path *P)
{
	const struct cs_scene *sc = c->sc;
	c->st->layer_crossings++;
	int naive = c->s->march == CS_MARCH_NAIVE, skip = c->s->march == CS_MARCH_SKIP;
	int adaptive = CS_MARCH_BATCH > 1 && c->s->march == CS_MARCH_ADAPTIVE;
	double len = t1 - t0, dt0 = crossing_step(sc, c->s, mask);
	double steps = ceil(len / dt0);
	int cap = naive ? 1000000 : c->s->max_steps;
	int ns = steps < 1.0 ? 1 : steps > cap ? cap : (int)steps;
	double growth = steps > cap ? step_growth(dt0, len, ns) : 1.0;
	double grown = growth > 1.0 ? dt0 : len / ns, ts = t0;
	if (skip || CS_MARCH_BATCH == 1) { /* one sample at a time */
		int amb = 0; /* the layer a sample is in: the one with most extinction there */
		int empty_run = 0; /* skip: how many samples in a row found nothing */
		for (int j = 0; j < ns; j++, ts += grown, grown *= growth) {
			/* the last step ends where the crossing does */
			double dt = j == ns - 1 ? t1 - ts : grown;
			if (!(dt > 0.0))
				break;
			double t = naive ? ts : ts + c->jitter_u * dt;
			cs_v3 p = v3_mad(c->o, c->d, t);
			double alt = cs_scene_altitude(sc, p);
			double sigma = cs_extinction_at(sc, mask, p, alt, &amb);
			c->st->density_samples++;
			if (sigma <= 0.0) {
				/* skip: after two empty samples, probe 4 steps
				 * ahead and jump there while that is empty too */
				if (skip && ++empty_run >= 2 && j + 4 < ns - 1 && growth == 1.0) {
					cs_v3 q = v3_mad(c->o, c->d, t + 4.0 * dt);
					int a2;
					c->st->density_samples++;
					if (cs_extinction_at(sc, mask, q, cs_scene_altitude(sc, q), &a2) <= 0.0) {
						j += 3, ts += 3.0 * grown;
					} else
						empty_run = 0;
				}
				continue;
			}
			empty_run = 0;
			if (march_sample(c, P, mask, j & 1, ts, t, dt, p, alt, sigma, amb))
				return;
		}
		return;
	}
	for (int j = 0; j < ns;) {
		double bts[CS_MARCH_BATCH], bt[CS_MARCH_BATCH], bdt[CS_MARCH_BATCH];
		double bx[CS_MARCH_BATCH], by[CS_MARCH_BATCH], bz[CS_MARCH_BATCH], balt[CS_MARCH_BATCH];
		double sigma[CS_MARCH_BATCH];
		int amb[CS_MARCH_BATCH], m = 0, end = 0;
		for (; m < CS_MARCH_BATCH && j < ns; m++, j++, ts += grown, grown *= growth) {
			/* the last step ends where the crossing does */
			double dt = j == ns - 1 ? t1 - ts : grown;
			if (!(dt > 0.0)) {
				end = 1;
				break;
			}
			double t = naive ? ts : ts + c->jitter_u * dt;
			cs_v3 p = v3_mad(c->o, c->d, t);
			bts[m] = ts, bt[m] = t, bdt[m] = dt;
			bx[m] = p.x, by[m] = p.y, bz[m] = p.z;
		}
		cs_altitude_n(m, bx, by, bz, sc->earth_radius_m, balt);
		cs_extinction_at_n(sc, mask, m, bx, by, balt, sigma, amb);
		c->st->density_samples += (uint64_t)m;
		for (int k = 0; k < m; k++) {
			if (!(sigma[k] > 0.0))
				continue;
			if (adaptive && sigma[k] * bdt[k] > CS_ADAPTIVE_TAU
				    ? march_parts(c, P, mask, bts[k], bdt[k], sigma[k])
				    : march_sample(c, P, mask, (j - m + k) & 1, bts[k], bt[k], bdt[k],
						   v3(bx[k], by[k], bz[k]), balt[k], sigma[k], amb[k]))
				return;
		}
		if (end)
			break;
	}
}

/* The march through every interval, in order. */
CS_HD static void march_intervals(const struct ray_ctx *c, struct interval *iv,
				  int n, struct path *P)
{
	for (int i = 0; i < n && !P->terminated; i++) {
		if (iv[i].mask == 0) {
			if (CS_BUILT(CS_FX_RAIN | CS_FX_SNOW))
				march_rain(c, &iv[i], P);
			continue;
		}
		double t0 = iv[i].t0, t1 = iv[i].t1;
		unsigned mask = iv[i].mask;
		while (i + 1 < n && iv[i + 1].mask != 0 && iv[i + 1].t0 < t1) {
			i++;
			mask |= iv[i].mask;
			t1 = iv[i].t1 > t1 ? iv[i].t1 : t1;
		}
		march_crossing(c, t0, t1, mask, P);
		flush_pending(c, P, mask);
	}
}

/* The background behind what the clouds and rain let through: the ground
 * at tg, seen through the haze, or the sky and the sun disk, whose
 * radiance already holds the haze of a clear path (so the haze gathered in
 * front of the clouds counts only for the light they took away); then the
 * ray's result into out. */
CS_HD CS_COLD static void finish_ray(const struct ray_ctx *c, double tg, int on_terrain,
			     struct path *P, struct cs_ray_result *out)
{
	const struct cs_scene *sc = c->sc;
	double bg[3] = {0.0, 0.0, 0.0}, sky[3] = {0.0, 0.0, 0.0};
	if (!P->terminated) {
		if (isfinite(tg)) {
			haze_to(c, P, tg);
			cs_ground_light(sc, c->s, v3_mad(c->o, c->d, tg), c->d, on_terrain, c->st, bg);
			for (int k = 0; k < 3; k++)
				bg[k] *= P->th;
			if (P->depth == CS_SKY_DEPTH_M)
				P->depth = tg;
		} else if (CS_FX_IS(sc, CS_FX_SKY)) {
			/* the fog is not in the sky's radiance: it dims it */
			haze_to(c, P, 1e7);
			double disk[3], stars[3], tf = exp(-P->tau_f);
			cs_scene_sky(sc, c->d, sky);
			cs_scene_disk(sc, c->d, disk);
			cs_scene_stars(sc, c->d, stars);
			for (int k = 0; k < 3; k++) {
				/* the stars are behind the haze too; the clear
				 * air's haze light, which the sky's radiance
				 * holds, is the actual haze's (in L) instead, and the
				 * fog dims what it held of it as the rest (with
				 * it undimmed, fog under a low sun went dark where
				 * it met the sky and bright where a cloud hid it).
				 * The sky's light comes through the clouds with
				 * what their forward lobe kept in its direction
				 * (Tsky), the sun's disk and the stars without */
				bg[k] = disk[k] * tf + stars[k] * P->th;
				sky[k] *= P->Tsky * tf;
				P->L[k] -= P->Tsky * tf * c->hclear[k] * (1.0 - P->thh);
			}
		}
	}
	for (int k = 0; k < 3; k++) {
		double v = P->L[k] + P->T * bg[k] + sky[k];
		out->rgb[k] = isfinite(v) && v > 0.0 ? v : 0.0;
	}
	out->transmittance = P->Tcloud >= 0.0 && P->Tcloud <= 1.0 ? P->Tcloud : 0.0;
	out->depth_m = isfinite(P->depth) ? P->depth : CS_SKY_DEPTH_M;
}

CS_HD void cs_render_ray(const struct cs_scene *sc, const struct cs_render_settings *s,
			 cs_v3 o, cs_v3 d, double jitter_u, struct cs_render_stats *st,
			 struct cs_ray_result *out)
{
	int on_terrain;
	double tg = cs_find_ground(sc, o, d, &on_terrain, st);
	struct interval iv[2 * CS_SCENE_MAX_LAYERS + 2];
	int n = gather_intervals(sc, o, d, isfinite(tg) ? tg : 1e7, iv);

	struct ray_ctx c = {sc, s, o, d, jitter_u, {0.0}, {0.0}, st, 0, 0.0, 0.0,
			    {0.0}, {0.0}, {0.0}, {0.0}, 0.0, 0.0, -1.0, 1.0, 0.0, 0.0, 0, 0.0, 1.0, 1.0};
	c.eye_alt_m = cs_scene_altitude(sc, o);
	c.escape_sheet = cs_slab_escape(fabs(d.z));
	c.escape_wall = cs_slab_escape(0.25 * CS_PI * sqrt(fmax(0.0, 1.0 - d.z * d.z)));
	if (sc->deck.on)
		c.below_share = below_share(&sc->deck, -d.z);
	c.sky_on = sc->deck.on && CS_FX_IS(sc, CS_FX_SKY) && d.z > 0.0 && !isfinite(tg);
	double dh = d.x * d.x + d.y * d.y, sh = sc->sun_dir.x * sc->sun_dir.x +
						   sc->sun_dir.y * sc->sun_dir.y;
	c.cphi_sun = dh > 1e-24 && sh > 1e-24
			     ? (d.x * sc->sun_dir.x + d.y * sc->sun_dir.y) / sqrt(dh * sh)
			     : 1.0;
	double cos_theta = v3_dot(d, sc->sun_dir);
	c.cos_sun = cos_theta;
	/* octave k: eccentricity x g_forward^k (the octaves' comment) */
	for (int k = 0; k < s->ms_octaves; k++)
		c.phase[k] = cs_phase_two_lobe(cos_theta, sc->g_forward, sc->g_back,
					       sc->w_forward, pow(sc->g_forward, k));
	for (int k = 0; k < 3 && CS_FX_IS(sc, CS_FX_HALO); k++)
		c.halo[k] = cs_phase_halo(cos_theta, k);
	c.haze = CS_FX_IS(sc, CS_FX_HAZE) &&
		 (sc->haze_beta0_per_m > 0.0 || (CS_BUILT(CS_FX_FOG) && sc->fog_beta_per_m > 0.0));
	if (c.haze) {
		c.h0 = cs_scene_altitude(sc, o);
		c.dz = v3_dot(d, v3_norm(v3(o.x, o.y, o.z + sc->earth_radius_m)));
		cs_haze_light(sc, d, c.hclear, c.hsun);
		c.tsun = sc->deck.on ? sc->deck.direct_below : 1.0;
		/* the fog's light: its scattered field from the scene's
		 * solution (cs_fog_source) and the sun's beam scattered once,
		 * with the droplets' phase function (octave 0's, the full
		 * one): the glow around the sun */
		int sun_up = CS_FX_IS(sc, CS_FX_KEY) && sc->sun_dir.z > 0.0;
		double fphase = sun_up ? sc->albedo * c.phase[0] : 0.0;
		for (int k = 0; k < 3; k++) {
			c.hdome[k] = c.hclear[k] - c.hsun[k];
			c.fsun[k] = fphase * sc->sun_illuminance[k];
		}
		if (CS_BUILT(CS_FX_FOG) && sc->fog_beta_per_m > 0.0 && fabs(c.dz) > 1e-12) {
			double tc = (sc->fog_top_m - c.h0) / c.dz;
			c.fog_cross = tc > 0.0 ? tc : -1.0;
		}
		if (CS_FX_IS(sc, CS_FX_SHAFTS) && s->haze_steps > 0)
			c.shaft_dt = CS_SHAFTS_RANGE_M / s->haze_steps;
	}
	struct path P = {.L = {0.0, 0.0, 0.0}, .T = 1.0, .Tcloud = 1.0, .depth = CS_SKY_DEPTH_M, .th = 1.0, .thh = 1.0, .Tsky = 1.0};
	march_intervals(&c, iv, n, &P);
	if (P.terminated)
		st->rays_terminated_early++;
	finish_ray(&c, tg, on_terrain, &P, out);
}
