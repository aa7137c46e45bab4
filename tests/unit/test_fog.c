/* The fog's light field (lib/render/fog.c) against closed forms and the
 * independent adding-doubling table: the phase function's azimuthal
 * modes, the slab's reflectance and transmittance, the isotropic
 * equilibrium, the sky's azimuthal modes. */
#include "core/err.h"
#include "render/march.h"
#include "render/phase.h"
#include "render/render.h"
#include "test.h"

/* A conservative fog problem with the clouds' two-lobe phase, no light. */
static void problem(struct cs_fog_problem *p, double tau, double g_forward, double g_back,
		    double w_forward, double albedo)
{
	memset(p, 0, sizeof *p);
	p->tau = tau, p->albedo = albedo;
	p->g_forward = g_forward, p->g_back = g_back, p->w_forward = w_forward;
}

/* The azimuthal mean of the two-lobe phase function (the elliptic
 * integral's closed form) against the azimuth integral summed on a
 * million points, for pairs of directions from the poles to the horizon,
 * the forward peak (equal directions) among them; and normalised: 2 pi
 * times its integral over the other direction's cosine is 1. */
static void phase_mean_is_the_azimuth_integral(void)
{
	const double mus[] = {-0.99, -0.6, -0.1, 0.0, 0.05, 0.3, 0.3, 0.97};
	const double nus[] = {-0.99, 0.2, -0.1, 0.0, 0.3, 0.3, -0.8, 0.95};
	enum { N = 1000000 };
	double worst = 0.0;
	for (int k = 0; k < 8; k++) {
		double mu = mus[k], nu = nus[k], s = sqrt((1 - mu * mu) * (1 - nu * nu)), sum = 0.0;
		for (int i = 0; i < N; i++)
			sum += cs_phase_two_lobe(mu * nu + s * cos(2.0 * CS_PI * (i + 0.5) / N), 0.9,
						 -0.3, 0.96, 1.0);
		sum /= N;
		double got = cs_fog_phase_mean(mu, nu, 0.9, -0.3, 0.96);
		double d = fabs(got / sum - 1.0);
		worst = d > worst ? d : worst;
		CHECK_NEAR(got, sum, 1e-6 * sum);
	}
	for (double mu = -1.0; mu <= 1.0; mu += 0.25) {
		enum { M = 200000 };
		double sum = 0.0;
		for (int i = 0; i < M; i++)
			sum += cs_fog_phase_mean(mu, -1.0 + 2.0 * (i + 0.5) / M, 0.85, 0.0, 1.0);
		CHECK_NEAR(2.0 * CS_PI * sum * 2.0 / M, 1.0, 2e-3);
	}
	printf("  largest relative difference %.2g\n", worst);
}

/* Plane albedo R and total transmittance T of a slab over a black ground
 * lit by a beam against every row of optical depth 16 or less of the
 * adding-doubling table tests/reference/slab-table.txt (an independent
 * solver that matches van de Hulst's 1980 tables to 1e-6): isotropic,
 * Henyey-Greenstein 0.85 and a two-lobe mixture, with and without
 * absorption, optical depths 0.1 to 16, beams at cosines 1 and 0.5;
 * within 0.01 (measured at most 0.006, at optical depth 16).  Thicker
 * slabs are outside what fog and decks ask for at the levels' 0.1 (at 50
 * the solver is 0.03 low in R). */
static void slab_matches_adding_doubling(void)
{
	char path[4096], line[512];
	FILE *f = fopen(t_top_path(path, sizeof path, "tests/reference/slab-table.txt"), "r");
	CHECK(f != NULL);
	if (f == NULL)
		return;
	static struct cs_fog_field fld;
	int rows = 0;
	double worst = 0.0;
	while (fgets(line, sizeof line, f)) {
		char phase[16], params[64];
		double w, mu0, tau, R, T, Td;
		if (line[0] == '#' ||
		    sscanf(line, "%15s %63s %lf %lf %lf %lf %lf %lf", phase, params, &w, &mu0, &tau, &R,
			   &T, &Td) != 8 || tau > 16.0)
			continue;
		double g1 = 0.0, g2 = 0.0, wf = 1.0;
		if (strcmp(phase, "HG") == 0) {
			CHECK(sscanf(params, "g=%lf", &g1) == 1);
			g2 = g1;
		} else if (strcmp(phase, "2HG") == 0)
			CHECK(sscanf(params, "wf=%lf,g1=%lf,g2=%lf", &wf, &g1, &g2) == 3);
		else
			CHECK(strcmp(phase, "isotropic") == 0);
		struct cs_fog_problem p;
		problem(&p, tau, g1, g2, wf, w);
		p.mu0 = mu0;
		p.sun[0] = p.sun[1] = p.sun[2] = 1.0;
		CHECK(cs_fog_solve(&p, &fld) == CS_OK);
		double r = fld.up[0][1] / mu0;
		double t = fld.down[CS_FOG_LEVELS - 1][1] / mu0 + exp(-tau / mu0);
		CHECK_NEAR(r, R, 0.01);
		CHECK_NEAR(t, T, 0.01);
		worst = fmax(worst, fmax(fabs(r - R), fabs(t - T)));
		rows++;
	}
	fclose(f);
	printf("  %d rows, largest difference %.4f\n", rows, worst);
	CHECK(rows == 59); /* the table's rows of optical depth 16 or less */
}

/* Conservative droplets over a white ground under an isotropic sky of
 * radiance 1: nothing is absorbed and nothing is lost, and the light is
 * isotropic and 1 everywhere (the only field the sky and the ground leave
 * unchanged); the source at every level and direction is 1, the light
 * down on a plane pi.  A fog that absorbed 1 % per order, or lost the
 * ground's return, would be 20 % dimmer somewhere. */
static void isotropic_light_stays_isotropic(void)
{
	struct cs_fog_problem p;
	problem(&p, 4.0, 0.9, -0.3, 0.96, 1.0);
	for (int j = 0; j < CS_FOG_SKY; j++)
		for (int c = 0; c < 3; c++)
			p.sky_down[j][0][c] = 1.0;
	p.albedo_ground[0] = p.albedo_ground[1] = p.albedo_ground[2] = 1.0;
	static struct cs_fog_field f;
	CHECK(cs_fog_solve(&p, &f) == CS_OK);
	double lo = 1e9, hi = -1e9;
	for (int k = 0; k < CS_FOG_LEVELS; k++)
		for (int m = 0; m < CS_FOG_DIRS; m++) {
			double v = f.src[k][m][0][1];
			lo = v < lo ? v : lo, hi = v > hi ? v : hi;
			for (int n = 1; n < CS_FOG_MODES; n++)
				CHECK(fabs(f.src[k][m][n][1]) < 1e-9);
		}
	printf("  source from %.4f to %.4f, light down at the ground %.4f (pi %.4f), %d orders\n", lo,
	       hi, f.down[CS_FOG_LEVELS - 1][1], CS_PI, f.orders);
	CHECK_NEAR(lo, 1.0, 0.01);
	CHECK_NEAR(hi, 1.0, 0.01);
	CHECK_NEAR(f.down[CS_FOG_LEVELS - 1][1], CS_PI, 0.01 * CS_PI);
	CHECK_NEAR(f.up[0][1], CS_PI, 0.01 * CS_PI);
}

/* At the top of a fog over a black ground the source toward a direction
 * is the droplets' phase function over the sky's light coming in (what
 * the fog itself adds there is small in a thin fog: at optical depth 0.02
 * the light it sends up, scattered on forward, was 14 % of the source
 * looking up 17 deg; at 1e-3, 1 %): for a sky brighter
 * toward one azimuth, 1 + 0.6 cos(phi) + 0.2 cos(2 phi), brighter toward
 * the zenith, the source read back through cs_fog_source (the modes put
 * together by the march's lookup) against the integral over the sky
 * summed on a 400 x 720 grid, in six directions; within 3 %.  A mode put together with
 * the wrong weight or sign, or the azimuth measured from the wrong
 * direction, is 10 to 60 % off. */
static void sky_modes_come_back_through_the_lookup(void)
{
	struct cs_fog_problem p;
	problem(&p, 1e-3, 0.9, -0.3, 0.96, 1.0);
	for (int j = 0; j < CS_FOG_SKY; j++) {
		double up = (double)j / (CS_FOG_SKY - 1), base = 0.5 + up;
		for (int c = 0; c < 3; c++) {
			p.sky_down[j][0][c] = base;
			p.sky_down[j][1][c] = base * 0.3; /* (1/2pi) int 0.6 cos^2 = 0.3 */
			p.sky_down[j][2][c] = base * 0.1;
		}
	}
	static struct cs_scene sc;
	memset(&sc, 0, sizeof sc);
	sc.ground_alt_m = 0.0, sc.fog_top_m = 100.0, sc.fog_beta_per_m = 1e-3 / 100.0;
	CHECK(cs_fog_solve(&p, &sc.fog) == CS_OK);
	const double dirs[6][2] = {{-0.5, 1.0}, {-0.5, -1.0}, {-0.5, 0.0},
				   {0.3, 1.0},  {0.8, -0.5}, {-0.95, 0.3}};
	for (int q = 0; q < 6; q++) {
		double mu = dirs[q][0], cphi = dirs[q][1], s = sqrt(1.0 - mu * mu);
		double sphi = sqrt(fmax(0.0, 1.0 - cphi * cphi));
		enum { NM = 400, NP = 720 };
		double want = 0.0;
		for (int a = 0; a < NM; a++) {
			double nu = -(a + 0.5) / NM, t = sqrt(1.0 - nu * nu); /* coming down */
			double sky = 0.5 + -nu;
			for (int b = 0; b < NP; b++) {
				double phi = 2.0 * CS_PI * (b + 0.5) / NP;
				double L = sky * (1.0 + 0.6 * cos(phi) + 0.2 * cos(2.0 * phi));
				double cth = mu * nu + s * t * (cphi * cos(phi) + sphi * sin(phi));
				want += L * cs_phase_two_lobe(cth, 0.9, -0.3, 0.96, 1.0);
			}
		}
		want *= (1.0 / NM) * (2.0 * CS_PI / NP);
		double got[3];
		cs_fog_source(&sc, 100.0, mu, cphi, got);
		printf("  mu %+.2f cos(phi) %+.2f: source %.4f, integral %.4f (%+.1f %%)\n", mu, cphi,
		       got[1], want, 100.0 * (got[1] / want - 1.0));
		CHECK_NEAR(got[1], want, 0.03 * want);
	}
}

/* Several problems at once (a deck's depths: one phase function, one
 * sun) on 1 and 3 threads: every field the same bits as each problem
 * solved on its own, whatever the threads; a fourth problem of another
 * sun among them too. */
static void problems_at_once_are_each_alone_on_any_threads(void)
{
	enum { N = 4 };
	static struct cs_fog_problem p[N];
	static struct cs_fog_field alone[N], one[N], three[N];
	static const double taus[N] = {0.5, 2.0, 8.0, 3.0};
	for (int i = 0; i < N; i++) {
		problem(&p[i], taus[i], 0.9, -0.3, 0.96, 0.99999);
		p[i].mu0 = i < 3 ? 0.6 : 0.3;
		for (int c = 0; c < 3; c++) {
			p[i].sun[c] = 100.0 + 10.0 * c;
			p[i].albedo_ground[c] = 0.1 + 0.05 * c;
			for (int j = 0; j < CS_FOG_SKY; j++)
				for (int n = 0; n < CS_FOG_MODES; n++)
					p[i].sky_down[j][n][c] = (5.0 + j + c) / (1.0 + n);
		}
		CHECK(cs_fog_solve(&p[i], &alone[i]) == CS_OK);
	}
	CHECK(cs_fog_solve_n(p, N, one, 1) == CS_OK);
	CHECK(cs_fog_solve_n(p, N, three, 3) == CS_OK);
	for (int i = 0; i < N; i++) {
		CHECK(alone[i].on && one[i].on && three[i].on);
		CHECK(memcmp(&alone[i], &one[i], sizeof alone[i]) == 0);
		CHECK(memcmp(&alone[i], &three[i], sizeof alone[i]) == 0);
	}
	/* (and they differ: a mix-up of problems would show) */
	CHECK(memcmp(&alone[0], &alone[1], sizeof alone[0]) != 0);
	CHECK(memcmp(&alone[2], &alone[3], sizeof alone[0]) != 0);
	/* a bad problem among them: none is on; too many: refused */
	p[1].tau = -1.0;
	CHECK(cs_fog_solve_n(p, N, three, 3) == CS_EINVAL);
	for (int i = 0; i < N; i++)
		CHECK(!three[i].on);
	p[1].tau = taus[1];
	static struct cs_fog_field many[CS_FOG_MAX_PROBLEMS + 1];
	static struct cs_fog_problem pm[CS_FOG_MAX_PROBLEMS + 1];
	CHECK(cs_fog_solve_n(pm, CS_FOG_MAX_PROBLEMS + 1, many, 2) == CS_EINVAL);
	CHECK(cs_fog_solve_n(p, 0, three, 2) == CS_OK);
	/* the azimuth's Fourier modes do not mix (the equation leaves each
	 * on its own): a sky of mode m alone, no sun, lights mode m and no
	 * other; every mode is solved */
	for (int m = 0; m < CS_FOG_MODES; m++) {
		problem(&p[m], 2.0, 0.9, -0.3, 0.96, 0.99999);
		for (int j = 0; j < CS_FOG_SKY; j++)
			for (int c = 0; c < 3; c++)
				p[m].sky_down[j][m][c] = 1.0 + j;
	}
	CHECK(cs_fog_solve_n(p, CS_FOG_MODES, three, 3) == CS_OK);
	for (int m = 0; m < CS_FOG_MODES; m++) {
		double own = 0.0, other = 0.0;
		for (int t = 0; t < CS_FOG_LEVELS; t++)
			for (int d = 0; d < CS_FOG_DIRS; d++)
				for (int n = 0; n < CS_FOG_MODES; n++)
					for (int c = 0; c < 3; c++)
						*(n == m ? &own : &other) += fabs(three[m].src[t][d][n][c]);
		printf("  a sky of mode %d alone: |source| %.3g in it, %.3g in the others\n", m, own,
		       other);
		CHECK(own > 1.0 && other == 0.0);
	}
}

/* Nonsense in is an error out, not a field. */
static void bad_problems_are_refused(void)
{
	struct cs_fog_problem p;
	static struct cs_fog_field f;
	problem(&p, -1.0, 0.9, -0.3, 0.96, 1.0);
	CHECK(cs_fog_solve(&p, &f) == CS_EINVAL && !f.on);
	problem(&p, NAN, 0.9, -0.3, 0.96, 1.0);
	CHECK(cs_fog_solve(&p, &f) == CS_EINVAL);
	problem(&p, 4.0, 0.9, -0.3, 0.96, 1.5);
	CHECK(cs_fog_solve(&p, &f) == CS_EINVAL);
	problem(&p, 4.0, 0.9, -0.3, 0.96, 1.0);
	CHECK(cs_fog_solve(&p, &f) == CS_OK && f.on);
}

static const struct t_case t_cases[] = {
	CASE(phase_mean_is_the_azimuth_integral),
	CASE(slab_matches_adding_doubling),
	CASE(isotropic_light_stays_isotropic),
	CASE(sky_modes_come_back_through_the_lookup),
	CASE(problems_at_once_are_each_alone_on_any_threads),
	CASE(bad_problems_are_refused),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
