/* fog.c - the light inside fog: the radiance field of a plane-parallel
 * layer of the clouds' droplets over the ground, solved once a scene by
 * successive orders of scattering over discrete ordinates, and tabulated as
 * the source the view rays' march reads (render.h, struct cs_fog_field).
 *
 * Fog is thin in transport terms: at 300 m visibility and 300 m depth its
 * optical depth is 3.8, but with the droplets' forward peak (g = 0.85) a
 * photon keeps its direction for 500 m, more than the fog is deep.  The
 * light inside it is then far from isotropic: looking up it is the sky's
 * light, diffused; along the ground only what scattered sideways.  The
 * reference path tracer measured the horizon 1.8 times dimmer than 20
 * degrees up at the bottom of such a fog; an isotropic source (what the
 * march used before) cannot show that.
 *
 * The solution is by Fourier modes of the azimuth from the sun's beam
 * (each of which the radiative transfer equation leaves on its own; four
 * of them: two left the fog 4 % too dark toward a low sun, six changed
 * nothing): Gauss-Legendre ordinates in the cosine of the
 * direction of travel, levels evenly spaced in optical depth, the
 * source linear in optical depth between them (the formal solution's
 * exact integral for that), a Lambertian ground below.  The sun's
 * unscattered beam is not in the field: its single scattering is the
 * march's own term, with the full phase function (the sun's glow).  The
 * azimuthal mean of the Henyey-Greenstein phase function is a complete
 * elliptic integral of the second kind (below), exact to rounding. */
#include "render/render.h"

#include "core/err.h"
#include "core/pool.h"
#include "render/phase.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* the levels' spacing in optical depth, at most */
#define FOG_DTAU 0.1
enum {
	NG = 16,        /* ordinates per hemisphere (24 changed the fog scene by 0.2 %) */
	NO = 2 * NG,    /* 0..NG-1 travel down (mu < 0), NG.. up */
	MAX_SUB = 8,    /* the solution's levels between two of the table's, at most
			   (16 took 8 times as long for test_render's random
			   scenes, whose broken layers solve up to four fields;
			   with 8 a near-conservative slab's reflection is 2.7 %
			   low at optical depth 64, 5.6 % at 128, against 16; the
			   study's overcast -0.6 -> -1.1 %) */
	MAX_LEV = MAX_SUB * (CS_FOG_LEVELS - 1) + 1,
	NDIR = CS_FOG_DIRS,
	NSKY = CS_FOG_SKY,
	NMODE = CS_FOG_MODES,
	NPSI = 256,     /* azimuth differences over [0, pi] for the modes' kernels */
	MAX_ORDERS = 20000
};

/* The complete elliptic integral of the second kind E(m), m = k^2 in
 * [0, 1], by the arithmetic-geometric mean (Abramowitz & Stegun 17.6). */
static double ellip_e(double m)
{
	if (m >= 1.0)
		return 1.0;
	double a = 1.0, b = sqrt(1.0 - m), sum = 0.5 * m, pw = 1.0;
	for (int i = 0; i < 40; i++) {
		double c = 0.5 * (a - b);
		if (c < 1e-17)
			break;
		double an = 0.5 * (a + b);
		b = sqrt(a * b);
		a = an;
		sum += pw * c * c;
		pw *= 2.0;
	}
	return CS_PI / (2.0 * a) * (1.0 - sum);
}

/* The azimuthal mean (1/sr) of the Henyey-Greenstein phase function
 * between directions of cosines mu and nu: with a = 1 + g^2 - 2 g mu nu,
 * b = 2 |g| sin sin', the integral over the azimuth of
 * (a - b cos phi)^-3/2 is 4 E(2b / (a + b)) / ((a - b) sqrt(a + b)). */
static double hg_mean(double mu, double nu, double g)
{
	double s = sqrt(fmax(0.0, 1.0 - mu * mu) * fmax(0.0, 1.0 - nu * nu));
	double a = 1.0 + g * g - 2.0 * g * mu * nu, b = 2.0 * fabs(g) * s;
	double lo = a - b > 1e-300 ? a - b : 1e-300;
	return (1.0 - g * g) * ellip_e(2.0 * b / (a + b)) / (2.0 * CS_PI * CS_PI * lo * sqrt(a + b));
}

double cs_fog_phase_mean(double mu, double nu, double g_forward, double g_back,
			 double w_forward)
{
	return w_forward * hg_mean(mu, nu, g_forward) + (1.0 - w_forward) * hg_mean(mu, nu, g_back);
}

/* Gauss-Legendre nodes and weights on [0, 1] (Newton on P_n). */
static void gauss01(int n, double *x, double *w)
{
	for (int i = 0; i < n; i++) {
		double z = cos(CS_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
		for (int it = 0; it < 100; it++) {
			double p0 = 1.0, p1 = z;
			for (int k = 2; k <= n; k++) {
				double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
				p0 = p1, p1 = p2;
			}
			dp = n * (z * p1 - p0) / (z * z - 1.0);
			double dz = p1 / dp;
			z -= dz;
			if (fabs(dz) < 1e-16)
				break;
		}
		x[i] = 0.5 * (1.0 - z);
		w[i] = 1.0 / ((1.0 - z * z) * dp * dp);
	}
}

/* The Fourier kernels of the two-lobe phase function (1/sr) between
 * directions of cosines mu and nu: out[n] = (1 / 2 pi) times the integral
 * over the azimuth difference psi of p cos(n psi), n < NMODE.  Mode 0 is
 * cs_fog_phase_mean's closed form; the others by the midpoint rule on
 * NPSI points over [0, pi] (the forward peak is 0.1 rad wide: 20 points
 * across it along the horizon, more toward the poles). */
static void phase_modes(const struct cs_fog_problem *p, const double (*cpsi)[NMODE], double mu,
			double nu, double out[NMODE])
{
	double s = sqrt(fmax(0.0, 1.0 - mu * mu) * fmax(0.0, 1.0 - nu * nu));
	out[0] = cs_fog_phase_mean(mu, nu, p->g_forward, p->g_back, p->w_forward);
	for (int n = 1; n < NMODE; n++)
		out[n] = 0.0;
	if (NMODE < 2 || s < 1e-12)
		return;
	for (int q = 0; q < NPSI; q++) {
		double f = cs_phase_two_lobe(mu * nu + s * cpsi[q][1], p->g_forward, p->g_back,
					     p->w_forward, 1.0);
		for (int n = 1; n < NMODE; n++)
			out[n] += f * cpsi[q][n];
	}
	for (int n = 1; n < NMODE; n++)
		out[n] *= 1.0 / NPSI; /* (1 / 2 pi) 2 int_0^pi = (1 / pi) pi / NPSI sum */
}

/* The quadrature and the phase matrices of a phase function and a sun
 * (setup): read only once set up, shared by the solvers of every problem
 * that has them. */
struct quadrature {
	double mu[NO], wt[NO];   /* cosine of the direction of travel, weight */
	/* of mode n: 2 pi w_j p_n(mu_i, mu_j) at PT[n][j][i] (transposed, so
	 * that scatter sums over j for every i at once), mode 0's columns
	 * summing to 1 */
	double PT[NMODE][NO][NO];
	double Pout[NMODE][NDIR][NO]; /* the same from ordinate j into table direction m */
	double psun[NMODE][NO];  /* p_n from the sun's beam, 1/sr */
	double psun_out[NMODE][NDIR]; /* the same into table direction m */
};

/* One mode and colour of a problem being solved (a worker's). */
struct solver {
	const struct quadrature *q; /* the problem's */
	int nlev, sub;           /* levels of the solution, of them between the table's */
	double L[MAX_LEV][NO], J[MAX_LEV][NO];
	double dJ[MAX_LEV][NO];  /* the last order's change of J */
};

/* The ordinates nearest below and above cosine mu (*lo, *hi) and where
 * mu lies between them (*f, 0 at lo); beyond the outermost, that one. */
static void bracket(const struct quadrature *Q, double mu, int *lo, int *hi, double *f)
{
	*lo = *hi = -1;
	for (int j = 0; j < NO; j++) {
		if (Q->mu[j] <= mu && (*lo < 0 || Q->mu[j] > Q->mu[*lo]))
			*lo = j;
		if (Q->mu[j] >= mu && (*hi < 0 || Q->mu[j] < Q->mu[*hi]))
			*hi = j;
	}
	*lo = *lo < 0 ? *hi : *lo;
	*hi = *hi < 0 ? *lo : *hi;
	double span = Q->mu[*hi] - Q->mu[*lo];
	*f = span > 0.0 ? (mu - Q->mu[*lo]) / span : 0.0;
}

/* The quadrature's phase matrices.  Near the poles the forward peak is
 * narrower than the ordinates' spacing, and the quadrature's sum over the
 * light scattered out of a direction misses 4 % at the zenith: the
 * missing part (or the excess) goes to the forward direction itself (the
 * ordinate, or the two around a table direction or the sun's beam), where
 * the peak is, and nowhere else.  (Scaling the whole row instead, the
 * light sent back up from the sky at the fog's top came out 14 % too
 * bright.) */
static void setup(struct quadrature *Q, const struct cs_fog_problem *p)
{
	double x[NG], w[NG], pm[NMODE], cpsi[NPSI][NMODE];
	gauss01(NG, x, w);
	for (int q = 0; q < NPSI; q++)
		for (int n = 0; n < NMODE; n++)
			cpsi[q][n] = cos(n * CS_PI * (q + 0.5) / NPSI);
	for (int i = 0; i < NG; i++) {
		Q->mu[i] = -x[i], Q->wt[i] = w[i];
		Q->mu[NG + i] = x[i], Q->wt[NG + i] = w[i];
	}
	for (int j = 0; j < NO; j++) {
		for (int i = 0; i <= j; i++) {
			phase_modes(p, cpsi, Q->mu[i], Q->mu[j], pm);
			for (int n = 0; n < NMODE; n++) {
				Q->PT[n][j][i] = 2.0 * CS_PI * Q->wt[j] * pm[n];
				Q->PT[n][i][j] = 2.0 * CS_PI * Q->wt[i] * pm[n];
			}
		}
	}
	for (int j = 0; j < NO; j++) {
		double sum = 0.0;
		for (int i = 0; i < NO; i++)
			sum += Q->PT[0][j][i] * Q->wt[i] / Q->wt[j];
		for (int n = 0; n < NMODE; n++)
			Q->PT[n][j][j] += 1.0 - sum;
	}
	int lo, hi;
	double f;
	for (int m = 0; m < NDIR; m++) {
		double mu = -1.0 + 2.0 * m / (NDIR - 1), sum = 0.0;
		for (int j = 0; j < NO; j++) {
			phase_modes(p, cpsi, mu, Q->mu[j], pm);
			for (int n = 0; n < NMODE; n++)
				Q->Pout[n][m][j] = 2.0 * CS_PI * Q->wt[j] * pm[n];
			sum += Q->Pout[0][m][j];
		}
		bracket(Q, mu, &lo, &hi, &f);
		for (int n = 0; n < NMODE; n++) {
			Q->Pout[n][m][lo] += (1.0 - sum) * (1.0 - f);
			Q->Pout[n][m][hi] += (1.0 - sum) * f;
		}
	}
	double sum = 0.0;
	for (int i = 0; i < NO; i++) {
		phase_modes(p, cpsi, Q->mu[i], -p->mu0, pm);
		for (int n = 0; n < NMODE; n++)
			Q->psun[n][i] = pm[n];
		sum += 2.0 * CS_PI * Q->wt[i] * pm[0];
	}
	for (int m = 0; m < NDIR; m++) {
		phase_modes(p, cpsi, -1.0 + 2.0 * m / (NDIR - 1), -p->mu0, pm);
		for (int n = 0; n < NMODE; n++)
			Q->psun_out[n][m] = pm[n];
	}
	bracket(Q, -p->mu0, &lo, &hi, &f);
	for (int n = 0; n < NMODE && p->mu0 > 0.0; n++) {
		Q->psun[n][lo] += (1.0 - sum) * (1.0 - f) / (2.0 * CS_PI * Q->wt[lo]);
		Q->psun[n][hi] += (1.0 - sum) * f / (2.0 * CS_PI * Q->wt[hi]);
	}
}

/* The sun's beam at level k of n, on a plane facing it (klux). */
static double beam_at(const struct cs_fog_problem *p, int k, int n, int c)
{
	if (!(p->mu0 > 0.0))
		return 0.0;
	double tau = p->tau * k / (n - 1);
	return p->sun[c] * exp(-tau / p->mu0);
}

/* The radiance of mode n, channel c, along every ordinate from the
 * sources J: down from the top, the ground's reflection (mode 0 only:
 * Lambertian), up from the ground.  Level by level, every ordinate of a
 * direction at once (each ordinate's sum in the same order as alone). */
static void sweep(struct solver *S, const struct cs_fog_problem *p, int n, int c)
{
	const struct quadrature *Q = S->q;
	double dt = p->tau / (S->nlev - 1), E[NO], a[NO], b[NO];
	for (int i = 0; i < NO; i++) {
		double x = dt / fabs(Q->mu[i]);
		E[i] = exp(-x);
		/* the linear source's weights: of the near level and the far */
		a[i] = x > 1e-6 ? (1.0 - E[i]) / x - E[i] : 0.5 * x;
		b[i] = x > 1e-6 ? 1.0 - (1.0 - E[i]) / x : 0.5 * x;
	}
	for (int i = 0; i < NG; i++) {
		double u = -Q->mu[i] * (NSKY - 1);
		int q = (int)u < NSKY - 1 ? (int)u : NSKY - 2;
		S->L[0][i] = p->sky_down[q][n][c] +
			     (u - q) * (p->sky_down[q + 1][n][c] - p->sky_down[q][n][c]);
	}
	for (int k = 0; k + 1 < S->nlev; k++)
		for (int i = 0; i < NG; i++)
			S->L[k + 1][i] = S->L[k][i] * E[i] + S->J[k][i] * a[i] + S->J[k + 1][i] * b[i];
	/* the ground: all that arrives, diffused */
	double e = n == 0 ? beam_at(p, S->nlev - 1, S->nlev, c) * p->mu0 : 0.0;
	for (int j = 0; j < NG && n == 0; j++)
		e += 2.0 * CS_PI * Q->wt[j] * -Q->mu[j] * S->L[S->nlev - 1][j];
	for (int j = NG; j < NO; j++)
		S->L[S->nlev - 1][j] = p->albedo_ground[c] * e / CS_PI;
	for (int k = S->nlev - 1; k > 0; k--)
		for (int i = NG; i < NO; i++)
			S->L[k - 1][i] = S->L[k][i] * E[i] + S->J[k][i] * a[i] + S->J[k - 1][i] * b[i];
}

/* The sources of mode n, channel c, from the radiance: the scattered
 * field and the sun's beam scattered once; the sum of the changes' sizes
 * into *norm; the largest change, relative to the largest source. */
static double scatter(struct solver *S, const struct cs_fog_problem *p, int n, int c,
		      double *norm)
{
	const struct quadrature *Q = S->q;
	double change = 0.0, peak = 1e-300;
	for (int k = 0; k < S->nlev; k++) {
		double sun = beam_at(p, k, S->nlev, c), sum[NO];
		for (int i = 0; i < NO; i++)
			sum[i] = sun * Q->psun[n][i];
		/* (every ordinate's sum at once, each in the order j) */
		for (int j = 0; j < NO; j++) {
			const double *P = Q->PT[n][j], L = S->L[k][j];
			for (int i = 0; i < NO; i++)
				sum[i] += P[i] * L;
		}
		for (int i = 0; i < NO; i++) {
			double s = sum[i] * p->albedo;
			S->dJ[k][i] = s - S->J[k][i];
			S->J[k][i] = s;
		}
	}
	/* (apart from the sums: their registers left peak on the stack, a
	 * chain of stores and loads that took most of the time) */
	double sum_d = 0.0;
	for (int k = 0; k < S->nlev; k++)
		for (int i = 0; i < NO; i++) {
			double d = fabs(S->dJ[k][i]), s = fabs(S->J[k][i]);
			sum_d += d;
			change = d > change ? d : change;
			peak = s > peak ? s : peak;
		}
	*norm = sum_d;
	return change / peak;
}

/* Mode n, channel c, solved: orders of scattering until they add less
 * than 1e-6 of the source.  Each order adds less than the one before, by
 * a ratio that settles (the slowest mode's: near 1 in thick fog, where
 * thousands of orders would be needed); once it has settled, the orders
 * still to come are a geometric series, added at once (Aitken's
 * extrapolation, as successive-orders codes such as 6S sum their tails),
 * and the orders go on from there.  The orders taken. */
static int solve_mode(struct solver *S, const struct cs_fog_problem *p, int n, int c)
{
	memset(S->J, 0, sizeof S->J);
	int orders = 0;
	double last = 0.0, ratio = 0.0;
	sweep(S, p, n, c);
	while (orders < MAX_ORDERS) {
		orders++;
		double norm, change = scatter(S, p, n, c, &norm);
		sweep(S, p, n, c);
		if (change < 1e-6)
			break;
		double r = last > 0.0 ? norm / last : 0.0;
		if (orders > 8 && r > 0.0 && r < 0.999 && fabs(r - ratio) < 1e-3 * (1.0 - r)) {
			double tail = r / (1.0 - r);
			for (int k = 0; k < S->nlev; k++)
				for (int i = 0; i < NO; i++)
					S->J[k][i] += tail * S->dJ[k][i];
			sweep(S, p, n, c);
			r = 0.0, norm = 0.0;
		}
		ratio = r, last = norm;
	}
	return orders;
}

/* Mode n, channel c of p into out's tables with S, whose phase
 * matrices (setup) are p's; the orders it took. */
static int solve(struct solver *S, const struct cs_fog_problem *p, int n, int c,
		 struct cs_fog_field *out)
{
	const struct quadrature *Q = S->q;
	/* levels at most FOG_DTAU apart in optical depth (the linear source
	 * between them loses 1 % of the light at 0.125 in a conservative
	 * slab of optical depth 16), up to MAX_LEV: beyond optical depth
	 * 12.8 they are further apart (MAX_SUB) */
	S->sub = (int)ceil(p->tau / (FOG_DTAU * (CS_FOG_LEVELS - 1)));
	S->sub = S->sub < 2 ? 2 : S->sub > MAX_SUB ? MAX_SUB : S->sub;
	S->nlev = S->sub * (CS_FOG_LEVELS - 1) + 1;
	int orders = solve_mode(S, p, n, c);
	for (int t = 0; t < CS_FOG_LEVELS; t++) {
		/* the table's level t, at the solution's x (linear between its
		 * levels) */
		double h = 1.0 - (double)t / (CS_FOG_LEVELS - 1);
		double x = (1.0 - h * h) * (S->nlev - 1);
		int k = (int)x < S->nlev - 1 ? (int)x : S->nlev - 2;
		double a = x - k, L[NO];
		for (int j = 0; j < NO; j++)
			L[j] = (1.0 - a) * S->L[k][j] + a * S->L[k + 1][j];
		/* the scattered field only: the sun's beam scattered once is
		 * the march's own term, with the full phase function, but for
		 * the part sun_field of it */
		double once = p->mu0 > 0.0 ? p->sun_field[c] *
						 exp(-p->tau * x / (S->nlev - 1) / p->mu0)
					   : 0.0;
		for (int m = 0; m < NDIR; m++) {
			double s = once * Q->psun_out[n][m];
			for (int j = 0; j < NO; j++)
				s += Q->Pout[n][m][j] * L[j];
			out->src[t][m][n][c] = (float)(p->albedo * s);
		}
		if (n > 0)
			continue;
		double dn = 0.0, upf = 0.0;
		for (int j = 0; j < NG; j++)
			dn += 2.0 * CS_PI * Q->wt[j] * -Q->mu[j] * L[j];
		for (int j = NG; j < NO; j++)
			upf += 2.0 * CS_PI * Q->wt[j] * Q->mu[j] * L[j];
		out->down[t][c] = dn;
		out->up[t][c] = upf;
	}
	return orders;
}

/* Whether a and b have the same quadrature (setup's inputs). */
static int same_setup(const struct cs_fog_problem *a, const struct cs_fog_problem *b)
{
	return a->g_forward == b->g_forward && a->g_back == b->g_back &&
	       a->w_forward == b->w_forward && a->mu0 == b->mu0;
}

/* cs_fog_solve_n's tasks: problem i's mode n, channel c, each on its
 * worker's own solver with its problem's quadrature (quad[i]) */
struct solve_job {
	const struct cs_fog_problem *p;
	struct cs_fog_field *out;
	const struct quadrature *const *quad; /* per problem */
	struct solver *work;     /* per worker */
	int *orders;             /* per task */
	int count;               /* problems */
};

/* Task t of count problems: its problem *i, mode *n and channel *c.
 * Mode 0 first, from the last problem (the deepest of a deck's): in deep
 * layers its orders of scattering are most of the work (hundreds against
 * tens for the other modes), and begun first they end together. */
static void task_of(int t, int count, int *i, int *n, int *c)
{
	*c = t % 3;
	if (t < 3 * count) {
		*i = count - 1 - t / 3, *n = 0;
		return;
	}
	t -= 3 * count;
	*i = count - 1 - t / (3 * (NMODE - 1)), *n = 1 + t / 3 % (NMODE - 1);
}

static void solve_task(void *user, int task, int worker)
{
	struct solve_job *job = user;
	int i, n, c;
	task_of(task, job->count, &i, &n, &c);
	struct solver *S = &job->work[worker];
	S->q = job->quad[i];
	job->orders[task] = solve(S, &job->p[i], n, c, &job->out[i]);
}

int cs_fog_solve_n(const struct cs_fog_problem *p, int n, struct cs_fog_field *out, int nthreads)
{
	if (n <= 0)
		return CS_OK;
	if (n > CS_FOG_MAX_PROBLEMS)
		return cs_error(CS_EINVAL, "fog: %d problems, at most %d", n, CS_FOG_MAX_PROBLEMS);
	for (int i = 0; i < n; i++)
		memset(&out[i], 0, sizeof out[i]);
	for (int i = 0; i < n; i++)
		if (!(p[i].tau >= 0.0) || !(p[i].tau <= 1e4) ||
		    !(p[i].albedo >= 0.0 && p[i].albedo <= 1.0))
			return cs_error(CS_EINVAL, "fog: optical depth %g or albedo %g out of range",
					p[i].tau, p[i].albedo);
	int tasks = n * NMODE * 3, orders[CS_FOG_MAX_PROBLEMS * NMODE * 3];
	nthreads = nthreads > 0 ? nthreads : cs_pool_cpus();
	nthreads = nthreads < tasks ? nthreads : tasks;
	struct quadrature *made = malloc((size_t)n * sizeof *made);
	struct solver *work = malloc((size_t)nthreads * sizeof *work);
	if (made == NULL || work == NULL) {
		free(made);
		free(work);
		return cs_error(CS_ENOMEM, "out of memory");
	}
	/* the quadratures, once for the problems that share one */
	const struct quadrature *quad[CS_FOG_MAX_PROBLEMS];
	for (int i = 0, nmade = 0; i < n; i++) {
		if (i > 0 && same_setup(&p[i], &p[i - 1])) {
			quad[i] = quad[i - 1];
			continue;
		}
		setup(&made[nmade], &p[i]);
		quad[i] = &made[nmade++];
	}
	struct solve_job job = {p, out, quad, work, orders, n};
	int rc = cs_pool_run(tasks, nthreads, solve_task, &job, NULL, NULL, NULL);
	for (int t = 0; t < tasks && rc == CS_OK; t++) {
		int i, mode, c;
		task_of(t, n, &i, &mode, &c);
		out[i].orders = orders[t] > out[i].orders ? orders[t] : out[i].orders;
		out[i].on = 1;
	}
	free(made);
	free(work);
	if (rc != CS_OK)
		for (int i = 0; i < n; i++)
			memset(&out[i], 0, sizeof out[i]);
	return rc;
}

int cs_fog_solve(const struct cs_fog_problem *p, struct cs_fog_field *out)
{
	return cs_fog_solve_n(p, 1, out, 1);
}

/* A droplet layer of optical depth tau of scene sc, lit from above by
 * the sun's beam sun[] (on a plane facing it) and, under other clouds, by
 * their diffuse light dome[] (radiance, isotropic), else by the clear
 * sky, over the ground of albedo ground[]. */
static void problem_of(const struct cs_scene *sc, double tau, const double sun[3],
		       const double *dome, const double ground[3], struct cs_fog_problem *p)
{
	memset(p, 0, sizeof *p);
	p->tau = tau;
	p->albedo = sc->albedo;
	p->g_forward = sc->g_forward, p->g_back = sc->g_back, p->w_forward = sc->w_forward;
	int up = (sc->effects & CS_FX_KEY) && sc->sun_dir.z > 0.0;
	p->mu0 = up ? sc->sun_dir.z : 0.0;
	for (int c = 0; c < 3; c++) {
		p->sun[c] = up ? sun[c] : 0.0;
		p->albedo_ground[c] = ground[c];
	}
	/* the sky's Fourier modes in the azimuth from the sun's (the light
	 * seen at azimuth a travels toward a + pi, as the sun's beam toward
	 * its azimuth + pi) */
	enum { NAZ = 64 };
	double sun_az = atan2(sc->sun_dir.x, sc->sun_dir.y);
	for (int j = 0; j < CS_FOG_SKY && (sc->effects & CS_FX_SKY); j++) {
		double mu = (double)j / (CS_FOG_SKY - 1), flat = sqrt(1.0 - mu * mu);
		for (int a = 0; a < NAZ && dome == NULL; a++) {
			double phi = 2.0 * CS_PI * (a + 0.5) / NAZ, az = sun_az + phi, rgb[3];
			cs_scene_sky(sc, v3(flat * sin(az), flat * cos(az), mu), rgb);
			for (int n = 0; n < CS_FOG_MODES; n++)
				for (int c = 0; c < 3; c++)
					p->sky_down[j][n][c] += rgb[c] * cos(n * phi) / NAZ;
		}
		for (int c = 0; c < 3 && dome != NULL; c++)
			p->sky_down[j][0][c] = dome[c];
	}
}

/* The fog of a scene is lit at its top by the sky, or under clouds by
 * what they let through (the deck's diffuse light, the sun's beam times
 * the area's mean transmittance), over the wet or dry flat ground. */
int cs_scene_fog_light(struct cs_scene *sc, int nthreads)
{
	memset(&sc->fog, 0, sizeof sc->fog);
	if (!(sc->fog_beta_per_m > 0.0) || !(sc->fog_top_m > sc->ground_alt_m))
		return CS_OK;
	double wet = sc->ground_wet > 0.0 ? sc->ground_wet : 1.0, sun[3], ground[3];
	for (int c = 0; c < 3; c++) {
		sun[c] = sc->sun_illuminance[c] * (sc->deck.on ? sc->deck.direct_below : 1.0);
		ground[c] = sc->ground_albedo[c] * wet;
	}
	struct cs_fog_problem p;
	problem_of(sc, sc->fog_beta_per_m * (sc->fog_top_m - sc->ground_alt_m), sun,
		   sc->deck.on ? sc->deck.sky_below : NULL, ground, &p);
	return cs_fog_solve_n(&p, 1, &sc->fog, nthreads);
}

/* The tilted columns' fields (struct cs_deck's tilt) and the layers'
 * shares of them (tilt_weight), where a layer is cumulonimbus of less
 * than CS_DECK_TILT_NONE cover, or cumulus of less than
 * CS_DECK_HEAP_TILT_NONE, and the key light is up (as problem_of
 * has it): slabs facing it, lit by its beam square on (mu0 1) and by
 * nothing else (the sky's light in a tower is cloud_ambient's), nothing
 * under them.  The share falls with the cover because the more the
 * towers merge, the more the slabs, with nothing beside them, overstate
 * their light: under a low sun (13 deg, the view of the study's scene)
 * against the path tracer at high, all of it measured +12 % at 22 %
 * cover, +31 % at 35 % and +89 % at 60 %, none of it -59, -51 and -11 %;
 * the share from 0.2 to 0.5, +7, -10 and -11 % (relative MSE 0.32, 0.31
 * and 0.40 against 0.57, 0.51 and 0.40 with none); from 0.25 to 0.5, +12
 * and -2 % (0.34, 0.32).  Heaps of cumulus are towers too, as wide as
 * they are tall: lit as the columns of a slab, the faces the sun lights
 * sent little back toward it, and cumulus with the sun behind the eye
 * (32 deg up, tests/scenes' cumulus-sun-behind) was -15 % against the
 * path tracer at high, relative MSE 0.128 (160x90); with the towers'
 * light (these fields, and the diffused light, tower_light.c) -9 %,
 * 0.046.
 * The heaps' share falls to 0 at CS_DECK_HEAP_TILT_NONE (80 %), not at
 * half cover: heaps stay apart longer than towers, whose anvils merge,
 * and with none (the march's model alone) thin cumulus of half cover was
 * +12.3 % against the path tracer at high (tests/scenes' cumulus-thin,
 * 320x180), its bases seen from below too bright.  Measured with
 * integrator.c's HEAP_WALL, both chosen on the study's five cumulus
 * scenes (320x180) and three more (160x90): the share's end at 0.5, 0.6,
 * 0.7 and 0.8 and the wall share from 0.6 to 0.85; with 0.8 and 0.65 the
 * five went from -2.7, -0.6, -6.3, -3.8 and +12.3 % to -2.5, +1.0, -3.4, -2.5
 * and +3.9 % (fair cumulus, the silver lining, the sun behind the eye,
 * the afternoon, thin; relative MSE 0.034, 0.027, 0.036, 0.029, 0.063
 * -> 0.041, 0.027, 0.031, 0.029, 0.029); five scenes held out from the
 * choice (40 to 75 % cover, sun 16 to 65 deg up, 160x90) from +3.9, +5.6,
 * +1.4, +5.2 and -1.4 % to +3.0, +3.0, +0.6, +5.2 (75 %: its light
 * fields light it alone from 70 %, cs_scene_deck_fields) and +0.6 %,
 * geometric mean relative MSE 0.0453 -> 0.0427.  Where a layer has
 * fields (above half cover, or thin for the beam) they take the share
 * field_weight of the light that is left, so that the heaps' share acts
 * as (1 - field_weight) of it. */
static void solve_tilt(struct cs_scene *sc, int nthreads);

static void tilt_fields(struct cs_scene *sc, int nthreads)
{
	struct cs_deck *d = &sc->deck;
	int any = 0;
	for (int i = 0; i < CS_SCENE_MAX_LAYERS; i++) {
		const struct cs_cloud_layer *l = &sc->layers[i];
		double none = l->genus == CS_CUMULUS ? CS_DECK_HEAP_TILT_NONE : CS_DECK_TILT_NONE;
		double w = (none - l->coverage) / (none - CS_DECK_TILT_FULL);
		int heaps = l->genus == CS_CUMULONIMBUS || l->genus == CS_CUMULUS;
		/* a layer its fields light alone takes nothing from the tilted
		 * columns (sample_source replaces their light with the
		 * fields'): the heaps' share, which reaches past
		 * CS_DECK_FIELD_FULL, is none there, so that no frame solves
		 * the columns and the towers' lattice, or builds the GPU's
		 * towers' kernel, for them (cumulus of 75 % cover at high: the
		 * same pixels, the scene 0.15 -> 0.06 s, the render 0.08 ->
		 * 0.02 s at 64x36) */
		int fields_alone = d->field_of[i] >= 0 && d->field_weight[i] >= 1.0;
		d->tilt_weight[i] = i < sc->nlayers && l->kind == CS_LAYER_CLOUD && heaps && w > 0.0 &&
					    !fields_alone
					    ? (w < 1.0 ? w : 1.0)
					    : 0.0;
		any |= d->tilt_weight[i] > 0.0;
	}
	if (!(any && d->on && (sc->effects & CS_FX_KEY) && sc->sun_dir.z > 0.0)) {
		for (int i = 0; i < CS_SCENE_MAX_LAYERS; i++)
			d->tilt_weight[i] = 0.0;
		return;
	}
	/* the towers' fields now (those any settings read:
	 * cs_tower_share with the heaps off); the heaps' where a frame's
	 * settings light them so (cs_scene_tilt_fields): at low and medium,
	 * which do not, they cost a scene of cumulus 0.07 s for nothing */
	const struct cs_render_settings heaps_off = {.heap_towers = 0};
	cs_scene_tilt_fields(sc, &heaps_off, nthreads);
}

int cs_scene_tilt_wanted(const struct cs_scene *sc, const struct cs_render_settings *s)
{
	if (sc->deck.tilt[0].on)
		return 0;
	for (int i = 0; i < sc->nlayers; i++)
		if (cs_tower_share(sc, s, i) > 0.0)
			return 1;
	return 0;
}

void cs_scene_tilt_fields(struct cs_scene *sc, const struct cs_render_settings *s, int nthreads)
{
	if (cs_scene_tilt_wanted(sc, s))
		solve_tilt(sc, nthreads);
}

/* The tilted columns' fields for the key light (sc->deck.tilt); where
 * they cannot be solved (out of memory) no layer has a towers' share:
 * the towers keep the octaves. */
static void solve_tilt(struct cs_scene *sc, int nthreads)
{
	struct cs_deck *d = &sc->deck;
	struct cs_fog_problem p[CS_DECK_DEPTHS];
	memset(p, 0, sizeof p);
	for (int k = 0; k < CS_DECK_DEPTHS; k++) {
		p[k].tau = d->tilt_tau[k] = CS_DECK_TILT_TAU0 * (double)(1 << (2 * k));
		p[k].albedo = sc->albedo;
		p[k].g_forward = sc->g_forward, p[k].g_back = sc->g_back;
		p[k].w_forward = sc->w_forward;
		p[k].mu0 = 1.0;
		for (int c = 0; c < 3; c++)
			p[k].sun[c] = sc->sun_illuminance[c];
	}
	if (cs_fog_solve_n(p, CS_DECK_DEPTHS, d->tilt, nthreads) != CS_OK)
		for (int i = 0; i < CS_SCENE_MAX_LAYERS; i++)
			d->tilt_weight[i] = 0.0;
}

/* The beam's slant depth through layer i, tau_in / mu0 (infinite without
 * a key light above the horizon). */
static double slant_depth(const struct cs_deck *d, int i)
{
	return d->mu0 > 0.0 ? d->tau_in[i] / d->mu0 : INFINITY;
}

/* The share of layer i's diffuse light that light fields give
 * (deck.field_weight): by its cover, 0 at CS_DECK_FIELD_COVER rising to 1
 * at CS_DECK_FIELD_FULL, and, whatever its cover, by how thin it is for
 * the key light's beam, its in-cloud depth over mu0: 1 at
 * CS_DECK_FIELD_THIN or less, 0 from CS_DECK_FIELD_THIN_END, linear
 * between; the larger.  A thin cloud's light has scattered a few times
 * near where it came in, so a broken veil's columns are lit as slabs
 * are, which the fields solve; the march's model of the diffuse light
 * (integrator.c, cloud_ambient) takes all the sun's light that a slab's
 * column scatters as diffuse, where in a veil most of it is still the
 * phase function's forward peak travelling with the beam, and its octaves
 * add as much light again at any depth: a homogeneous layer of optical
 * depth 0.25 to 0.8 came out 2.7 to 4.3 times as bright as the
 * adding-doubling slab seen from below (test_render), and the cirrus of
 * the meteoblue capture's fair hour (cover 0.32, in-cloud depth 0.56, the
 * sun 60 deg up) 2.4 times as bright in the sun's light as the path
 * tracer draws it.  Where the beam crosses the layer on a long slant path
 * (a low sun) it lights the cells' sides, which a slab's column has not:
 * cirrocumulus of half cover (in-cloud depth 0.84) toward the sun half a
 * degree up measured -19 % against the path tracer with fields, -5 % with
 * the model (test_reference).  Thicker broken layers keep the model too:
 * their cells lose light through their sides, and lit by fields the
 * accuracy study's long view through altocumulus of half cover (in-cloud
 * depth 4.4) went from -2.2 to -4.6 % against the path tracer (96x54). */
static double field_weight(const struct cs_scene *sc, int i)
{
	double w = (sc->layers[i].coverage - CS_DECK_FIELD_COVER) /
		   (CS_DECK_FIELD_FULL - CS_DECK_FIELD_COVER);
	double t = (CS_DECK_FIELD_THIN_END - slant_depth(&sc->deck, i)) /
		   (CS_DECK_FIELD_THIN_END - CS_DECK_FIELD_THIN);
	return cs_clamp01(t > w ? t : w);
}

/* The layers that fields may light, in the order they take the
 * CS_DECK_FIELDS sets: those of more than CS_DECK_FIELD_COVER in their
 * order, then the thin ones of less cover, thinnest for the beam first
 * (insertion: a few layers).  Returns their count; *thin: the first thin
 * one's place. */
static int field_candidates(const struct cs_scene *sc, int order[CS_SCENE_MAX_LAYERS], int *thin)
{
	const struct cs_deck *d = &sc->deck;
	int n = 0;
	for (int pass = 0; pass < 2; pass++) {
		if (pass == 1)
			*thin = n;
		for (int i = 0; i < sc->nlayers; i++) {
			if ((sc->layers[i].coverage > CS_DECK_FIELD_COVER) != (pass == 0) ||
			    !(field_weight(sc, i) > 0.0) || !(d->tau_in[i] > 0.0))
				continue;
			int k = n++;
			for (; pass == 1 && k > *thin && slant_depth(d, order[k - 1]) > slant_depth(d, i); k--)
				order[k] = order[k - 1];
			order[k] = i;
		}
	}
	return n;
}

void cs_scene_deck_fields(struct cs_scene *sc, int nthreads)
{
	struct cs_deck *d = &sc->deck;
	int used = 0;
	for (int i = 0; i < CS_SCENE_MAX_LAYERS; i++)
		d->field_of[i] = -1, d->field_weight[i] = 0.0;
	/* (a thin altocumulus first in the layers' order under a full
	 * cirrostratus had taken its fields) */
	int order[CS_SCENE_MAX_LAYERS], thin = 0;
	int n = d->on ? field_candidates(sc, order, &thin) : 0, next = 0;
	for (; next < n && used < CS_DECK_FIELDS; next++) {
		int i = order[next];
		const struct cs_cloud_layer *l = &sc->layers[i];
		/* under other layers: the sun's beam with the light their
		 * forward peak keeps along it (sun_lobe), and the rest of their
		 * diffuse light and the light sent between them and this one
		 * (top_extra), isotropic */
		int under = 0;
		for (int j = 0; j < sc->nlayers; j++)
			under |= cs_layer_share_above(sc, j, i) > 0.0;
		double sun[3], dome[3], lobe[3]; /* lobe: the peak's beyond the unscattered beam */
		for (int c = 0; c < 3; c++) {
			double excess = d->sun_lobe[i][c] - d->sun_top[i][c];
			lobe[c] = d->mu0 > 0.0 ? excess / d->mu0 : 0.0;
			sun[c] = d->mu0 > 0.0 ? d->sun_lobe[i][c] / d->mu0 : 0.0;
			dome[c] = (d->dif_top[i][c] + d->top_extra[i][c] - excess) / CS_PI;
			dome[c] = dome[c] > 0.0 ? dome[c] : 0.0;
		}
		/* the depths, and which of them the measured columns reach: a
		 * field is read for columns between its neighbours' depths; one
		 * no column reaches (a full deck's columns are all tau_in) is a
		 * copy of the nearest solved one, not solved itself */
		static const double share[CS_DECK_DEPTHS] = {1.0 / 16.0, 0.25, 1.0, 2.0};
		double *tau = d->field_tau[used];
		int need[CS_DECK_DEPTHS], any = 0, ok = 1;
		for (int k = 0; k < CS_DECK_DEPTHS; k++) {
			tau[k] = d->tau_in[i] * share[k];
			tau[k] = tau[k] < CS_DECK_FIELD_TAU_MAX ? tau[k] : CS_DECK_FIELD_TAU_MAX;
		}
		for (int k = 0; k < CS_DECK_DEPTHS; k++) {
			double below = k > 0 ? tau[k - 1] * (1.0 + 1e-9) : 0.0;
			double above = k < CS_DECK_DEPTHS - 1 ? tau[k + 1] * (1.0 - 1e-9) : INFINITY;
			need[k] = d->tau_lo[i] < above && d->tau_hi[i] > below &&
				  (k == 0 || tau[k] > tau[k - 1]);
			any |= need[k];
		}
		if (!any)
			need[CS_DECK_DEPTHS - 2] = 1; /* (no column measured: tau_in's) */
		/* the depths needed are consecutive (tau rises with k; equal
		 * depths, at the cap, only at the top): those below the first
		 * are its copies, those above the last the last's */
		int first = 0, last = CS_DECK_DEPTHS - 1;
		while (!need[first])
			first++;
		while (!need[last])
			last--;
		struct cs_fog_problem p[CS_DECK_DEPTHS];
		for (int k = first; k <= last; k++) {
			problem_of(sc, tau[k], sun, under ? dome : NULL, sc->deck.albedo_in[i], &p[k]);
			memcpy(p[k].sun_field, lobe, sizeof lobe);
		}
		ok = cs_fog_solve_n(p + first, last - first + 1, d->field[used] + first, nthreads) ==
		     CS_OK;
		for (int k = 0; k < CS_DECK_DEPTHS && ok; k++)
			if (k < first || k > last) {
				d->field[used][k] = d->field[used][k < first ? first : last];
				/* (a copy above the last is at its depth: the
				 * deepest field's, which fields_source scales from) */
				tau[k] = k > last ? tau[last] : tau[k];
			}
		if (!ok) /* (out of memory) the layer keeps the diffuse light's model */
			continue;
		d->field_weight[i] = field_weight(sc, i);
		d->field_deep[used] =
			cs_clamp01((l->coverage - CS_DECK_FIELD_FULL) / (1.0 - CS_DECK_FIELD_FULL));
		d->field_of[i] = used++;
	}
	/* a thin layer with fields gives way as the next thin one in line
	 * nears its slant depth, so that neither steps in light when they
	 * swap places (the sun sinking: three veils' light under them fell
	 * 26 % between two frames 0.03 deg apart) */
	for (int k = thin; k < next && next < n; k++) {
		int i = order[k];
		if (d->field_of[i] >= 0)
			d->field_weight[i] *= cs_clamp01(slant_depth(d, order[next]) - slant_depth(d, i));
	}
	tilt_fields(sc, nthreads); /* (after the fields: their weights) */
}
