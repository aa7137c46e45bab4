/* tower_light.c - the key light's light deep inside a cumulonimbus's
 * towers: the diffusion approximation of radiative transfer solved over
 * one period of the layer, built once a frame with the light caches
 * (light_cache.c), read by the march (integrator.c, sample_source).
 *
 * A tower is hundreds of optical depths across.  The light that reaches
 * its base and the anvil's underside from the sunlit walls has scattered
 * tens of times (the path tracer: more than half of it after 30
 * scatterings), which no march along one or two directions follows.  In
 * that regime the radiance is nearly isotropic and its mean over
 * directions, the fluence phi, obeys the diffusion equation (Ishimaru,
 * Wave Propagation and Scattering in Random Media, 1978, ch. 9):
 *
 *     -div(D grad phi) + sigma_a phi = Q,    D = 1 / (3 sigma_tr),
 *
 * sigma_tr = (1 - g) sigma_t the transport extinction (the similarity
 * relation: the forward share g of each scattering counted as not
 * scattered), Q the power a volume that the beam (what reaches the
 * layer's top through the layers above, deck.sun_top), attenuated by the
 * same transport depth, gives up to scattering (all of it: the clouds'
 * albedo is 1 to within 1e-5).  The diffusion holds in cloud
 * only: clear air is not part of the problem.  A face of cloud toward
 * clear air, or at the layer's base or top, takes Marshak's condition
 * with the light J (W/m^2) that comes in there: the outward flux is
 * phi_face / 2 - 2 J.  From above comes the sky's diffuse light, from
 * below the ground's (its albedo times the beam that reaches it under
 * the towers, plus the diffuse light), on a wall half of each.  Light
 * that leaves the cloud leaves the problem: the exchange between towers
 * is left out.  Along the wind and across it the field repeats, as the
 * clouds do.
 *
 * Discretised on a lattice of nodes (finite volumes around each node,
 * half a level at the base and the top; a node is cloud where the mean
 * extinction of its volume is more than 0), the system is symmetric
 * positive definite: conjugate gradients with the diagonal as
 * preconditioner solve it.  The source: the beam is followed down a
 * sheared column from each top node (SUB_STEPS samples a level), and the
 * power each step loses is shared out among the nodes around the step's
 * middle (trilinear weights), so that the field receives what the beam
 * loses.  The lattice is struct cs_light_cache's without shear, node
 * (i, j, k) at index (j nu + i) (nh + 1) + k, so that cs_cached_depth
 * reads it; the march reads the fluence and its gradient (the flux's
 * part of the radiance: integrator.c, tower_diffused). */
#include "render/render.h"

#include "core/err.h"
#include "core/pool.h"
#include "render/cloud.h"
#include "render/march.h"

#include <math.h>
#include <stdlib.h>

#define SUB_STEPS 4      /* the beam's samples a level */
#define TAU_CELL_MIN 0.3 /* the least transport depth across a node's cell of cloud */
#define CG_TOL 1e-5      /* relative residual */
#define CG_MAX_ITER 2000 /* (the study's cumulonimbus: 25, 49 and 94 at 800, 400, 200 m) */
/* A key light lower than this lights no field: its beam would cross the
 * flat, periodic layer's 40 km periods many times over (5 deg: 112 km
 * through a cumulonimbus 9.8 km thick; the light march's paths are capped
 * at 150). */
#define SUN_MIN_SIN 0.0871557427 /* sin 5 deg */
/* The most nodes a layer's lattice takes (80 MB of the solver's
 * doubles): a finer cell is coarsened to fit */
#define MAX_NODES 2e7

#define IDX(i, j, k) (((size_t)(j) * (size_t)nu + (size_t)(i)) * (size_t)nk + (size_t)(k))

/* The six neighbours of node (i, j, k): +u, -u, +v, -v, +k, -k (n where
 * there is none, out of the layer). */
static void neighbours(int nu, int nv, int nk, int i, int j, int k, size_t nb[6])
{
	size_t n = (size_t)nu * (size_t)nv * (size_t)nk, m = IDX(i, j, k);
	nb[0] = IDX(i + 1 < nu ? i + 1 : 0, j, k);
	nb[1] = IDX(i > 0 ? i - 1 : nu - 1, j, k);
	nb[2] = IDX(i, j + 1 < nv ? j + 1 : 0, k);
	nb[3] = IDX(i, j > 0 ? j - 1 : nv - 1, k);
	nb[4] = k + 1 < nk ? m + 1 : n;
	nb[5] = k > 0 ? m - 1 : n;
}

/* out = A in: the diagonal, and the conductances to the next node along
 * u, v and k (g[4 m + 3], g[4 m + 0..2]) counted both ways. */
static void apply(const double *g, int nu, int nv, int nk, const double *in, double *out)
{
	size_t n = (size_t)nu * (size_t)nv * (size_t)nk;
	for (size_t m = 0; m < n; m++)
		out[m] = g[4 * m + 3] * in[m];
	for (int j = 0; j < nv; j++)
		for (int i = 0; i < nu; i++)
			for (int k = 0; k < nk; k++) {
				size_t m = IDX(i, j, k);
				size_t u = IDX(i + 1 < nu ? i + 1 : 0, j, k);
				size_t v = IDX(i, j + 1 < nv ? j + 1 : 0, k);
				out[m] -= g[4 * m + 0] * in[u] + g[4 * m + 1] * in[v];
				out[u] -= g[4 * m + 0] * in[m];
				out[v] -= g[4 * m + 1] * in[m];
				if (k + 1 < nk) {
					out[m] -= g[4 * m + 2] * in[m + 1];
					out[m + 1] -= g[4 * m + 2] * in[m];
				}
			}
}

/* The light coming in from below under column (i, j): ground_in's, or
 * j_in[1] everywhere. */
static double light_up(const double j_in[2], const double *ground_in, int nu, int i, int j)
{
	return ground_in != NULL ? ground_in[(size_t)j * (size_t)nu + (size_t)i] : j_in[1];
}

/* (render.h) */
int cs_diffusion_solve(int nu, int nv, int nk, double du_m, double dv_m, double dh_m,
		       const float *sigma_tr, const float *sigma_a, const double *source,
		       const double j_in[2], const double *ground_in, float *phi, int *iterations)
{
	size_t n = (size_t)nu * (size_t)nv * (size_t)nk;
	double *buf = calloc(6 * n, sizeof *buf), *g = calloc(4 * n, sizeof *g);
	if (buf == NULL || g == NULL) {
		free(buf);
		free(g);
		return cs_error(CS_ENOMEM, "out of memory for the towers' light (%zu nodes)", n);
	}
	double *x = buf, *r = buf + n, *z = buf + 2 * n, *p = buf + 3 * n, *q = buf + 4 * n;
	double *b = buf + 5 * n;
	/* Between two nodes of cloud the conductance of the face, D (the
	 * harmonic mean: two resistances in series) times its area over the
	 * distance.  A face toward clear air, half the nodes' distance d / 2
	 * away: the flux D (phi - phi_f) / (d / 2) through it is Marshak's
	 * phi_f / 2 - 2 J, so a / (2 a + 1) (phi - 4 J) an area, a = 2 D / d:
	 * the conductance a / (2 a + 1) to the fluence 4 J of the light
	 * coming in; at the layer's base and top, where the node is, 1/2. */
	for (int j = 0; j < nv; j++)
		for (int i = 0; i < nu; i++)
			for (int k = 0; k < nk; k++) {
				size_t m = IDX(i, j, k), nb[6];
				if (!(sigma_tr[m] > 0.0)) {
					g[4 * m + 3] = 1.0; /* clear: no unknown (phi 0 here) */
					continue;
				}
				neighbours(nu, nv, nk, i, j, k, nb);
				double h = k == 0 || k == nk - 1 ? 0.5 : 1.0; /* the volume's height */
				double D = 1.0 / (3.0 * sigma_tr[m]);
				double up = light_up(j_in, ground_in, nu, i, j);
				double wall = 0.5 * (j_in[0] + up);
				double area[6] = {dv_m * dh_m * h, dv_m * dh_m * h, du_m * dh_m * h,
						  du_m * dh_m * h, du_m * dv_m,      du_m * dv_m};
				double dist[6] = {du_m, du_m, dv_m, dv_m, dh_m, dh_m};
				double J[6] = {wall, wall, wall, wall, j_in[0], up};
				double diag = sigma_a[m] * du_m * dv_m * dh_m * h;
				for (int f = 0; f < 6; f++) {
					if (nb[f] < n && sigma_tr[nb[f]] > 0.0) {
						double Dn = 1.0 / (3.0 * sigma_tr[nb[f]]);
						double c = area[f] * 2.0 * D * Dn / (D + Dn) / dist[f];
						diag += c;
						if (f % 2 == 0)
							g[4 * m + (size_t)f / 2] = c;
					} else {
						double a = 2.0 * D / dist[f];
						double c = area[f] * (nb[f] < n ? a / (2.0 * a + 1.0) : 0.5);
						diag += c;
						b[m] += c * 4.0 * J[f];
					}
				}
				g[4 * m + 3] = diag;
				b[m] += source[m];
			}
	double bb = 0.0, rz = 0.0;
	for (size_t m = 0; m < n; m++) {
		r[m] = b[m];
		z[m] = r[m] / g[4 * m + 3];
		p[m] = z[m];
		bb += b[m] * b[m];
		rz += r[m] * z[m];
	}
	int it = 0;
	for (double rr = bb; it < CG_MAX_ITER && bb > 0.0 && rr > CG_TOL * CG_TOL * bb; it++) {
		apply(g, nu, nv, nk, p, q);
		double pq = 0.0, rz1 = 0.0;
		for (size_t m = 0; m < n; m++)
			pq += p[m] * q[m];
		double alpha = rz / pq;
		rr = 0.0;
		for (size_t m = 0; m < n; m++) {
			x[m] += alpha * p[m];
			r[m] -= alpha * q[m];
			z[m] = r[m] / g[4 * m + 3];
			rz1 += r[m] * z[m];
			rr += r[m] * r[m];
		}
		double beta = rz1 / rz;
		rz = rz1;
		for (size_t m = 0; m < n; m++)
			p[m] = z[m] + beta * p[m];
	}
	/* a clear node: its cloud neighbours' mean, so that a sample of
	 * cloud between nodes reads the cloud's light; with none, the light
	 * around, 2 (J_down + J_up) (each hemisphere's radiance J / pi over
	 * 2 pi sr) */
	for (int j = 0; j < nv; j++)
		for (int i = 0; i < nu; i++)
			for (int k = 0; k < nk; k++) {
				size_t m = IDX(i, j, k), nb[6];
				if (sigma_tr[m] > 0.0) {
					phi[m] = (float)(x[m] > 0.0 ? x[m] : 0.0);
					continue;
				}
				neighbours(nu, nv, nk, i, j, k, nb);
				double sum = 0.0;
				int cnt = 0;
				for (int f = 0; f < 6; f++)
					if (nb[f] < n && sigma_tr[nb[f]] > 0.0) {
						sum += x[nb[f]] > 0.0 ? x[nb[f]] : 0.0;
						cnt++;
					}
				phi[m] = (float)(cnt > 0 ? sum / cnt
							 : 2.0 * (j_in[0] + light_up(j_in, ground_in, nu, i, j)));
			}
	*iterations = it;
	free(buf);
	free(g);
	return CS_OK;
}

/* The wrapped index along an axis of n. */
static int wrap(long i, int n)
{
	long w = i % n;
	return (int)(w < 0 ? w + n : w);
}

/* Shares e among the 8 nodes around fractional position (fu, fv, fk),
 * only those of cloud (st > 0), by their trilinear weights; none: lost
 * (the light leaves into clear air). */
static void deposit(double *src, const float *st, int nu, int nv, int nk, double fu, double fv,
		    double fk, double e)
{
	double iu = floor(fu), iv = floor(fv);
	double a = fu - iu, b = fv - iv;
	long k0 = (long)floor(fk);
	k0 = k0 < 0 ? 0 : k0 > nk - 2 ? nk - 2 : k0;
	double c = fk - (double)k0;
	c = c < 0.0 ? 0.0 : c > 1.0 ? 1.0 : c;
	size_t m[8];
	double w[8], sum = 0.0;
	for (int s = 0; s < 8; s++) {
		int di = s & 1, dj = (s >> 1) & 1, dk = s >> 2;
		m[s] = IDX(wrap((long)iu + di, nu), wrap((long)iv + dj, nv), k0 + dk);
		w[s] = (di ? a : 1.0 - a) * (dj ? b : 1.0 - b) * (dk ? c : 1.0 - c);
		w[s] = st[m[s]] > 0.0 ? w[s] : 0.0;
		sum += w[s];
	}
	for (int s = 0; s < 8 && sum > 0.0; s++)
		src[m[s]] += e * w[s] / sum;
}

/* Adds v into the 4 columns around (fu, fv) of map T by their bilinear
 * weights, and the weights into wsum. */
static void splat_columns(double *T, double *wsum, int nu, int nv, double fu, double fv, double v)
{
	double iu = floor(fu), iv = floor(fv), a = fu - iu, b = fv - iv;
	for (int s = 0; s < 4; s++) {
		int di = s & 1, dj = s >> 1;
		size_t m = (size_t)wrap((long)iv + dj, nv) * (size_t)nu + (size_t)wrap((long)iu + di, nu);
		double w = (di ? a : 1.0 - a) * (dj ? b : 1.0 - b);
		T[m] += w * v;
		wsum[m] += w;
	}
}

int cs_tower_light_wanted(const struct cs_scene *sc, const struct cs_render_settings *s)
{
	if (!(s->tower_cell_m > 0.0) || !s->ambient || !sc->deck.on || !(sc->effects & CS_FX_KEY) ||
	    !(sc->sun_dir.z >= SUN_MIN_SIN))
		return 0;
	for (int i = 0; i < sc->nlayers; i++)
		if (sc->deck.tilt_weight[i] > 0.0)
			return 1;
	return 0;
}

struct extinction_job {
	const struct cs_scene *sc;
	const struct cs_cloud_layer *l;
	int nu, nk;
	double du, dv, dh, one_minus_g;
	float *st, *sa;
};

/* Row j of the lattice: each node's extinction, the mean of 8 points
 * around it (inside the layer), as transport extinction (st, at least
 * TAU_CELL_MIN across its cell where there is cloud; 0 where none) and
 * absorption (sa). */
static void extinction_row(void *user, int j, int worker)
{
	(void)worker;
	const struct extinction_job *job = user;
	const struct cs_cloud_layer *l = job->l;
	int nu = job->nu, nk = job->nk, nh = nk - 1;
	double du = job->du, dv = job->dv, dh = job->dh;
	double least = du < dv ? du : dv;
	least = least < dh ? least : dh;
	for (int i = 0; i < nu; i++)
		for (int k = 0; k < nk; k++) {
			double xyz[3 * 8], e[8], mean = 0.0;
			for (int s = 0; s < 8; s++) {
				double a = (i + ((s & 1) ? 0.25 : -0.25)) * du + l->offset_along_m;
				double c = (j + ((s & 2) ? 0.25 : -0.25)) * dv + l->offset_across_m;
				double kk = k + ((s & 4) ? 0.25 : -0.25);
				kk = kk < 0.0 ? 0.25 : kk > nh ? nh - 0.25 : kk;
				cs_cloud_axes_to_en(l, a, c, &xyz[3 * s], &xyz[3 * s + 1]);
				xyz[3 * s + 2] = l->base_m + kk * dh;
			}
			cs_render_extinction(l, job->sc->noise, 8, xyz, e);
			for (int s = 0; s < 8; s++)
				mean += e[s] / 8.0;
			size_t m = IDX(i, j, k);
			double tr = job->one_minus_g * mean, lo = TAU_CELL_MIN / least;
			job->st[m] = (float)(mean > 0.0 ? (tr > lo ? tr : lo) : 0.0);
			job->sa[m] = (float)((1.0 - job->sc->albedo) * mean);
		}
}

struct beam_job {
	const struct cs_scene *sc;
	const struct cs_cloud_layer *l;
	int nu, steps;
	double du, dv, step, shu, shv; /* step: a sample's height; shear per metre of it */
	float *ext;                    /* [(j nu + i) steps + s], s down from the top */
};

/* Row j of the beam's columns: the extinction at each step's middle,
 * down from the layer's top along the key light's direction, in batches
 * of BEAM_BATCH points. */
#define BEAM_BATCH 64
static void beam_row(void *user, int j, int worker)
{
	(void)worker;
	const struct beam_job *job = user;
	const struct cs_cloud_layer *l = job->l;
	double xyz[3 * BEAM_BATCH], e[BEAM_BATCH];
	for (int i = 0; i < job->nu; i++) {
		float *out = job->ext + ((size_t)j * (size_t)job->nu + (size_t)i) * (size_t)job->steps;
		for (int s0 = 0; s0 < job->steps; s0 += BEAM_BATCH) {
			int cnt = job->steps - s0 < BEAM_BATCH ? job->steps - s0 : BEAM_BATCH;
			for (int q = 0; q < cnt; q++) {
				double down = (s0 + q + 0.5) * job->step;
				double a = i * job->du - down * job->shu + l->offset_along_m;
				double c = j * job->dv - down * job->shv + l->offset_across_m;
				cs_cloud_axes_to_en(l, a, c, &xyz[3 * q], &xyz[3 * q + 1]);
				xyz[3 * q + 2] = l->top_m - down;
			}
			cs_render_extinction(l, job->sc->noise, cnt, xyz, e);
			for (int q = 0; q < cnt; q++)
				out[s0 + q] = (float)e[q];
		}
	}
}

/* Layer l's field into *out (none where the layer has no periods or is
 * far weather): the lattice, the nodes' extinction, the beam's source,
 * the light coming in, the solve. */
static int build_layer(const struct cs_scene *sc, int li, double cell_m, int nthreads,
		       struct cs_light_cache *out, uint64_t *evaluations)
{
	const struct cs_cloud_layer *l = &sc->layers[li];
	*out = (struct cs_light_cache){0};
	double pa, pc, th = l->top_m - l->base_m;
	if (l->nfar > 0 || !(l->coverage > 0.0) || !(th > 0.0) || !cs_cloud_periods(l, &pa, &pc))
		return CS_OK;
	/* the lattice, its cell grown by 1 % at a time until it fits */
	double least = cbrt(pa * pc * th / MAX_NODES);
	cell_m = cell_m > least ? cell_m : least;
	int nh, nk, nu, nv;
	for (;;) {
		nh = (int)ceil(th / cell_m);
		nh = nh < 4 ? 4 : nh > 256 ? 256 : nh;
		nk = nh + 1, nu = (int)ceil(pa / cell_m), nv = (int)ceil(pc / cell_m);
		nu = nu < 4 ? 4 : nu;
		nv = nv < 4 ? 4 : nv;
		if ((double)nu * nv * nk <= MAX_NODES)
			break;
		cell_m *= 1.01;
	}
	double du = pa / nu, dv = pc / nv, dh = th / nh;
	size_t n = (size_t)nu * (size_t)nv * (size_t)nk, cols = (size_t)nu * (size_t)nv;
	float *st = malloc(n * sizeof *st), *sa = malloc(n * sizeof *sa), *phi = malloc(n * sizeof *phi);
	double *src = calloc(n, sizeof *src), *gT = calloc(2 * cols, sizeof *gT);
	int rc = CS_OK;
	if (st == NULL || sa == NULL || phi == NULL || src == NULL || gT == NULL) {
		rc = cs_error(CS_ENOMEM, "out of memory for the towers' light (%zu nodes)", n);
		goto done;
	}
	double g = sc->deck.g; /* (the deck is on: cs_tower_light_wanted) */
	/* each node's extinction (extinction_row) */
	struct extinction_job job = {sc, l, nu, nk, du, dv, dh, 1.0 - g, st, sa};
	rc = cs_pool_run(nv, nthreads, extinction_row, &job, NULL, NULL, NULL);
	if (rc != CS_OK)
		goto done;
	*evaluations += 8 * n;
	/* the beam down the sheared column through each top node
	 * (beam_row: the extinction at its steps' middles); a unit
	 * irradiance facing the key light, sun.z of it on the horizontal;
	 * where the column meets the ground, the share of the beam left */
	cs_v3 sun = sc->sun_dir;
	int steps = nh * SUB_STEPS;
	struct beam_job beam = {sc, l, nu, steps, du, dv, dh / SUB_STEPS,
				(sun.x * l->wind_x + sun.y * l->wind_y) / sun.z,
				(-sun.x * l->wind_y + sun.y * l->wind_x) / sun.z, NULL};
	beam.ext = malloc(cols * (size_t)steps * sizeof *beam.ext);
	if (beam.ext == NULL) {
		rc = cs_error(CS_ENOMEM, "out of memory for the towers' light (%zu nodes)", n);
		goto done;
	}
	rc = cs_pool_run(nv, nthreads, beam_row, &beam, NULL, NULL, NULL);
	/* the beam that reaches the layer's top through the layers above
	 * (deck.sun_top), of a unit irradiance facing the key light */
	double E = sc->sun_illuminance[1] > 0.0 ? sc->sun_illuminance[1] : 1.0;
	double above = sc->deck.sun_top[li][1] / (E * sun.z);
	above = above > 0.0 ? (above < 1.0 ? above : 1.0) : 0.0;
	double step = dh / SUB_STEPS, power = above * sun.z * du * dv;
	double below = l->base_m - sc->ground_alt_m;
	below = below > 0.0 ? below : 0.0;
	for (int j = 0; j < nv && rc == CS_OK; j++)
		for (int i = 0; i < nu; i++) {
			const float *ext = beam.ext + ((size_t)j * (size_t)nu + (size_t)i) * (size_t)steps;
			double tau = 0.0, T = 1.0;
			for (int s = 0; s < steps; s++) { /* down from the top */
				double down = (s + 0.5) * step;
				tau += (1.0 - g) * ext[s] * step / sun.z;
				double T1 = exp(-tau);
				deposit(src, st, nu, nv, nk, (i * du - down * beam.shu) / du,
					(j * dv - down * beam.shv) / dv, (th - down) / dh, power * (T - T1));
				T = T1;
			}
			splat_columns(gT, gT + cols, nu, nv, (i * du - (th + below) * beam.shu) / du,
				      (j * dv - (th + below) * beam.shv) / dv, T);
		}
	free(beam.ext);
	if (rc != CS_OK)
		goto done;
	*evaluations += (uint64_t)cols * (uint64_t)steps;
	/* the light coming in, per unit irradiance of the key light: the
	 * sky's from above (the diffuse light at the layer's top), the
	 * ground's from below (its albedo times the beam left under each
	 * column and the diffuse light under the layers), in the green
	 * channel, the luminance's most */
	double j_in[2] = {sc->deck.dif_top[li][1] / E, CS_PI * sc->deck.ground_below[1] / E};
	for (size_t m = 0; m < cols; m++) {
		double Tg = gT[cols + m] > 0.0 ? gT[m] / gT[cols + m] : 1.0;
		gT[m] = sc->ground_albedo[1] * (above * sun.z * Tg + CS_PI * sc->deck.sky_below[1] / E);
	}
	int iterations;
	rc = cs_diffusion_solve(nu, nv, nk, du, dv, dh, st, sa, src, j_in, gT, phi, &iterations);
	if (rc == CS_OK) {
		*out = (struct cs_light_cache){
			.depth = phi, .nu = nu, .nv = nv, .nh = nh,
			.du_m = du, .dv_m = dv, .dh_m = dh, .path_per_m = 1.0,
		};
		phi = NULL;
	}
done:
	free(st);
	free(sa);
	free(phi);
	free(src);
	free(gT);
	return rc;
}

int cs_tower_light_build(struct cs_scene *sc, double cell_m, int nthreads, uint64_t *evaluations)
{
	for (int n = 0; n < CS_SCENE_MAX_LAYERS; n++)
		sc->tower_light[n] = (struct cs_light_cache){0};
	int rc = CS_OK;
	for (int li = 0; li < sc->nlayers && rc == CS_OK; li++)
		if (sc->deck.tilt_weight[li] > 0.0)
			rc = build_layer(sc, li, cell_m, nthreads, &sc->tower_light[li], evaluations);
	return rc;
}
