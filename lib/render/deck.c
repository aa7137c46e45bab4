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

#include <math.h>
#include <string.h>

enum {
	COLS = 16,    /* columns per side of the area */
	COL_STEPS = 24 /* samples through a layer in one column */
};
#define AREA_M 24000.0 /* side of the area: a forecast grid cell or two */
/* Asymmetry of scattering by cloud droplets (r_eff ~ 10 um, visible light):
 * what diffusion through a thick cloud depends on.  The renderer's
 * two-lobe phase shapes the single-scattering look (silver linings); the
 * transport through a deck is the droplets'. */
#define CS_CLOUD_G 0.85

CS_HD double cs_slab_transmittance(double tau, double g)
{
	if (!(tau > 0.0))
		return 1.0;
	double t = 1.0 / (0.9 + 0.6 * (1.0 - g) * tau);
	double direct = exp(-tau);
	t = t < 1.0 ? t : 1.0;
	return t > direct ? t : direct;
}

/* The light on a horizontal plane under a column of optical depth tau:
 * the sun's beam (klux, per unit of e_sun_h) and the diffuse part. */
static void under(const struct cs_deck *d, double tau, const double e_sun_h[3],
		  const double e_sky[3], double *beam, double dif[3])
{
	double T = cs_slab_transmittance(tau, d->g);
	*beam = d->mu0 > 0.0 ? exp(-tau / d->mu0) : 0.0;
	double scat = T - *beam > 0.0 ? T - *beam : 0.0;
	for (int c = 0; c < 3; c++)
		dif[c] = e_sun_h[c] * scat + e_sky[c] * T;
}

/* Layer j lies wholly above layer i. */
static int above(const struct cs_scene *sc, int j, int i)
{
	return j != i && sc->layers[j].base_m >= sc->layers[i].top_m - 1.0;
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

void cs_scene_deck_light(struct cs_scene *sc)
{
	struct cs_deck *d = &sc->deck;
	memset(d, 0, sizeof *d);
	if (sc->nlayers == 0)
		return;
	d->on = 1;
	phase_shares(sc, d->below_share);
	d->g = CS_CLOUD_G;
	int sun = (sc->effects & CS_FX_KEY) && sc->sun_dir.z > 0.0;
	d->mu0 = sun ? sc->sun_dir.z : 0.0;
	double e_sun_h[3], e_sky[3];
	for (int c = 0; c < 3; c++) {
		e_sun_h[c] = sun ? sc->sun_illuminance[c] * d->mu0 : 0.0;
		e_sky[c] = (sc->effects & CS_FX_SKY) ? CS_PI * sc->ambient_up[c] : 0.0;
	}
	int n = sc->nlayers, incloud[CS_SCENE_MAX_LAYERS] = {0};
	double beam_all = 0.0, dif_all[3] = {0.0, 0.0, 0.0};
	for (int jy = 0; jy < COLS; jy++)
		for (int jx = 0; jx < COLS; jx++) {
			double x = ((jx + 0.5) / COLS - 0.5) * AREA_M;
			double y = ((jy + 0.5) / COLS - 0.5) * AREA_M;
			double tau[CS_SCENE_MAX_LAYERS], total = 0.0, beam, dif[3];
			for (int i = 0; i < n; i++) {
				const struct cs_cloud_layer *l = &sc->layers[i];
				tau[i] = cs_cloud_column(l, sc->noise, x, y, l->base_m, l->top_m,
							 COL_STEPS);
				total += tau[i];
				if (tau[i] > 0.05)
					d->tau_in[i] += tau[i], incloud[i]++;
			}
			under(d, total, e_sun_h, e_sky, &beam, dif);
			beam_all += beam;
			for (int c = 0; c < 3; c++)
				dif_all[c] += dif[c];
			for (int i = 0; i < n; i++) { /* what reaches each layer's top */
				double over = 0.0;
				for (int j = 0; j < n; j++)
					over += above(sc, j, i) ? tau[j] : 0.0;
				under(d, over, e_sun_h, e_sky, &beam, dif);
				for (int c = 0; c < 3; c++) {
					d->sun_top[i][c] += e_sun_h[c] * beam;
					d->dif_top[i][c] += dif[c];
				}
			}
		}
	double inv = 1.0 / (COLS * COLS);
	d->direct_below = beam_all * inv;
	for (int c = 0; c < 3; c++) {
		d->sky_below[c] = dif_all[c] * inv / CS_PI;
		d->ground_below[c] = 0.2 * (e_sun_h[c] * d->direct_below + dif_all[c] * inv) / CS_PI;
	}
	for (int i = 0; i < n; i++) {
		d->tau_in[i] = incloud[i] > 0 ? d->tau_in[i] / incloud[i] : 0.0;
		for (int c = 0; c < 3; c++) {
			d->sun_top[i][c] *= inv;
			d->dif_top[i][c] *= inv;
		}
	}
	sc->effects |= CS_FX_DECK;
}
