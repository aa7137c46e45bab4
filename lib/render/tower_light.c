/* tower_light.c - the key light's light deep inside a cumulonimbus's
 * towers (and a cumulus's heaps: any layer with tilted columns,
 * deck.tilt_weight): the diffusion approximation of radiative transfer solved over
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
 * the towers, plus the diffuse light), on a wall half of each; at a face
 * toward clear air inside the layer, what the clear air there sees: the
 * sky, the ground and the light that leaves other faces of cloud (the
 * exchange between towers and across the gaps in one, struct exchange).
 * Along the wind and across it the field repeats, as the clouds do.
 *
 * Discretised on a lattice of nodes (finite volumes around each node,
 * half a level at the base and the top; a node is cloud where the mean
 * extinction of its volume is more than 0), with the light coming in at
 * each face toward clear air as an unknown of its own, the system is
 * linear but not symmetric: BiCGSTAB with the diagonal as preconditioner
 * solves it.  The source: the beam is followed down a
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
#include <stdint.h>
#include <stdlib.h>

#define SUB_STEPS 4      /* the beam's samples a level */
#define TAU_CELL_MIN 0.3 /* the least transport depth across a node's cell of cloud */
#define SOLVE_TOL 1e-5      /* relative residual */
#define SOLVE_MAX_ITER 2000 /* (the study's cumulonimbus: 17, 31 and 61 at 800, 400, 200 m) */
/* A key light lower than this lights no field: its beam would cross the
 * flat, periodic layer's 40 km periods many times over (5 deg: 112 km
 * through a cumulonimbus 9.8 km thick; the light march's paths are capped
 * at 150). */
#define SUN_MIN_SIN 0.0871557427 /* sin 5 deg */
/* The most nodes a layer's lattice takes (the build and the solver
 * allocate about 110 bytes a node, and touch the solver's pages of the
 * nodes of cloud only: cloudrender measured 1.3 GB and 17 s a frame on 2
 * threads for the study's cumulonimbus, a cloudier layer takes more): a
 * finer cell is coarsened to fit */
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

/* The light coming in from below under column (i, j): ground_in's, or
 * j_in[1] everywhere. */
static double light_up(const double j_in[2], const double *ground_in, int nu, int i, int j)
{
	return ground_in != NULL ? ground_in[(size_t)j * (size_t)nu + (size_t)i] : j_in[1];
}

/* The wrapped index along an axis of n. */
static int wrap(long i, int n)
{
	long w = i % n;
	return (int)(w < 0 ? w + n : w);
}

/* The light from the other cloud around: directions from a clear node
 * (a spherical Fibonacci set), the most cells a ray of them crosses
 * before it is taken to see the horizon.  Cloud a ray meets in its first
 * EXCHANGE_MIN_CELLS cells is taken as the horizon too: at cells of
 * hundreds of metres that is mostly the staircase the lattice makes of a
 * slanted wall, which the wall does not see (the study's cumulonimbus
 * scenes against the path tracer: counting it, the 12 % cover seen from
 * under it went from +0.3 % to +17.8 % in mean luminance, relative MSE
 * 0.110 to 0.123; leaving out the first cell only, +7.4 %, 0.098; the
 * first two, +5.0 %, 0.099). */
#define GATHER_DIRS 48
#define GATHER_CELLS 256
#define EXCHANGE_MIN_CELLS 2

struct lattice {
	int nu, nv, nk;
	double d[3]; /* the cells' size along u, v and k, m */
	const float *st;
	const double *j_in, *ground_in;
};

/* The area (m^2) of node m's faces across axis a (0 u, 1 v, 2 k): half
 * a level high at the layer's base and top. */
static double face_area(const struct lattice *lt, size_t m, int a)
{
	size_t k = m % (size_t)lt->nk;
	double h = k == 0 || k + 1 == (size_t)lt->nk ? 0.5 : 1.0;
	return a == 0 ? lt->d[1] * lt->d[2] * h : a == 1 ? lt->d[0] * lt->d[2] * h : lt->d[0] * lt->d[1];
}

/* Marshak's condition at a face of cloud node m across axis a, toward
 * clear air half a cell away: the flux D (phi - phi_f) / (d / 2) through
 * it is phi_f / 2 - 2 J, so gamma (phi - 4 J) an area, gamma =
 * a' / (2 a' + 1), a' = 2 D / d. */
static double marshak_gamma(const struct lattice *lt, size_t m, int a)
{
	double D = 1.0 / (3.0 * lt->st[m]), ka = 2.0 * D / lt->d[a];
	return ka / (2.0 * ka + 1.0);
}

/* What a ray from a clear node meets (struct exchange's targets): a face
 * of cloud, 6 h + f (node h's face f, the side the ray came from); the
 * ground under column c, TO_GROUND | c; the sky; the horizon. */
#define TO_GROUND 0x80000000u
#define TO_SKY 0xffffffffu
#define TO_HORIZON 0xfffffffeu

/* The first thing a ray from clear node (i, j, k) along dir (metres)
 * meets: the first node of cloud it enters (from its EXCHANGE_MIN_CELLS
 * + 1st cell on), the sky above the layer's top, the ground below its
 * base, or the horizon.  The cells are the nodes' boxes; along k, half a
 * box at the base and the top. */
static uint32_t trace(const struct lattice *lt, int i, int j, int k, const double dir[3])
{
	int nu = lt->nu, nk = lt->nk, nh = nk - 1, idx[3] = {i, j, k}, step[3];
	double tmax[3], tdelta[3];
	for (int a = 0; a < 3; a++) {
		step[a] = dir[a] > 0.0 ? 1 : -1;
		double v = fabs(dir[a]);
		tdelta[a] = v > 0.0 ? lt->d[a] / v : HUGE_VAL;
		double half = 0.5 * lt->d[a];
		if (a == 2 && ((k == nh && step[2] > 0) || (k == 0 && step[2] < 0)))
			half = 0.0; /* the layer's top or base is the box's face */
		tmax[a] = v > 0.0 ? half / v : HUGE_VAL;
	}
	for (int c = 0; c < GATHER_CELLS; c++) {
		int a = tmax[0] < tmax[1] ? (tmax[0] < tmax[2] ? 0 : 2) : (tmax[1] < tmax[2] ? 1 : 2);
		if (a == 2 && ((idx[2] == nh && step[2] > 0) || (idx[2] == 0 && step[2] < 0)))
			return step[2] > 0 ? TO_SKY
					   : TO_GROUND | (uint32_t)((size_t)idx[1] * (size_t)nu +
								    (size_t)idx[0]);
		idx[a] += step[a];
		if (a < 2)
			idx[a] = wrap(idx[a], a == 0 ? lt->nu : lt->nv);
		tmax[a] += tdelta[a];
		if (a == 2 && ((idx[2] == nh && step[2] > 0) || (idx[2] == 0 && step[2] < 0)))
			tmax[2] -= 0.5 * tdelta[2]; /* the last box is half a level */
		size_t h = IDX(idx[0], idx[1], idx[2]);
		if (lt->st[h] > 0.0)
			return c < EXCHANGE_MIN_CELLS
				       ? TO_HORIZON
				       : (uint32_t)(6 * h + (size_t)(2 * a + (step[a] > 0 ? 1 : 0)));
	}
	return TO_HORIZON;
}

/* The light sent from cloud to cloud through clear air.  Each face of
 * cloud toward a clear node c of the layer has its own unknown, the light
 * J coming in there, numbered 6 (c's place among the clear nodes next to
 * cloud) + (the side of c the cloud is on).  It is what c sees over the
 * half of the directions away from the face, J = pi sum L (d . n) /
 * sum (d . n) over GATHER_DIRS rays from c (a spherical Fibonacci set), n
 * the face's normal, so that a uniform radiance L gives pi L.  A ray meets
 * the sky (pi L = J_top), the ground (its light), the horizon (half each)
 * or another face of cloud, whose outgoing light is Marshak's
 * pi L = phi_f / 2 - J = J + gamma (phi - 4 J), gamma = a / (2 a + 1),
 * a = 2 D / d (the node's fluence phi at d / 2 from the face). */
struct exchange {
	size_t count;    /* clear nodes next to cloud */
	uint32_t *node;  /* [count] their indices, ascending */
	uint32_t *cloud; /* [6 count] the node of cloud of each face; n: none */
	double *gamma;   /* [6 count] its gamma, and its conductance (area gamma, W per W/m^2) */
	double *cond;
	double *fixed;   /* [6 count] what the sky, the ground and the horizon give its J */
	double *out;     /* [6 count] scratch: the light leaving each face, pi L */
	/* what each face gathers from the faces of cloud its rays meet: the
	 * sparse rows [row[id], row[id + 1]) of (face, share of the rays) */
	uint32_t *row, *col;
	double *share;
	double dir[GATHER_DIRS][3];
	double w[6][GATHER_DIRS]; /* ray q's share of the J of the face on side f: (d . n) / sum (d . n) */
};

static void exchange_free(struct exchange *ex)
{
	free(ex->node);
	free(ex->cloud);
	free(ex->gamma);
	free(ex->row);
	free(ex->col);
	free(ex->share);
	*ex = (struct exchange){0};
}

/* Whether node m is clear and next to cloud (nb: its neighbours). */
static int next_to_cloud(const struct lattice *lt, size_t m, size_t nb[6])
{
	size_t n = (size_t)lt->nu * (size_t)lt->nv * (size_t)lt->nk, col = m / (size_t)lt->nk;
	if (lt->st[m] > 0.0)
		return 0;
	neighbours(lt->nu, lt->nv, lt->nk, (int)(col % (size_t)lt->nu), (int)(col / (size_t)lt->nu),
		   (int)(m % (size_t)lt->nk), nb);
	for (int f = 0; f < 6; f++)
		if (nb[f] < n && lt->st[nb[f]] > 0.0)
			return 1;
	return 0;
}

static int by_node(const void *a, const void *b)
{
	uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
	return (x > y) - (x < y);
}

/* The rays of a task's TRACE_BATCH clear nodes (on the CPU pool): what
 * each meets, a face's unknown (the clear node before the face, and the
 * side) or TO_*. */
#define TRACE_BATCH 256
struct trace_job {
	const struct lattice *lt;
	const struct exchange *ex;
	uint32_t *target; /* [count * GATHER_DIRS] */
};

static void trace_batch(void *user, int task, int worker)
{
	(void)worker;
	const struct trace_job *job = user;
	const struct lattice *lt = job->lt;
	const struct exchange *ex = job->ex;
	size_t end = ((size_t)task + 1) * TRACE_BATCH;
	end = end < ex->count ? end : ex->count;
	for (size_t c = (size_t)task * TRACE_BATCH; c < end; c++) {
		size_t m = ex->node[c], col = m / (size_t)lt->nk;
		int i = (int)(col % (size_t)lt->nu), j = (int)(col / (size_t)lt->nu);
		for (int q = 0; q < GATHER_DIRS; q++) {
			uint32_t t = trace(lt, i, j, (int)(m % (size_t)lt->nk), ex->dir[q]);
			if (!(t & TO_GROUND)) { /* face f of node h: the clear node before it */
				size_t h = t / 6, hc = h / (size_t)lt->nk, back[6];
				int f = (int)(t % 6);
				neighbours(lt->nu, lt->nv, lt->nk, (int)(hc % (size_t)lt->nu),
					   (int)(hc / (size_t)lt->nu), (int)(h % (size_t)lt->nk), back);
				uint32_t key = (uint32_t)back[f];
				const uint32_t *at = bsearch(&key, ex->node, ex->count, sizeof key, by_node);
				/* (the cell before a face of cloud is a clear node
				 * next to it: found) */
				t = at != NULL ? (uint32_t)(6 * (size_t)(at - ex->node) + (size_t)(f ^ 1))
					       : TO_HORIZON;
			}
			job->target[c * GATHER_DIRS + (size_t)q] = t;
		}
	}
}

/* The clear nodes next to cloud, their faces' unknowns, the rays (on
 * nthreads of the CPU pool) and the rows of what each face gathers. */
static int exchange_setup(const struct lattice *lt, int nthreads, struct exchange *ex)
{
	size_t n = (size_t)lt->nu * (size_t)lt->nv * (size_t)lt->nk, nb[6];
	*ex = (struct exchange){0};
	/* the face on side f of a clear node faces along -e_f */
	double norm[6] = {0};
	for (int q = 0; q < GATHER_DIRS; q++) {
		double z = 1.0 - (2.0 * q + 1.0) / GATHER_DIRS, r = sqrt(1.0 - z * z);
		double phi = q * 2.39996322972865332; /* the golden angle */
		ex->dir[q][0] = r * cos(phi), ex->dir[q][1] = r * sin(phi), ex->dir[q][2] = z;
		for (int f = 0; f < 6; f++) {
			double c = (f % 2 ? 1.0 : -1.0) * ex->dir[q][f / 2];
			ex->w[f][q] = c > 0.0 ? c : 0.0;
			norm[f] += ex->w[f][q];
		}
	}
	for (int f = 0; f < 6; f++)
		for (int q = 0; q < GATHER_DIRS; q++)
			ex->w[f][q] /= norm[f];
	for (size_t m = 0; m < n; m++)
		ex->count += (size_t)next_to_cloud(lt, m, nb);
	if (ex->count == 0)
		return CS_OK;
	if (6 * n >= TO_GROUND) /* (MAX_NODES keeps a layer's lattice far below) */
		return cs_error(CS_EINVAL, "the towers' lattice is too large (%zu nodes)", n);
	size_t nf = 6 * ex->count, cap = nf;
	uint32_t *target = malloc(ex->count * GATHER_DIRS * sizeof *target);
	ex->node = malloc(ex->count * sizeof *ex->node);
	ex->cloud = malloc(nf * sizeof *ex->cloud);
	ex->gamma = malloc(4 * nf * sizeof *ex->gamma);
	ex->row = malloc((nf + 1) * sizeof *ex->row);
	ex->col = malloc(cap * sizeof *ex->col);
	ex->share = malloc(cap * sizeof *ex->share);
	int rc = CS_OK;
	if (target == NULL || ex->node == NULL || ex->cloud == NULL || ex->gamma == NULL ||
	    ex->row == NULL || ex->col == NULL || ex->share == NULL) {
		rc = cs_error(CS_ENOMEM, "out of memory for the towers' light (%zu nodes)", n);
		goto done;
	}
	ex->cond = ex->gamma + nf, ex->fixed = ex->gamma + 2 * nf, ex->out = ex->gamma + 3 * nf;
	size_t c = 0;
	for (size_t m = 0; m < n; m++)
		if (next_to_cloud(lt, m, nb))
			ex->node[c++] = (uint32_t)m;
	struct trace_job job = {lt, ex, target};
	rc = cs_pool_run((int)((ex->count + TRACE_BATCH - 1) / TRACE_BATCH), nthreads, trace_batch, &job,
			 NULL, NULL, NULL);
	if (rc != CS_OK)
		goto done;
	ex->row[0] = 0;
	for (c = 0; c < ex->count; c++) {
		size_t m = ex->node[c], col = m / (size_t)lt->nk;
		int i = (int)(col % (size_t)lt->nu), j = (int)(col / (size_t)lt->nu);
		const uint32_t *t = target + c * GATHER_DIRS;
		double up = light_up(lt->j_in, lt->ground_in, lt->nu, i, j), R[GATHER_DIRS];
		for (int q = 0; q < GATHER_DIRS; q++) /* pi L of the sky, the ground, the horizon */
			R[q] = t[q] == TO_SKY ? lt->j_in[0]
			     : t[q] == TO_HORIZON ? 0.5 * (lt->j_in[0] + up)
			     : t[q] & TO_GROUND
				     ? light_up(lt->j_in, lt->ground_in, lt->nu,
						(int)((t[q] & ~TO_GROUND) % (size_t)lt->nu),
						(int)((t[q] & ~TO_GROUND) / (size_t)lt->nu))
				     : 0.0;
		next_to_cloud(lt, m, nb);
		for (int f = 0; f < 6; f++) {
			size_t id = 6 * c + (size_t)f, h = nb[f];
			ex->cloud[id] = (uint32_t)n;
			ex->fixed[id] = 0.0;
			ex->out[id] = 0.0;
			ex->row[id + 1] = ex->row[id];
			if (!(h < n && lt->st[h] > 0.0))
				continue;
			/* the face of h toward this node */
			ex->cloud[id] = (uint32_t)h;
			ex->gamma[id] = marshak_gamma(lt, h, f / 2);
			ex->cond[id] = face_area(lt, h, f / 2) * ex->gamma[id];
			/* the row: each face met once, its rays' shares summed */
			for (int q = 0; q < GATHER_DIRS; q++) {
				double w = ex->w[f][q];
				if (!(w > 0.0))
					continue;
				if (t[q] == TO_SKY || t[q] & TO_GROUND) { /* (TO_HORIZON too) */
					ex->fixed[id] += w * R[q];
					continue;
				}
				size_t e = ex->row[id];
				while (e < ex->row[id + 1] && ex->col[e] != t[q])
					e++;
				if (e < ex->row[id + 1]) {
					ex->share[e] += w;
					continue;
				}
				if (e == cap) {
					cap *= 2;
					uint32_t *col2 = realloc(ex->col, cap * sizeof *col2);
					if (col2 != NULL)
						ex->col = col2;
					double *share2 = realloc(ex->share, cap * sizeof *share2);
					if (share2 != NULL)
						ex->share = share2;
					if (col2 == NULL || share2 == NULL) {
						rc = cs_error(CS_ENOMEM, "out of memory for the towers' light "
									 "(%zu nodes)",
							      n);
						goto done;
					}
				}
				ex->col[e] = t[q];
				ex->share[e] = w;
				ex->row[id + 1]++;
			}
		}
	}
done:
	free(target);
	if (rc != CS_OK)
		exchange_free(ex);
	return rc;
}

/* out = A in over the nodes (in[0, n)) and the faces' unknowns (in[n, n +
 * 6 count)): the nodes' diagonal and conductances to the next node along
 * u, v and k (g[4 m + 3], g[4 m + 0..2]) counted both ways, less 4 times
 * each face's conductance times its J; a face's J less what it gathers
 * from the faces of cloud its rays meet.  Only the unknowns act[0, na)
 * (ascending) take part: the ncl nodes of cloud, then the faces that
 * have one.  A clear node's row is its fluence alone and a face without
 * cloud gathers nothing, so theirs stay 0 from the start: left out, they
 * change no sum (the same terms in the same order). */
static void apply(const double *g, const struct exchange *ex, int nu, int nv, int nk,
		  const uint32_t *act, size_t ncl, size_t na, const double *in, double *out)
{
	size_t n = (size_t)nu * (size_t)nv * (size_t)nk;
	for (size_t a = 0; a < ncl; a++)
		out[act[a]] = g[4 * (size_t)act[a] + 3] * in[act[a]];
	for (size_t a = 0; a < ncl; a++) {
		size_t m = act[a], col = m / (size_t)nk;
		int i = (int)(col % (size_t)nu), j = (int)(col / (size_t)nu), k = (int)(m % (size_t)nk);
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
	const double *J = in + n;
	for (size_t a = ncl; a < na; a++) { /* the light leaving each face, pi L */
		size_t id = act[a] - n;
		ex->out[id] = (1.0 - 4.0 * ex->gamma[id]) * J[id] + ex->gamma[id] * in[ex->cloud[id]];
	}
	for (size_t a = ncl; a < na; a++) {
		size_t id = act[a] - n;
		double sum = 0.0;
		for (size_t e = ex->row[id]; e < ex->row[id + 1]; e++)
			sum += ex->share[e] * ex->out[ex->col[e]];
		out[n + id] = J[id] - sum;
		out[ex->cloud[id]] -= 4.0 * ex->cond[id] * J[id];
	}
}

/* (render.h) */
int cs_diffusion_solve(int nu, int nv, int nk, double du_m, double dv_m, double dh_m,
		       const float *sigma_tr, const float *sigma_a, const double *source,
		       const double j_in[2], const double *ground_in, int exchange, int nthreads,
		       float *phi, int *iterations)
{
	size_t n = (size_t)nu * (size_t)nv * (size_t)nk;
	struct lattice lt = {nu, nv, nk, {du_m, dv_m, dh_m}, sigma_tr, j_in, ground_in};
	struct exchange ex = {0};
	int columns = exchange == CS_DIFFUSE_COLUMNS;
	exchange = exchange == 1;
	int rc = exchange ? exchange_setup(&lt, nthreads, &ex) : CS_OK;
	if (rc != CS_OK)
		return rc;
	size_t N = n + 6 * ex.count; /* the unknowns: the nodes' fluence, the faces' J */
	if (N > UINT32_MAX) { /* (act's indices) */
		exchange_free(&ex);
		return cs_error(CS_EINVAL, "the towers' lattice is too large (%zu nodes)", n);
	}
	/* the unknowns that take part (apply), ascending: the nodes of cloud,
	 * then the faces that have one */
	size_t ncl = 0, nact = 0, na = 0; /* (na: those in act so far) */
	for (size_t m = 0; m < n; m++)
		ncl += sigma_tr[m] > 0.0;
	for (size_t id = 0; id < 6 * ex.count; id++)
		nact += ex.cloud[id] < n;
	nact += ncl;
	double *buf = calloc(9 * N, sizeof *buf), *g = calloc(4 * n, sizeof *g);
	uint32_t *act = malloc((nact > 0 ? nact : 1) * sizeof *act);
	if (buf == NULL || g == NULL || act == NULL) {
		free(buf);
		free(g);
		free(act);
		exchange_free(&ex);
		return cs_error(CS_ENOMEM, "out of memory for the towers' light (%zu nodes)", n);
	}
	double *x = buf, *b = buf + N, *r = buf + 2 * N, *r0 = buf + 3 * N, *p = buf + 4 * N;
	double *v = buf + 5 * N, *y = buf + 6 * N, *t = buf + 7 * N, *inv = buf + 8 * N;
	/* Between two nodes of cloud the conductance of the face, D (the
	 * harmonic mean: two resistances in series) times its area over the
	 * distance.  A face toward clear air, half the nodes' distance away:
	 * the conductance gamma an area (marshak_gamma) to the fluence 4 J of
	 * the light coming in (the sky's from above, the ground's from below,
	 * on a wall half each; toward a clear node of the layer with the
	 * exchange, the face's own unknown); at the layer's base and top,
	 * where the node is, 1/2. */
	for (int j = 0; j < nv; j++)
		for (int i = 0; i < nu; i++)
			for (int k = 0; k < nk; k++) {
				size_t m = IDX(i, j, k), nb[6];
				if (!(sigma_tr[m] > 0.0))
					continue; /* clear: no unknown (phi 0 here) */
				act[na++] = (uint32_t)m; /* (m ascending) */
				neighbours(nu, nv, nk, i, j, k, nb);
				double D = 1.0 / (3.0 * sigma_tr[m]);
				double up = light_up(j_in, ground_in, nu, i, j);
				double wall = 0.5 * (j_in[0] + up);
				double J[6] = {wall, wall, wall, wall, j_in[0], up};
				/* (the volume: its u face's area times du) */
				double diag = sigma_a[m] * face_area(&lt, m, 0) * du_m;
				for (int f = columns ? 4 : 0; f < 6; f++) {
					double area = face_area(&lt, m, f / 2);
					if (nb[f] < n && sigma_tr[nb[f]] > 0.0) {
						double Dn = 1.0 / (3.0 * sigma_tr[nb[f]]);
						double c = area * 2.0 * D * Dn / (D + Dn) / lt.d[f / 2];
						diag += c;
						if (f % 2 == 0)
							g[4 * m + (size_t)f / 2] = c;
					} else {
						double c = area * (nb[f] < n ? marshak_gamma(&lt, m, f / 2) : 0.5);
						diag += c;
						b[m] += nb[f] < n && exchange ? 0.0 : c * 4.0 * J[f];
					}
				}
				g[4 * m + 3] = diag;
				b[m] += source[m];
			}
	for (size_t id = 0; id < 6 * ex.count; id++) {
		b[n + id] = ex.fixed[id];
		if (ex.cloud[id] < n)
			act[na++] = (uint32_t)(n + id);
	}
	for (size_t a = 0; a < na; a++)
		inv[act[a]] = act[a] < n ? 1.0 / g[4 * (size_t)act[a] + 3] : 1.0;
	/* independent columns: each a tridiagonal system, solved by
	 * elimination down the column and substitution back up (a clear
	 * node couples to nothing: its row is phi = 0) */
	if (columns) {
		for (size_t c = 0; c < (size_t)nu * (size_t)nv; c++) {
			double *cp = r, *dp = r0; /* (scratch, nk each) */
			size_t m0 = c * (size_t)nk;
			for (int k = 0; k < nk; k++) {
				size_t m = m0 + (size_t)k;
				double d = sigma_tr[m] > 0.0 ? g[4 * m + 3] : 1.0;
				double lo = k > 0 ? -g[4 * (m - 1) + 2] : 0.0;
				double hi = k + 1 < nk ? -g[4 * m + 2] : 0.0;
				double den = d - (k > 0 ? lo * cp[k - 1] : 0.0);
				cp[k] = hi / den;
				dp[k] = (b[m] - (k > 0 ? lo * dp[k - 1] : 0.0)) / den;
			}
			for (int k = nk - 1; k >= 0; k--)
				x[m0 + (size_t)k] = dp[k] - (k + 1 < nk ? cp[k] * x[m0 + (size_t)k + 1] : 0.0);
		}
		na = 0; /* (no iterations) */
	}
	/* BiCGSTAB (van der Vorst 1992; the exchange makes the system
	 * unsymmetric) with the diagonal as preconditioner, from 0 */
	double bb = 0.0, rho = 1.0, alpha = 1.0, omega = 1.0;
	for (size_t a = 0; a < na; a++) {
		size_t m = act[a];
		r[m] = r0[m] = b[m];
		bb += b[m] * b[m];
	}
	int it = 0;
	for (double rr = bb; it < SOLVE_MAX_ITER && bb > 0.0 && rr > SOLVE_TOL * SOLVE_TOL * bb; it++) {
		double rho1 = 0.0;
		for (size_t a = 0; a < na; a++)
			rho1 += r0[act[a]] * r[act[a]];
		if (!(rho1 != 0.0)) /* breakdown (or the residual's NaN): stop here */
			break;
		double beta = rho1 / rho * (alpha / omega);
		rho = rho1;
		for (size_t a = 0; a < na; a++) { /* y: the preconditioned p */
			size_t m = act[a];
			p[m] = r[m] + beta * (p[m] - omega * v[m]);
			y[m] = p[m] * inv[m];
		}
		apply(g, &ex, nu, nv, nk, act, ncl, na, y, v);
		double r0v = 0.0;
		for (size_t a = 0; a < na; a++)
			r0v += r0[act[a]] * v[act[a]];
		if (!(r0v != 0.0))
			break;
		alpha = rho / r0v;
		for (size_t a = 0; a < na; a++) { /* r: s = r - alpha v; x: half a step */
			size_t m = act[a];
			r[m] -= alpha * v[m];
			x[m] += alpha * y[m];
			y[m] = r[m] * inv[m]; /* the preconditioned s */
		}
		apply(g, &ex, nu, nv, nk, act, ncl, na, y, t);
		double ts = 0.0, tt = 0.0;
		for (size_t a = 0; a < na; a++) {
			size_t m = act[a];
			ts += t[m] * r[m];
			tt += t[m] * t[m];
		}
		omega = tt > 0.0 ? ts / tt : 0.0;
		rr = 0.0;
		for (size_t a = 0; a < na; a++) {
			size_t m = act[a];
			x[m] += omega * y[m];
			r[m] -= omega * t[m];
			rr += r[m] * r[m];
		}
		if (!(omega != 0.0)) {
			it++;
			break;
		}
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
	*iterations = columns ? 1 : it;
	free(act);
	free(buf);
	free(g);
	exchange_free(&ex);
	return CS_OK;
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

/* Whether layer li takes a lattice under settings s: a towers' share, or
 * a thick deck's with s->deck_lattice. */
static int lattice_wanted(const struct cs_scene *sc, const struct cs_render_settings *s, int li)
{
	return cs_tower_share(sc, s, li) > 0.0 || (s->deck_lattice && cs_deck_lattice(sc, li));
}

int cs_tower_light_wanted(const struct cs_scene *sc, const struct cs_render_settings *s)
{
	if (!(s->tower_cell_m > 0.0) || !s->ambient || !sc->deck.on || !(sc->effects & CS_FX_KEY) ||
	    !(sc->sun_dir.z >= SUN_MIN_SIN))
		return 0;
	for (int i = 0; i < sc->nlayers; i++)
		if (lattice_wanted(sc, s, i))
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

/* A deck's lattice (cs_deck_lattice): phi, the fluence of the lattice,
 * becomes its ratio to the fluence of independent columns, each a slab
 * whose beam (power a column at its top) comes down it as through a
 * plane-parallel layer, sun_z the key light's sine, the light coming
 * in (j_in, ground_in) the same, raised to CS_DECK_LATTICE_POWER; 1
 * where either is none, and no less than 1.  A deck's light fields are
 * such columns' light, with its angles (how a base looks darker toward
 * the horizon, which the diffusion's radiance does not give); what they
 * lack is the light a thick cell takes in through its sides from the
 * gaps around it, and the sunlit walls, which the lattice has: its ratio
 * to the columns', in one approximation, so that the diffusion's own
 * errors cancel, scales the fields' light (integrator.c, sample_source).
 * Where the ratio is under 1 (the lattice's tops near the gaps, thin
 * cells that it lets leak) it is taken for 1: at 1 the study's tops from
 * above and altocumulus from below, which the fields meet within 5 %,
 * are where they were; with it they measured -12.9 % and -13.8 % against
 * the path tracer (-4.1 % and -3.6 % before).  Let under 1 only where
 * the sun's beam is spent (by 1 - exp(-(1 - g) tau_sun)), the shaded
 * walls, it took the view toward the sun under the 70 % deck of
 * test_reference from +10.7 to +5.2 %, but the study's view from inside
 * a cloud from -4.4 to -5.4 % and its tops from above from -4.0 to
 * -4.9 %. */
static int deck_ratio(int nu, int nv, int nk, double du, double dv, double dh, double sun_z,
		      double power,
		      const float *st, const float *sa, const double j_in[2], const double *gT,
		      int nthreads, float *phi)
{
	size_t n = (size_t)nu * (size_t)nv * (size_t)nk, cols = (size_t)nu * (size_t)nv;
	double *src = calloc(n, sizeof *src);
	float *one = malloc(n * sizeof *one);
	if (src == NULL || one == NULL) {
		free(src);
		free(one);
		return cs_error(CS_ENOMEM, "out of memory for the deck's light (%zu nodes)", n);
	}
	/* the beam down each column from its top node, the nodes' volumes
	 * half a level at the base and the top */
	for (size_t c = 0; c < cols; c++) {
		double T = 1.0;
		for (int k = nk - 1; k >= 0; k--) {
			size_t m = c * (size_t)nk + (size_t)k;
			double len = k == 0 || k == nk - 1 ? 0.5 * dh : dh;
			double T1 = T * exp(-(double)st[m] * len / sun_z);
			src[m] = power * (T - T1);
			T = T1;
		}
	}
	int iterations;
	int rc = cs_diffusion_solve(nu, nv, nk, du, dv, dh, st, sa, src, j_in, gT,
				    CS_DIFFUSE_COLUMNS, nthreads, one, &iterations);
	for (size_t m = 0; rc == CS_OK && m < n; m++) {
		double r = one[m] > 0.0 && phi[m] > 0.0 ? (double)phi[m] / one[m] : 1.0;
		phi[m] = (float)(r > 1.0 ? pow(r, CS_DECK_LATTICE_POWER) : 1.0);
	}
	free(src);
	free(one);
	return rc;
}

/* Layer l's field into *out (none where the layer has no periods or is
 * far weather): the lattice, the nodes' extinction, the beam's source,
 * the light coming in, the solve.  A deck's faces toward its gaps take
 * the light its rays gather across them where deck is CS_DECK_EXCHANGE,
 * the sky's and the ground's where CS_DECK_DIFFUSION: that halves a rain
 * deck's solve (the study's broken-deck-below at 160x90 on one thread,
 * 0.72 -> 0.38 s a frame at medium) and moved its errors both ways
 * against the path tracer (broken-deck-below medium -5.2 -> -7.4 %,
 * relative MSE 0.054 -> 0.052; the view from inside a cloud 0.0026 ->
 * 0.0030; the capture's rain hour -7.4 -> -5.5 %, 0.057 -> 0.051;
 * cloudrender(1), QUALITY).  A towers' share always takes the
 * exchange. */
static int build_layer(const struct cs_scene *sc, int li, double cell_m, int deck, int nthreads,
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
	double su, sv; /* the sun's direction on the layer's axes */
	cs_cloud_en_to_axes(l, sun.x, sun.y, &su, &sv);
	struct beam_job beam = {sc, l, nu, steps, du, dv, dh / SUB_STEPS, su / sun.z, sv / sun.z, NULL};
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
				if (!(ext[s] > 0.0)) /* clear air: nothing lost */
					continue;
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
	int exchange = !cs_deck_lattice(sc, li) || deck == CS_DECK_EXCHANGE; /* (0 or 1, not
										 CS_DIFFUSE_COLUMNS) */
	rc = cs_diffusion_solve(nu, nv, nk, du, dv, dh, st, sa, src, j_in, gT, exchange, nthreads,
				phi, &iterations);
	if (rc == CS_OK && cs_deck_lattice(sc, li)) /* (built for it: s->deck_lattice) */
		rc = deck_ratio(nu, nv, nk, du, dv, dh, sun.z, power, st, sa, j_in, gT, nthreads,
				phi);
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

int cs_tower_light_build(struct cs_scene *sc, const struct cs_render_settings *s, int nthreads,
			 uint64_t *evaluations)
{
	for (int n = 0; n < CS_SCENE_MAX_LAYERS; n++)
		sc->tower_light[n] = (struct cs_light_cache){0};
	int rc = CS_OK;
	for (int li = 0; li < sc->nlayers && rc == CS_OK; li++)
		if (lattice_wanted(sc, s, li))
			rc = build_layer(sc, li, s->tower_cell_m, s->deck_lattice, nthreads,
					 &sc->tower_light[li], evaluations);
	return rc;
}
