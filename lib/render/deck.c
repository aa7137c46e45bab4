/* deck.c - light under a cloud deck.  Below an overcast the diffuse light
 * is not the clear sky's blue dome but what the clouds let through: grey,
 * and dimmer the thicker they are.  Thick clouds transmit like 1/tau, not
 * like exp(-tau) (the direct beam is gone, the light diffuses through), so
 * the transmittance is the two-stream similarity form of a plane-parallel
 * slab.  The layers' optical depths are measured on the density field the
 * renderer draws: columns over an area around the site, so broken cloud
 * lets its clear share through.  What comes out lights the ground, the
 * haze and the rain under the clouds, and the inside of the clouds
 * themselves (their bases grey, not blue). */
#include "render/render.h"

#include "core/color.h"
#include "render/cloud.h"
#include "render/march.h"
#include "render/slab_table.h"

#include <math.h>
#include <string.h>

enum {
	COLS = 16,    /* columns per side of the area */
	COL_STEPS = 24 /* samples through a layer in one column */
};
/* The transport through a deck is the droplets' (slab_table.h: asymmetry
 * 0.85, r_eff ~ 10 um in visible light); the renderer's two-lobe phase
 * shapes the single-scattering look (silver linings). */

/* Where tau falls in slab_table.h's optical depths: row *k and the
 * fraction *f toward row k + 1 (linear in log tau); 0 below the first
 * row, 1 above the last (the caller extends those). */
CS_HD static void slab_row(double tau, int *k, double *f)
{
	/* in float: the position between rows needs no more, and a GPU's
	 * double logarithm is long */
	double x = 2.0 * (double)log2f((float)(tau / CS_SLAB_TAU0));
	x = x < 0.0 ? 0.0 : x > CS_SLAB_NTAU - 1 ? CS_SLAB_NTAU - 1 : x;
	int i = (int)x < CS_SLAB_NTAU - 1 ? (int)x : CS_SLAB_NTAU - 2;
	*k = i, *f = x - i;
}

/* A value of a table row extended beyond it: toward 1 at tau 0 (linear
 * below the first depth), like 1 / (tau + 2z) beyond the last (the
 * diffusion limit, 1 / (3 (1 - g) tau / 4 + 1.42), scaled; the table's
 * g, 0.85). */
CS_HD static double slab_extend(double t, double tau)
{
	if (tau < CS_SLAB_TAU0)
		return 1.0 + (t - 1.0) * tau / CS_SLAB_TAU0;
	double z2 = cs_slab_extrapolation_2z(0.85);
	return tau > CS_SLAB_TAU_MAX ? t * (CS_SLAB_TAU_MAX + z2) / (tau + z2) : t;
}

/* The beam's transmittance from table row k, fraction f. */
CS_HD static double slab_beam(int k, double f, double tau, double mu0)
{
	double y = mu0 / 0.05 - 1.0;
	y = y < 0.0 ? 0.0 : y > CS_SLAB_NMU - 1 ? CS_SLAB_NMU - 1 : y;
	int j = (int)y < CS_SLAB_NMU - 1 ? (int)y : CS_SLAB_NMU - 2;
	double g = y - j;
	double a = cs_slab_beam[k][j] + g * (cs_slab_beam[k][j + 1] - cs_slab_beam[k][j]);
	double b = cs_slab_beam[k + 1][j] + g * (cs_slab_beam[k + 1][j + 1] - cs_slab_beam[k + 1][j]);
	double t = slab_extend(a + f * (b - a), tau);
	double direct = mu0 > 0.0 ? exp(-tau / mu0) : 0.0;
	t = t < 1.0 ? t : 1.0;
	return t > direct ? t : direct;
}

CS_HD static double slab_diffuse(int k, double f, double tau)
{
	double t = slab_extend(cs_slab_diffuse[k] + f * (cs_slab_diffuse[k + 1] - cs_slab_diffuse[k]), tau);
	return t < 1.0 ? t : 1.0;
}

CS_HD CS_COLD double cs_slab_beam_transmittance(double tau, double mu0)
{
	if (!(tau > 0.0))
		return 1.0;
	int k;
	double f;
	slab_row(tau, &k, &f);
	return slab_beam(k, f, tau, mu0);
}

CS_HD CS_COLD double cs_slab_diffuse_transmittance(double tau)
{
	if (!(tau > 0.0))
		return 1.0;
	int k;
	double f;
	slab_row(tau, &k, &f);
	return slab_diffuse(k, f, tau);
}

CS_HD double cs_slab_escape(double mu)
{
	mu = mu > 0.0 ? mu < 1.0 ? mu : 1.0 : 0.0;
	return 3.0 / 7.0 * (1.0 + 2.0 * mu);
}

CS_HD double cs_face_sky_share(double nz)
{
	nz = nz > -1.0 ? nz < 1.0 ? nz : 1.0 : -1.0;
	return 0.5 * (1.0 + nz);
}

CS_HD double cs_tower_share(const struct cs_scene *sc, const struct cs_render_settings *s, int li)
{
	if (!sc->deck.on || (sc->layers[li].genus == CS_CUMULUS && !s->heap_towers))
		return 0.0;
	return sc->deck.tilt_weight[li];
}

CS_HD int cs_deck_lattice(const struct cs_scene *sc, int li)
{
	int fi = sc->deck.on ? sc->deck.field_of[li] : -1;
	return fi >= 0 && sc->layers[li].coverage > CS_DECK_FIELD_COVER &&
	       !(sc->deck.tilt_weight[li] > 0.0) &&
	       (1.0 - sc->deck.g) * sc->deck.field_tau[fi][2] >= CS_DECK_LATTICE_TRANSPORT;
}

CS_HD CS_COLD void cs_slab_transmittances(double tau, double mu0, double *beam, double *diffuse)
{
	if (!(tau > 0.0)) {
		*beam = *diffuse = 1.0;
		return;
	}
	int k;
	double f;
	slab_row(tau, &k, &f);
	*beam = slab_beam(k, f, tau, mu0);
	*diffuse = slab_diffuse(k, f, tau);
}

/* The light on a horizontal plane under a column of optical depth tau:
 * the sun's beam (klux, per unit of e_sun_h) and the diffuse part, the
 * sun's through the slab at its elevation, the sky's as diffuse light;
 * with a ground of albedo albedo[c] below (NULL: black), what it sends
 * back up and the cloud's base returns to it, over and over: all the
 * light coming down is E / (1 - albedo R), R = 1 - Td the cloud's
 * reflectance of diffuse light (the geometric series of the reflections
 * between ground and cloud: what brightens an overcast over snow; 8 to
 * 12 % over green land, albedo 0.10 to 0.14, at tau 30). */
/* A slab of optical depth tau under the key light at deck.mu0: the
 * beam's transmittance *beam, the share of the key light it scatters
 * down *scat, the diffuse transmittance *Td. */
CS_HD static void slab_split(const struct cs_deck *d, double tau, double *beam, double *scat,
			     double *Td)
{
	double T;
	cs_slab_transmittances(tau, d->mu0, &T, Td);
	*beam = d->mu0 > 0.0 ? exp(-tau / d->mu0) : 0.0;
	*scat = T - *beam > 0.0 ? T - *beam : 0.0;
}

static void under(const struct cs_deck *d, double tau, const double e_sun_h[3],
		  const double e_sky[3], const double *albedo, double *beam, double dif[3])
{
	double scat, Td;
	slab_split(d, tau, beam, &scat, &Td);
	for (int c = 0; c < 3; c++) {
		dif[c] = e_sun_h[c] * scat + e_sky[c] * Td;
		if (albedo != NULL && tau > 0.0) {
			double gain = 1.0 / (1.0 - albedo[c] * (1.0 - Td));
			dif[c] = (dif[c] + e_sun_h[c] * *beam) * gain - e_sun_h[c] * *beam;
		}
	}
}

/* The reflectance for diffuse light from above of a conservative slab of
 * diffuse transmittance Td over ground of albedo a, the light bounced
 * between the two counted: 1 - Td (1 - a) / (1 - a (1 - Td)). */
static double reflectance_over_ground(double Td, double a)
{
	double q = 1.0 - a * (1.0 - Td);
	return q > 0.0 ? 1.0 - Td * (1.0 - a) / q : 1.0; /* (a white ground under no light) */
}

/* The albedo for diffuse light of a column of rain or snow of optical
 * depth tau over the ground, wet where it rains (cs_rain_column: F_up /
 * F_down at its top, the light sent between the drops and the ground
 * counted); the wet ground alone for tau 0. */
static void column_albedo(const struct cs_scene *sc, double tau, double a[3])
{
	double wet = sc->ground_wet > 0.0 ? sc->ground_wet : 1.0, g[3], mean[3], down[3];
	for (int c = 0; c < 3; c++)
		g[c] = sc->ground_albedo[c] * wet;
	cs_rain_column(sc->precip_albedo, tau, 0.0, g, mean, down);
	for (int c = 0; c < 3; c++)
		a[c] = 2.0 * mean[c] - 1.0;
}

/* What the clouds over (x, y) see under them, for diffuse light: the
 * column of rain or snow that falls there over the ground. */
static void albedo_under(const struct cs_scene *sc, double x, double y, double a[3])
{
	double tau = 0.0;
	if (CS_FX_IS(sc, CS_FX_RAIN | CS_FX_SNOW))
		tau = sc->rain_extinction_per_m * cs_rain_shaft(sc, x, y) *
		      (sc->rain_top_m - sc->ground_alt_m);
	column_albedo(sc, tau, a);
}

/* Layer i's top lies inside another layer of more than
 * CS_DECK_FIELD_COVER (a deck): the light there is that deck's own. */
static int top_in_deck(const struct cs_scene *sc, int i)
{
	double top = sc->layers[i].top_m;
	for (int j = 0; j < sc->nlayers; j++) {
		const struct cs_cloud_layer *l = &sc->layers[j];
		if (j != i && l->base_m < top - 1.0 && l->top_m > top &&
		    l->coverage > CS_DECK_FIELD_COVER) /* (1 m: above's) */
			return 1;
	}
	return 0;
}

/* Layer j lies wholly above layer i. */
static int above(const struct cs_scene *sc, int j, int i)
{
	return j != i && sc->layers[j].base_m >= sc->layers[i].top_m - 1.0;
}

double cs_layer_share_above(const struct cs_scene *sc, int j, int i)
{
	const struct cs_cloud_layer *a = &sc->layers[j], *b = &sc->layers[i];
	if (above(sc, j, i))
		return 1.0;
	if (j == i || !(a->base_m > b->base_m) || !(a->top_m > b->top_m))
		return 0.0;
	return (a->top_m - b->top_m) / (a->top_m - a->base_m);
}

/* Under or inside a broken layer the light at a layer's top is not the
 * area's mean (deck.sun_top, dif_top) but that of the columns over the
 * point: less under a cell, more in a gap (test_reference: cumulus under
 * stratocumulus of 60 %, the mean -38 % in a gap's middle and +164 %
 * under a cell against the path tracer's irradiance, the columns -10 %
 * and -0.6 %; under a deep deck's cell a few per cent of the mean).  The
 * capture's rain hour (2024-10-07T19Z: nimbostratus of 70 %, 834 to
 * 4034 m, over cumulus of 8 %, 650 to 1850 m), against the path tracer
 * at 240x135: the cumulus under the deck's cells, lit by the mean, were
 * 1.3 to 4.5 times its light in blocks of 30 x 22 pixels and stood out
 * white against the dark deck; lit by the columns, 0.8 to 1.2 times.
 * Independent columns (a point's own, not its neighbours': the light
 * that diffuses sideways through the layers over it is not counted).
 * The march reads this for the octaves' model and the towers' light, not
 * for a layer's light fields (integrator.c, sample_source). */
CS_HD double cs_deck_top_shade(const struct cs_scene *sc, int li, double x, double y, int steps,
			       int cached, double tau_key, double sun[3], double dif[3],
			       uint64_t *samples)
{
	const struct cs_deck *d = &sc->deck;
	const struct cs_cloud_layer *l = &sc->layers[li];
	/* the column over the point, for the sky's light */
	double tau_up = 0.0;
	for (int j = 0; j < sc->nlayers; j++) {
		if (!(d->over_mask[li] & (1u << j)))
			continue;
		const struct cs_cloud_layer *o = &sc->layers[j];
		double z0 = o->base_m > l->top_m ? o->base_m : l->top_m;
		if (cached && sc->column_cache[j].depth != NULL) {
			tau_up += cs_cached_depth(o, &sc->column_cache[j], x, y, z0);
		} else {
			tau_up += cs_cloud_column(o, sc->noise, x, y, z0, o->top_m, steps);
			*samples += (uint64_t)steps;
		}
	}
	/* The key light's beam through its slant path (tau_key, times mu0:
	 * the vertical depth of a slab it would cross), and of the light it
	 * scatters the share w = exp(-(1 - g) tau_up) that the scattering's
	 * forward peak keeps near the beam (the transport depth's unscattered
	 * share: a veil's light comes down along the beam, a deep deck's
	 * diffused where its column is) through the slant path too, the rest
	 * through the column over the point.  Against the path tracer, the
	 * columns over the point for both took the capture's fair hour
	 * (cumulus under cirrus of 32 %) from relative MSE 0.0216 to 0.0265,
	 * the slant path for both its rain hour from 0.185 to 0.147; this,
	 * 0.0189 and 0.133. */
	double w = exp(-(1.0 - d->g) * tau_up);
	tau_key = d->mu0 > 0.0 && tau_key >= 0.0 ? tau_key * d->mu0 : tau_up;
	double beam, scat_key, Td_key, beam_up, scat_up, Td_up;
	slab_split(d, tau_key, &beam, &scat_key, &Td_key);
	slab_split(d, tau_up, &beam_up, &scat_up, &Td_up);
	double scat = w * scat_key + (1.0 - w) * scat_up, top[3], least[3];
	for (int c = 0; c < 3; c++) {
		double e_sun_h = sc->sun_illuminance[c] * d->mu0;
		double e_sky = (sc->effects & CS_FX_SKY) ? CS_PI * sc->ambient_up[c] : 0.0;
		sun[c] = e_sun_h * beam;
		dif[c] = e_sun_h * scat + e_sky * Td_up;
		top[c] = d->sun_top[li][c] + d->dif_top[li][c];
		least[c] = 1e-9 * (e_sun_h + e_sky);
	}
	/* (a mean under 1e-9 of the light over all the layers, which the
	 * local light can pass only where the mean's columns missed a gap:
	 * ratio 1, not a quotient that overflows) */
	double mean = cs_luminance(top[0], top[1], top[2]);
	return mean > cs_luminance(least[0], least[1], least[2])
		       ? cs_luminance(sun[0] + dif[0], sun[1] + dif[1], sun[2] + dif[2]) / mean
		       : 1.0;
}

/* The share of the phase function taking light from the lower hemisphere
 * (travelling up) into each direction of travel (deck.below_share): the
 * integral over incoming directions mu_i > 0 and azimuth, by the midpoint
 * rule on 96 x 96 cells (1e-3 for the two-lobe phase). */
static void phase_shares(const struct cs_scene *sc, double share[CS_DECK_SHARES])
{
	enum { NMU = 96, NPHI = 96 };
	for (int k = 0; k < CS_DECK_SHARES; k++) {
		double mo = -1.0 + 2.0 * k / (CS_DECK_SHARES - 1), so = sqrt(fmax(0.0, 1.0 - mo * mo));
		double sum = 0.0;
		for (int i = 0; i < NMU; i++) {
			double mi = (i + 0.5) / NMU, si = sqrt(1.0 - mi * mi);
			for (int j = 0; j < NPHI; j++) {
				double c = mi * mo + si * so * cos((j + 0.5) * 2.0 * CS_PI / NPHI);
				sum += cs_phase_two_lobe(c, sc->g_forward, sc->g_back, sc->w_forward, 1.0);
			}
		}
		share[k] = sum * (1.0 / NMU) * (2.0 * CS_PI / NPHI);
	}
}

void cs_scene_deck_light(struct cs_scene *sc, int nthreads)
{
	struct cs_deck *d = &sc->deck;
	memset(d, 0, sizeof *d);
	if (sc->nlayers == 0) {
		cs_scene_deck_fields(sc, nthreads);
		return;
	}
	d->on = 1;
	phase_shares(sc, d->below_share);
	d->g = sc->w_forward * sc->g_forward + (1.0 - sc->w_forward) * sc->g_back;
	/* the share delta-M truncates, the phase's second moment
	 * (deck.sky_forward) */
	double chi2 = sc->w_forward * sc->g_forward * sc->g_forward +
		      (1.0 - sc->w_forward) * sc->g_back * sc->g_back;
	int sun = (sc->effects & CS_FX_KEY) && sc->sun_dir.z > 0.0;
	d->mu0 = sun ? sc->sun_dir.z : 0.0;
	double e_sun_h[3], e_sky[3];
	for (int c = 0; c < 3; c++) {
		e_sun_h[c] = sun ? sc->sun_illuminance[c] * d->mu0 : 0.0;
		e_sky[c] = (sc->effects & CS_FX_SKY) ? CS_PI * sc->ambient_up[c] : 0.0;
	}
	int n = sc->nlayers, incloud[CS_SCENE_MAX_LAYERS] = {0};
	double beam_all = 0.0, dif_all[3] = {0.0, 0.0, 0.0};
	/* the two mirrors of each layer's top (top_extra): the sums over the
	 * columns of the reflectance for diffuse light of the layers wholly
	 * over it, from below, and of all under its top down to the ground,
	 * from above */
	double r_over[CS_SCENE_MAX_LAYERS] = {0.0}, r_under[CS_SCENE_MAX_LAYERS][3] = {{0.0}};
	for (int jy = 0; jy < COLS; jy++)
		for (int jx = 0; jx < COLS; jx++) {
			double x = ((jx + 0.5) / COLS - 0.5) * CS_DECK_AREA_M;
			double y = ((jy + 0.5) / COLS - 0.5) * CS_DECK_AREA_M;
			double tau[CS_SCENE_MAX_LAYERS], total = 0.0, beam, dif[3];
			for (int i = 0; i < n; i++) {
				const struct cs_cloud_layer *l = &sc->layers[i];
				tau[i] = cs_cloud_column(l, sc->noise, x, y, l->base_m, l->top_m,
							 COL_STEPS);
				total += tau[i];
				if (tau[i] > 0.05) {
					if (incloud[i] == 0 || tau[i] < d->tau_lo[i])
						d->tau_lo[i] = tau[i];
					if (tau[i] > d->tau_hi[i])
						d->tau_hi[i] = tau[i];
					d->tau_in[i] += tau[i], incloud[i]++;
				}
			}
			double alb[3];
			albedo_under(sc, x, y, alb);
			for (int i = 0; i < n; i++)
				for (int c = 0; c < 3 && tau[i] > 0.05; c++)
					d->albedo_in[i][c] += alb[c];
			under(d, total, e_sun_h, e_sky, alb, &beam, dif);
			beam_all += beam;
			for (int c = 0; c < 3; c++)
				dif_all[c] += dif[c];
			for (int i = 0; i < n; i++) { /* what reaches each layer's top */
				double over = 0.0, whole = 0.0; /* whole: the layers wholly over it */
				for (int j = 0; j < n; j++) {
					over += cs_layer_share_above(sc, j, i) * tau[j];
					whole += above(sc, j, i) ? tau[j] : 0.0;
				}
				double scat, Td;
				slab_split(d, over, &beam, &scat, &Td);
				/* the sun's light in the forward peak (sun_lobe): the
				 * beam through the depth delta-M scales, between the
				 * unscattered beam and all of the sun's light that
				 * comes through */
				double kept = d->mu0 > 0.0 ? exp(-(1.0 - chi2) * over / d->mu0) : 0.0;
				kept = kept < beam + scat ? kept : beam + scat;
				kept = kept > beam ? kept : beam;
				r_over[i] += 1.0 - cs_slab_diffuse_transmittance(whole);
				double Td_under = cs_slab_diffuse_transmittance(total - over);
				for (int c = 0; c < 3; c++) {
					d->sun_top[i][c] += e_sun_h[c] * beam;
					d->dif_top[i][c] += e_sun_h[c] * scat + e_sky[c] * Td; /* (under's) */
					d->sun_lobe[i][c] += e_sun_h[c] * kept;
					r_under[i][c] += reflectance_over_ground(Td_under, alb[c]);
				}
			}
		}
	double inv = 1.0 / (COLS * COLS);
	d->direct_below = beam_all * inv;
	for (int c = 0; c < 3; c++) {
		d->sky_below[c] = dif_all[c] * inv / CS_PI;
		d->sky_ground[c] = d->sky_below[c]; /* the frame's dome's with CS_GROUND_SKY_DOME */
		d->ground_below[c] = 0.2 * (e_sun_h[c] * d->direct_below + dif_all[c] * inv) / CS_PI;
	}
	for (int i = 0; i < n; i++) {
		d->tau_in[i] = incloud[i] > 0 ? d->tau_in[i] / incloud[i] : 0.0;
		if (incloud[i] > 0)
			for (int c = 0; c < 3; c++)
				d->albedo_in[i][c] /= incloud[i];
		else /* (no column met it: the wet ground alone) */
			column_albedo(sc, 0.0, d->albedo_in[i]);
		int over_layer = 0, under_layer = 0;
		d->over_mask[i] = 0u;
		for (int j = 0; j < n; j++) {
			over_layer |= above(sc, i, j);
			if (cs_layer_share_above(sc, j, i) > 0.0)
				under_layer = 1, d->over_mask[i] |= 1u << j;
		}
		/* a layer no column met (sparse heaps) has no measured depth:
		 * it is not taken for a thin veil (with tau_in 0 a cumulus
		 * passed a fifth of the sky behind it) */
		int veil = !under_layer && incloud[i] > 0;
		d->sky_through[i] = veil ? sc->w_forward * exp(-d->tau_in[i]) : 0.0;
		/* the forward lobe's weight, dimmed by delta-M's scaled depth */
		d->sky_forward[i] = veil ? sc->w_forward * exp(-(1.0 - chi2) * d->tau_in[i]) : 0.0;
		double R = 1.0 - cs_slab_diffuse_transmittance(d->tau_in[i]);
		for (int c = 0; c < 3; c++)
			d->ground_gain[i][c] = over_layer ? 1.0 : 1.0 / (1.0 - d->albedo_in[i][c] * R);
		int mirrored = !top_in_deck(sc, i);
		for (int c = 0; c < 3; c++) {
			d->sun_top[i][c] *= inv;
			d->dif_top[i][c] *= inv;
			d->sun_lobe[i][c] *= inv;
			/* the light at the top, sent up and back down between
			 * the mirrors over and over: times 1 / (1 - Ro Ru) in
			 * all (the adding method's geometric series; at most
			 * 100 times, where both mirrors are clouds too deep for
			 * any light to pass: 0 times 1 / 0 is no number) */
			double rr = mirrored ? r_over[i] * inv * r_under[i][c] * inv : 0.0;
			rr = rr < 0.99 ? rr : 0.99;
			d->top_extra[i][c] = (d->sun_top[i][c] + d->dif_top[i][c]) * rr / (1.0 - rr);
		}
	}
	sc->effects |= CS_FX_DECK;
	cs_scene_deck_fields(sc, nthreads);
}
