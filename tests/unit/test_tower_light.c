/* test_tower_light - the towers' diffused light (render/tower_light.c):
 * the diffusion solver against closed forms, and the field's effect on a
 * cumulonimbus seen from the side against the path tracer. */
#include "core/color.h"
#include "core/err.h"
#include "core/time.h"
#include "noise/volume.h"
#include "render/camera.h"
#include "render/reference.h"
#include "render/render.h"
#include "render/scene.h"
#include "one_layer.h"
#include "test.h"
#include "weather/wx.h"

#include <stdlib.h>
#include <string.h>

/* A slab nu x nv x nk of uniform transport extinction str (1/m),
 * conservative, lit at its top by a beam of unit irradiance at mu0 (its
 * power given up to scattering, sigma_tr e^(-sigma_tr s / mu0) a unit
 * volume at depth s under the similarity relation, integrated over each
 * node's volume), j_top and j_bottom coming in: the solver's fluence at
 * each level into phi_k (nk values, the columns all alike). */
static void solve_slab_as(int mode, int nk, double H, double str, double mu0, double j_top,
			  double j_bot, double *phi_k)
{
	enum { NU = 3, NV = 3 };
	double du = 100.0, dh = H / (nk - 1);
	size_t n = (size_t)NU * NV * nk;
	float *st = malloc(n * sizeof *st), *sa = calloc(n, sizeof *sa), *phi = malloc(n * sizeof *phi);
	double *src = calloc(n, sizeof *src);
	CHECK(st != NULL && sa != NULL && phi != NULL && src != NULL);
	double k = str / mu0;
	for (size_t m = 0; m < n; m++) {
		int lev = (int)(m % (size_t)nk); /* level: 0 the base */
		double top = H - lev * dh;       /* depth of the node under the top */
		double s0 = top - 0.5 * dh, s1 = top + 0.5 * dh;
		s0 = s0 > 0.0 ? s0 : 0.0;
		s1 = s1 < H ? s1 : H;
		st[m] = (float)str;
		/* the beam's loss over the node's volume: mu0 (e^-k s0 - e^-k s1) */
		src[m] = du * du * mu0 * (exp(-k * s0) - exp(-k * s1));
	}
	double j_in[2] = {j_top, j_bot};
	int it = 0;
	CHECK(cs_diffusion_solve(NU, NV, nk, du, du, dh, st, sa, src, j_in, NULL, mode, 1, phi, &it) ==
	      CS_OK);
	CHECK(it > 0);
	for (int lev = 0; lev < nk; lev++)
		phi_k[lev] = phi[(size_t)(1 * NU + 1) * nk + lev];
	free(st), free(sa), free(phi), free(src);
}

static void solve_slab(int nk, double H, double str, double mu0, double j_top, double j_bot,
		       double *phi_k)
{
	solve_slab_as(0, nk, H, str, mu0, j_top, j_bot, phi_k);
}

/* The closed form of the same problem in depth s from the top:
 * -D phi'' = sigma e^(-k s), k = sigma / mu0, D = 1 / (3 sigma), so
 * phi = A + B s - 3 mu0^2 e^(-k s), with Marshak's conditions
 * D phi'(0) = phi(0) / 2 - 2 J_top and -D phi'(H) = phi(H) / 2 - 2 J_bottom
 * (the outward flux at each face), two equations for A and B. */
static double slab_closed_form(double s, double H, double str, double mu0, double j_top,
			       double j_bot)
{
	double D = 1.0 / (3.0 * str), k = str / mu0, c = 3.0 * mu0 * mu0, e = exp(-k * H);
	/* top:    -A/2 + D B          = -c/2 - 2 Jt - D c k
	 * bottom: -A/2 - (H/2 + D) B  = -c e/2 - 2 Jb + D c k e */
	double a11 = -0.5, a12 = D, b1 = -0.5 * c - 2.0 * j_top - D * c * k;
	double a21 = -0.5, a22 = -(0.5 * H + D), b2 = -0.5 * c * e - 2.0 * j_bot + D * c * k * e;
	double det = a11 * a22 - a12 * a21;
	double A = (b1 * a22 - a12 * b2) / det, B = (a11 * b2 - b1 * a21) / det;
	return A + B * s - c * exp(-k * s);
}

static void diffusion_matches_the_slab_closed_form(void)
{
	/* transport depths 2 and 20 (a thick tower's 100 m to a km at
	 * sigma_tr 0.01 /m), a sun 30 and 90 deg up, the sky's light too */
	static const struct {
		double H, mu0, jt, jb;
	} c[] = {{200.0, 1.0, 0.0, 0.0}, {2000.0, 0.5, 0.0, 0.0}, {2000.0, 1.0, 0.3, 0.1}};
	for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
		enum { NK = 401 };
		static double phi[NK];
		double str = 0.01;
		solve_slab(NK, c[i].H, str, c[i].mu0, c[i].jt, c[i].jb, phi);
		double worst = 0.0;
		for (int lev = 0; lev < NK; lev += 10) {
			double s = c[i].H - lev * c[i].H / (NK - 1);
			double want = slab_closed_form(s, c[i].H, str, c[i].mu0, c[i].jt, c[i].jb);
			double err = fabs(phi[lev] / want - 1.0);
			worst = err > worst ? err : worst;
		}
		/* the diffuse flux leaving the base: phi(H) / 2 - 2 J_bottom */
		double out = phi[0] / 2.0 - 2.0 * c[i].jb;
		double want = slab_closed_form(c[i].H, c[i].H, str, c[i].mu0, c[i].jt, c[i].jb) / 2.0 -
			      2.0 * c[i].jb;
		printf("  depth %.0f, mu0 %.1f: fluence within %.2g %%; diffuse flux out the base %.5f "
		       "(closed form %.5f)\n",
		       c[i].H * str, c[i].mu0, 100.0 * worst, out, want);
		CHECK(worst < 0.01);
		CHECK_NEAR(out, want, 0.01 * want);
	}
}

/* The independent columns (CS_DIFFUSE_COLUMNS, a deck's reference in
 * tower_light.c's deck_ratio) solved directly: a uniform slab's columns
 * are the slab, so the same closed form within 1 %; and a column's
 * light is its own: with the column beside it made clear, the 3D
 * lattice's middle column changes (its side now takes the light of the
 * clear air), the columns' does not, to the last bit. */
static void columns_match_the_slab_and_ignore_their_neighbours(void)
{
	enum { NK = 401 };
	static double phi[NK];
	double H = 2000.0, str = 0.01, mu0 = 0.5;
	solve_slab_as(CS_DIFFUSE_COLUMNS, NK, H, str, mu0, 0.3, 0.1, phi);
	double worst = 0.0;
	for (int lev = 0; lev < NK; lev += 10) {
		double want = slab_closed_form(H - lev * H / (NK - 1), H, str, mu0, 0.3, 0.1);
		double err = fabs(phi[lev] / want - 1.0);
		worst = err > worst ? err : worst;
	}
	printf("  columns: fluence within %.2g %% of the closed form\n", 100.0 * worst);
	CHECK(worst < 0.01);
	enum { N3 = 3, K = 11 };
	size_t n = (size_t)N3 * N3 * K;
	float st[N3 * N3 * K], sa[N3 * N3 * K], out[2][2][N3 * N3 * K];
	double src[N3 * N3 * K], j_in[2] = {0.3, 0.05};
	for (int mode = 0; mode < 2; mode++)
		for (int cleared = 0; cleared < 2; cleared++) {
			for (size_t m = 0; m < n; m++) {
				size_t col = m / K;
				st[m] = cleared && col == 1 * N3 + 2 ? 0.0f : 0.004f;
				sa[m] = 0.0f;
				src[m] = st[m] > 0.0f ? 100.0 * (double)(m % K) : 0.0;
			}
			int it = 0;
			CHECK(cs_diffusion_solve(N3, N3, K, 200.0, 200.0, 100.0, st, sa, src, j_in, NULL,
						 mode ? CS_DIFFUSE_COLUMNS : 0, 1, out[mode][cleared],
						 &it) == CS_OK);
		}
	size_t mid = (size_t)(1 * N3 + 1) * K + K / 2;
	printf("  the middle column's middle, its neighbour cloud then clear: 3D %.5f -> %.5f, "
	       "columns %.5f -> %.5f\n",
	       out[0][0][mid], out[0][1][mid], out[1][0][mid], out[1][1][mid]);
	CHECK(fabsf(out[0][1][mid] / out[0][0][mid] - 1.0f) > 0.01f);
	for (int k = 0; k < K; k++)
		CHECK(out[1][0][(size_t)(1 * N3 + 1) * K + k] == out[1][1][(size_t)(1 * N3 + 1) * K + k]);
}

/* A slab of cloud between clear nodes (levels 1 .. NK - 2 of cloud; 0
 * and NK - 1 clear, its faces half a level beyond its outer nodes),
 * absorbing sigma_a, no source, the light j_top coming in from above and
 * j_bot from below: -D phi'' + sigma_a phi = 0 in height z over the
 * slab's thickness L, with Marshak's condition at both faces (outward
 * flux phi / 2 - 2 J), phi = A cosh(k z) + B sinh(k z), k^2 = sigma_a / D
 * (phi = A + B z without absorption): the solver's nodes within 0.5 %. */
static void diffusion_slab_in_clear_air_matches_the_closed_form(void)
{
	enum { NU = 3, NV = 3, MAXK = 202 };
	static float st[NU * NV * MAXK], sa[NU * NV * MAXK], phi[NU * NV * MAXK];
	static double src[NU * NV * MAXK];
	double str = 0.01, D = 1.0 / (3.0 * str);
	/* cells of 400 m, ten times D (a face's conductance there is far
	 * from Marshak's 1/2), and of 10 m for the absorption's curve */
	static const double absorb[] = {0.0, 0.0, 1e-4};
	static const int levels[] = {12, 202, 202};
	static const double cell[] = {400.0, 10.0, 10.0};
	for (size_t c = 0; c < sizeof absorb / sizeof absorb[0]; c++) {
		int NK = levels[c];
		double dh = cell[c], L = (NK - 2) * dh;
		for (size_t m = 0; m < (size_t)NU * NV * NK; m++) {
			int k = (int)(m % NK);
			int cloud = k > 0 && k < NK - 1;
			st[m] = cloud ? (float)str : 0.0f;
			sa[m] = cloud ? (float)absorb[c] : 0.0f;
			src[m] = 0.0;
		}
		double jt = 0.3, jb = 0.05, j_in[2] = {jt, jb};
		int it;
		CHECK(cs_diffusion_solve(NU, NV, NK, 50.0, 50.0, dh, st, sa, src, j_in, NULL, 0, 1, phi, &it) ==
		      CS_OK);
		double kk = sqrt(absorb[c] / D), A, B;
		if (kk > 0.0) {
			/* bottom: D k B = A / 2 - 2 jb; top: -D k (A sh + B ch) =
			 * (A ch + B sh) / 2 - 2 jt */
			double ch = cosh(kk * L), sh = sinh(kk * L);
			double a11 = 0.5, a12 = -D * kk, b1 = 2.0 * jb;
			double a21 = 0.5 * ch + D * kk * sh, a22 = 0.5 * sh + D * kk * ch, b2 = 2.0 * jt;
			double det = a11 * a22 - a12 * a21;
			A = (b1 * a22 - a12 * b2) / det;
			B = (a11 * b2 - b1 * a21) / det;
		} else {
			B = 4.0 * (jt - jb) / (4.0 * D + L);
			A = 2.0 * D * B + 4.0 * jb;
		}
		double worst = 0.0;
		for (int k = 1; k < NK - 1; k++) {
			double z = (k - 0.5) * dh;
			double want = kk > 0.0 ? A * cosh(kk * z) + B * sinh(kk * z) : A + B * z;
			double err = fabs(phi[(size_t)(NU + 1) * NK + (size_t)k] / want - 1.0);
			worst = err > worst ? err : worst;
		}
		printf("  cells %g m, absorption %g /m: fluence within %.2g %% of the closed form (top "
		       "%.4f, bottom %.4f)\n",
		       dh, absorb[c], 100.0 * worst, phi[(size_t)(NU + 1) * NK + NK - 2],
		       phi[(size_t)(NU + 1) * NK + 1]);
		CHECK(worst < 0.005);
	}
}

/* A slab with three clear levels across its middle: what leaves the cloud
 * above the gap enters the cloud below it, and the other way round (every
 * ray from the gap meets one or the other), so that with Marshak's
 * condition at both faces the fluence and the flux carry on across the
 * gap unchanged: the slab's closed form with the gap taken out.  Without
 * the light sent across (the gap's faces taking the sky's and the
 * ground's light) the fluence near the gap is several times off. */
static void diffusion_carries_the_light_across_a_gap(void)
{
	enum { NU = 3, NV = 3, NK = 43, GAP = 20, GAPS = 3 }; /* clear: levels GAP .. GAP + GAPS - 1 */
	static float st[NU * NV * NK], sa[NU * NV * NK], phi[NU * NV * NK];
	static double src[NU * NV * NK];
	double dh = 50.0, H = (NK - 1) * dh, Hc = H - GAPS * dh, str = 0.01, mu0 = 1.0;
	double k = str / mu0, jt = 0.3, jb = 0.1, j_in[2] = {jt, jb};
	for (size_t m = 0; m < (size_t)NU * NV * NK; m++) {
		int lev = (int)(m % NK), clear = lev >= GAP && lev < GAP + GAPS;
		/* the depth under the top with the gap taken out */
		double s = H - lev * dh - (lev < GAP ? GAPS * dh : 0.0);
		double s0 = s - 0.5 * dh, s1 = s + 0.5 * dh;
		s0 = s0 > 0.0 ? s0 : 0.0;
		s1 = s1 < Hc ? s1 : Hc;
		st[m] = clear ? 0.0f : (float)str;
		sa[m] = 0.0f;
		src[m] = clear ? 0.0 : 100.0 * 100.0 * mu0 * (exp(-k * s0) - exp(-k * s1));
	}
	for (int exchange = 0; exchange <= 1; exchange++) {
		int it;
		CHECK(cs_diffusion_solve(NU, NV, NK, 100.0, 100.0, dh, st, sa, src, j_in, NULL, exchange,
					 2, phi, &it) == CS_OK);
		double worst = 0.0;
		for (int lev = 0; lev < NK; lev++) {
			if (lev >= GAP && lev < GAP + GAPS)
				continue;
			double s = H - lev * dh - (lev < GAP ? GAPS * dh : 0.0);
			double want = slab_closed_form(s, Hc, str, mu0, jt, jb);
			double err = fabs(phi[(size_t)(NU + 1) * NK + (size_t)lev] / want - 1.0);
			worst = err > worst ? err : worst;
		}
		printf("  %s the exchange: fluence within %.2g %% of the slab without the gap (%d "
		       "iterations)\n",
		       exchange ? "with" : "without", 100.0 * worst, it);
		CHECK(exchange ? worst < 0.01 : worst > 0.5);
	}
}

/* With no source and the same light J coming in at every face, a
 * conservative cloud of any shape fills with it: phi = 4 J (the radiance
 * J / pi from every direction). */
static void diffusion_fills_with_the_light_around(void)
{
	enum { NU = 12, NV = 10, NK = 9 };
	size_t n = (size_t)NU * NV * NK;
	static float st[NU * NV * NK], sa[NU * NV * NK], phi[NU * NV * NK];
	static double src[NU * NV * NK];
	for (size_t m = 0; m < n; m++) {
		int k = (int)(m % NK), i = (int)(m / NK % NU), j = (int)(m / NK / NU);
		/* a block of cloud, clear air around it, with a hole of 3 x 3 x 3
		 * nodes whose faces exchange their light (across the hole, from
		 * the third cell on) */
		int hole = i >= 4 && i <= 6 && j >= 3 && j <= 5 && k >= 3 && k <= 5;
		int cloud = i >= 1 && i <= 10 && k >= 1 && k <= 7 && !hole;
		st[m] = cloud ? (float)(0.001 * (1 + (m % 5))) : 0.0f;
		sa[m] = 0.0f;
		src[m] = 0.0;
	}
	double j_in[2] = {0.25, 0.25};
	for (int exchange = 0; exchange <= 1; exchange++) {
		int it;
		CHECK(cs_diffusion_solve(NU, NV, NK, 300.0, 200.0, 250.0, st, sa, src, j_in, NULL,
					 exchange, 2, phi, &it) == CS_OK);
		for (size_t m = 0; m < n; m++)
			if (st[m] > 0.0f)
				CHECK_NEAR(phi[m], 1.0, 1e-4);
	}
}

/* One node of cloud alone in a layer, with no source: its fluence is
 * 4 times the mean of the light J coming in at its six faces, weighted
 * by their conductances c = area a / (2 a + 1), a = 2 D / d.  With the
 * exchange each face's J is what the clear node beside it sees over the
 * half of 48 directions (a spherical Fibonacci set) away from the face,
 * weighted by the cosine: here only the sky (j_top) and the ground, whose
 * light varies from column to column.  The column a direction reaches is
 * computed here from the geometry (where the straight line from the clear
 * node's centre crosses the layer's base, to the nearest column), not by
 * the solver's walk from cell to cell; the node sits at the lattice's
 * corner, so that directions wrap across both periods (nu != nv). */
static void exchange_sees_the_ground_where_each_direction_meets_it(void)
{
	enum { NU = 40, NV = 30, NK = 6, K0 = 2 };
	size_t n = (size_t)NU * NV * NK, m0 = K0; /* node (0, 0, K0) */
	static float st[NU * NV * NK], sa[NU * NV * NK], phi[NU * NV * NK];
	static double src[NU * NV * NK], ground[NU * NV];
	double du = 100.0, dv = 80.0, dh = 50.0, sigma = 0.01, j_top = 0.3;
	for (size_t m = 0; m < n; m++)
		st[m] = m == m0 ? (float)sigma : 0.0f, sa[m] = 0.0f, src[m] = 0.0;
	for (int c = 0; c < NU * NV; c++)
		ground[c] = 0.05 + 0.02 * ((c * 7919) % 11);
	double dir[48][3];
	for (int q = 0; q < 48; q++) {
		double z = 1.0 - (2.0 * q + 1.0) / 48, r = sqrt(1.0 - z * z), a = q * 2.39996322972865332;
		dir[q][0] = r * cos(a), dir[q][1] = r * sin(a), dir[q][2] = z;
	}
	/* the faces +u, -u, +v, -v, +k, -k: the clear node beside each */
	static const int e[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
	double cell[3] = {du, dv, dh}, D = 1.0 / (3.0 * sigma), num[2] = {0, 0}, den = 0.0;
	for (int f = 0; f < 6; f++) {
		double x = e[f][0] * du, y = e[f][1] * dv, z = (K0 + e[f][2]) * dh;
		double sum = 0.0, wsum = 0.0;
		for (int q = 0; q < 48; q++) {
			double w = e[f][0] * dir[q][0] + e[f][1] * dir[q][1] + e[f][2] * dir[q][2];
			if (!(w > 0.0))
				continue;
			double R = j_top;
			if (dir[q][2] < 0.0) { /* the ground where the line meets the base */
				double t = z / -dir[q][2];
				long i = lround((x + t * dir[q][0]) / du), j = lround((y + t * dir[q][1]) / dv);
				i = ((i % NU) + NU) % NU, j = ((j % NV) + NV) % NV;
				R = ground[j * NU + i];
			}
			sum += w * R, wsum += w;
		}
		double Jx = sum / wsum; /* with the exchange */
		double up = ground[0], J0 = f < 4 ? 0.5 * (j_top + up) : f == 4 ? j_top : up;
		double a = 2.0 * D / cell[f / 2];
		double area = cell[0] * cell[1] * cell[2] / cell[f / 2];
		double c = area * a / (2.0 * a + 1.0);
		num[0] += c * 4.0 * J0, num[1] += c * 4.0 * Jx, den += c;
	}
	double j_in[2] = {j_top, 0.0};
	for (int exchange = 0; exchange <= 1; exchange++) {
		int it;
		CHECK(cs_diffusion_solve(NU, NV, NK, du, dv, dh, st, sa, src, j_in, ground, exchange, 1,
					 phi, &it) == CS_OK);
		printf("  %s the exchange: fluence %.6f (from the geometry %.6f)\n",
		       exchange ? "with" : "without", phi[m0], num[exchange] / den);
		CHECK_NEAR(phi[m0], num[exchange] / den, 1e-5 * num[exchange] / den);
	}
}

/* The exchange's rays are traced on the CPU pool, TRACE_BATCH clear nodes
 * a task: the fluence is the same to the bit on 1 and 3 threads (here
 * 1341 clear nodes next to cloud, six tasks), with the ground's
 * light varying under the columns. */
static void exchange_is_the_same_on_any_number_of_threads(void)
{
	enum { NU = 24, NV = 20, NK = 12 };
	size_t n = (size_t)NU * NV * NK;
	static float st[NU * NV * NK], sa[NU * NV * NK], phi[2][NU * NV * NK];
	static double src[NU * NV * NK], ground[NU * NV];
	for (size_t m = 0; m < n; m++) {
		int k = (int)(m % NK), i = (int)(m / NK % NU), j = (int)(m / NK / NU);
		/* towers of a few nodes across, of uneven heights */
		int di = i % 8 - 3, dj = j % 7 - 3, top = 4 + (i / 8 + 2 * (j / 7)) % 7;
		int cloud = di * di + dj * dj <= 5 && k >= 1 && k <= top;
		st[m] = cloud ? (float)(0.002 * (1 + (m % 3))) : 0.0f;
		sa[m] = cloud ? 1e-6f : 0.0f;
		src[m] = cloud && k == top ? 1e4 : 0.0;
	}
	for (int c = 0; c < NU * NV; c++)
		ground[c] = 0.05 + 0.01 * (c % 7);
	double j_in[2] = {0.3, 0.1};
	int it[2];
	for (int r = 0; r < 2; r++)
		CHECK(cs_diffusion_solve(NU, NV, NK, 400.0, 400.0, 300.0, st, sa, src, j_in, ground, 1,
					 r == 0 ? 1 : 3, phi[r], &it[r]) == CS_OK);
	CHECK(it[0] == it[1] && memcmp(phi[0], phi[1], sizeof phi[0]) == 0);
}

/* sc: one layer of genus, cover and base and top (m) over the default
 * site (wx) at when (UTC), on noise baked at n^3, without haze (the path
 * tracer has none). */
static void one_layer(struct cs_scene *sc, struct cs_volume *noise, struct cs_wx *wx, int n,
		      const char *when, enum cs_genus genus, double cover, double base_m,
		      double top_m)
{
	CHECK(cs_volume_new(noise, n, n) == CS_OK && cs_volume_bake(noise, 0, NULL, NULL) == CS_OK);
	one_layer_wx(wx, when, genus, cover, base_m, top_m, 40000.0);
	CHECK(cs_scene_build(sc, wx, wx->time_utc, noise) == CS_OK);
	sc->haze_beta0_per_m = 0.0;
}

/* The study's cumulonimbus side view (tests/scenes/cumulonimbus-side, on
 * a 32^3 noise, 32x18 pixels): the march at high within 12 % of the path
 * tracer's mean luminance (32 paths a pixel, seed 1) with the towers'
 * diffused light (measured -5.8 %; -7.5 % without the light its faces
 * exchange through clear air), not without it (-18.2 %: the towers'
 * bases and the anvil over the eye, lit by light scattered tens of
 * times, too dark). */
static void side_view_is_nearer_the_path_tracer_with_the_field(void)
{
	static struct cs_volume noise;
	static struct cs_scene sc;
	struct cs_wx wx;
	one_layer(&sc, &noise, &wx, 32, "2021-06-14T15:00:00Z", CS_CUMULONIMBUS, 0.04, 1200.0, 11000.0);
	struct cs_camera cam;
	enum { W = 32, H = 18 };
	CHECK(cs_camera_init(&cam, &sc, v3(0, 0, wx.site.alt_m), wx.site.lat_deg, 150.0, 8.0, 75.0, W,
			     H) == CS_OK);
	static float img[W * H * 5];
	struct cs_render_stats st;
	double y[2];
	for (int with = 0; with < 2; with++) {
		struct cs_render_settings s;
		CHECK(cs_render_quality("high", &s) == CS_OK);
		s.tower_cell_m = with ? s.tower_cell_m : 0.0;
		CHECK(cs_render_image(&sc, &cam, &s, 2, NULL, NULL, img, &st) == CS_OK);
		y[with] = 0.0;
		for (int i = 0; i < W * H; i++)
			y[with] += cs_luminance(img[5 * i], img[5 * i + 1], img[5 * i + 2]) / (W * H);
	}
	struct cs_reference_settings rs = {32, 1, 0};
	CHECK(cs_render_reference(&sc, &cam, &rs, 2, NULL, NULL, img, NULL, &st) == CS_OK);
	double yr = 0.0;
	for (int i = 0; i < W * H; i++)
		yr += cs_luminance(img[5 * i], img[5 * i + 1], img[5 * i + 2]) / (W * H);
	printf("  side view: march without the field %.3f (%+.1f %%), with %.3f (%+.1f %%), path "
	       "tracer %.3f\n",
	       y[0], 100.0 * (y[0] / yr - 1.0), y[1], 100.0 * (y[1] / yr - 1.0), yr);
	CHECK_NEAR(y[1] / yr, 1.0, 0.12);
	CHECK(fabs(y[0] / yr - 1.0) > 0.12);
	cs_volume_free(&noise);
}

/* The mean luminance of the cloud's pixels (W x H, 70 deg wide, looking
 * az, el from the site) of one layer of cumulus on a 128^3 noise, by the
 * march at high with its heaps lit as towers (y[1]) and not (y[0]), and
 * by the path tracer with 16 paths a pixel (yr), kcd/m^2: with them
 * within 4 % of the path tracer, and at least 3 points nearer than
 * without. */
static void heaps_against_the_path_tracer(const char *when, double cover, double base_m,
					  double top_m, double az, double el)
{
	double y[2], yr = 0.0;
	static struct cs_volume noise;
	static struct cs_scene sc;
	struct cs_wx wx;
	one_layer(&sc, &noise, &wx, 128, when, CS_CUMULUS, cover, base_m, top_m);
	CHECK(sc.deck.tilt_weight[0] > 0.0);
	/* the heaps' tilted columns are solved for a frame that wants them
	 * (high's), not with the scene (medium's do not) */
	struct cs_render_settings hi, med;
	CHECK(cs_render_quality("high", &hi) == CS_OK && cs_render_quality("medium", &med) == CS_OK);
	CHECK(!sc.deck.tilt[0].on && cs_scene_tilt_wanted(&sc, &hi) && !cs_scene_tilt_wanted(&sc, &med));
	struct cs_camera cam;
	enum { W = 64, H = 36 };
	CHECK(cs_camera_init(&cam, &sc, v3(0, 0, wx.site.alt_m), wx.site.lat_deg, az, el, 70.0, W,
			     H) == CS_OK);
	static float img[W * H * 5];
	static unsigned char cloud[W * H];
	memset(cloud, 0, sizeof cloud);
	struct cs_render_stats st;
	for (int with = 1; with >= 0; with--) {
		struct cs_render_settings s;
		CHECK(cs_render_quality("high", &s) == CS_OK);
		CHECK(s.heap_towers == 1); /* (high's) */
		s.heap_towers = with;
		CHECK(cs_render_image(&sc, &cam, &s, 2, NULL, NULL, img, &st) == CS_OK);
		y[with] = 0.0;
		for (int i = 0; i < W * H; i++) {
			cloud[i] |= img[5 * i + 3] >= 0.5f; /* (the same with and without) */
			y[with] += cloud[i] ? cs_luminance(img[5 * i], img[5 * i + 1], img[5 * i + 2]) : 0.0;
		}
	}
	struct cs_reference_settings rs = {16, 1, 0};
	CHECK(cs_render_reference(&sc, &cam, &rs, 2, NULL, NULL, img, NULL, &st) == CS_OK);
	int n = 0;
	for (int i = 0; i < W * H; i++) {
		yr += cloud[i] ? cs_luminance(img[5 * i], img[5 * i + 1], img[5 * i + 2]) : 0.0;
		n += cloud[i];
	}
	CHECK(n > W * H / 4);
	printf("  heaps (%d of %d pixels): march without the towers' light %.3f (%+.1f %%), with "
	       "%.3f (%+.1f %%), path tracer %.3f kcd/m^2\n",
	       n, W * H, y[0] / n, 100.0 * (y[0] / yr - 1.0), y[1] / n, 100.0 * (y[1] / yr - 1.0),
	       yr / n);
	CHECK_NEAR(y[1] / yr, 1.0, 0.04);
	CHECK(fabs(y[0] / yr - 1.0) > fabs(y[1] / yr - 1.0) + 0.03);
	cs_volume_free(&noise);
}

/* Heaps of cumulus (35 % cover, 1.7 km thick) under a morning sun 32 deg
 * up behind the eye, which sees their sunlit faces: with the towers' light
 * (their tilted columns and diffused light) within 4 % of the path tracer
 * (measured -0.3 %; -4.9 % with the heaps' wall share HEAP_WALL a fifth
 * less, 0.52) and at least 3 points nearer than without it (-10.1 %:
 * a column's slab does not send the light of a face the sun lights back
 * toward the sun).  At 320x180 on the accuracy study's noise the scene
 * (tests/scenes/cumulus-sun-behind) went from -7.4 % to -3.4 %. */
static void heaps_with_the_sun_behind_the_eye_take_the_towers_light(void)
{
	heaps_against_the_path_tracer("2021-06-14T07:00:00Z", 0.35, 1600.0, 3300.0, 250.0, 15.0);
}

/* Flat heaps of half cover (0.8 km thick) under a sun 57 deg up, seen from
 * below: they take half the towers' light (their share ends at 80 % cover,
 * CS_DECK_HEAP_TILT_NONE; where it ended at 50 %, as the cumulonimbus's
 * does, they had none, and the march's model alone made their bases too
 * bright).  With it within 4 % of the path tracer (measured +1.8 %; +6.0 %
 * with HEAP_WALL a fifth more, 0.78), at least 3 points nearer than
 * without it (+8.2 %).  At 320x180 on the
 * accuracy study's noise the scene (tests/scenes/cumulus-thin) went from
 * +12.3 % to +3.9 %. */
static void half_covered_heaps_take_a_share_of_the_towers_light(void)
{
	heaps_against_the_path_tracer("2021-07-20T10:00:00Z", 0.5, 1200.0, 2000.0, 200.0, 10.0);
}

/* Cumulus whose light fields light it alone (70 % cover and more,
 * CS_DECK_FIELD_FULL) asks for no tilted columns and no lattice at high,
 * where the heaps' share would still be above 0 (it ends at 80 %): the
 * fields replace their light, so the work would be thrown away (the same
 * pixels at 75 % cover); at 65 % both are wanted.  The lattice a cumulus
 * of 75 % asks for is a deck's (cs_deck_lattice), whose ratio to
 * independent columns its fields take. */
static void heaps_lit_by_their_fields_alone_take_no_towers_work(void)
{
	static struct cs_volume noise;
	static struct cs_scene sc;
	struct cs_wx wx;
	struct cs_render_settings hi;
	CHECK(cs_render_quality("high", &hi) == CS_OK);
	one_layer(&sc, &noise, &wx, 32, "2021-07-20T10:00:00Z", CS_CUMULUS, 0.65, 1200.0, 2000.0);
	CHECK(sc.deck.field_weight[0] > 0.0 && sc.deck.field_weight[0] < 1.0);
	CHECK(cs_scene_tilt_wanted(&sc, &hi) && cs_tower_light_wanted(&sc, &hi));
	cs_volume_free(&noise);
	one_layer(&sc, &noise, &wx, 32, "2021-07-20T10:00:00Z", CS_CUMULUS, 0.75, 1200.0, 2000.0);
	CHECK(sc.deck.field_weight[0] == 1.0);
	CHECK(!cs_scene_tilt_wanted(&sc, &hi) && cs_tower_share(&sc, &hi, 0) == 0.0);
	CHECK(cs_deck_lattice(&sc, 0) && cs_tower_light_wanted(&sc, &hi));
	cs_volume_free(&noise);
}

/* Which layers take a deck's lattice (cs_deck_lattice): the rain hour's
 * nimbostratus (70 %, 3.2 km) and a stratocumulus of 75 % do, as their
 * in-cloud transport depth (1 - g) tau_in is 1 or more; a cirrostratus
 * of full cover, lit by light fields but a veil (transport depth about
 * 0.1), does not, nor does a stratocumulus of half cover, lit by the
 * march's model (no fields), and no frame asks for a lattice for them. */
static void only_thick_decks_take_a_lattice(void)
{
	static const struct {
		enum cs_genus g;
		double cover, base_m, top_m;
		int want;
	} c[] = {{CS_NIMBOSTRATUS, 0.7, 834.0, 4034.0, 1},
		 {CS_STRATOCUMULUS, 0.75, 1200.0, 1900.0, 1},
		 {CS_CIRROSTRATUS, 1.0, 7500.0, 9000.0, 0},
		 {CS_STRATOCUMULUS, 0.5, 1200.0, 1900.0, 0}};
	struct cs_render_settings hi;
	CHECK(cs_render_quality("high", &hi) == CS_OK);
	for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
		static struct cs_volume noise;
		static struct cs_scene sc;
		struct cs_wx wx;
		one_layer(&sc, &noise, &wx, 32, "2021-06-14T12:00:00Z", c[i].g, c[i].cover, c[i].base_m,
			  c[i].top_m);
		int fi = sc.deck.field_of[0];
		printf("  %s of %.2f: fields %d, transport depth %.2f, lattice %d\n",
		       cs_genus_name(c[i].g), c[i].cover, fi,
		       fi >= 0 ? (1.0 - sc.deck.g) * sc.deck.field_tau[fi][2] : 0.0,
		       cs_deck_lattice(&sc, 0));
		CHECK(cs_deck_lattice(&sc, 0) == c[i].want);
		CHECK(cs_tower_light_wanted(&sc, &hi) == c[i].want);
		cs_volume_free(&noise);
	}
}

static const struct t_case t_cases[] = {
	CASE(diffusion_matches_the_slab_closed_form),
	CASE(columns_match_the_slab_and_ignore_their_neighbours),
	CASE(only_thick_decks_take_a_lattice),
	CASE(diffusion_slab_in_clear_air_matches_the_closed_form),
	CASE(diffusion_carries_the_light_across_a_gap),
	CASE(diffusion_fills_with_the_light_around),
	CASE(exchange_sees_the_ground_where_each_direction_meets_it),
	CASE(exchange_is_the_same_on_any_number_of_threads),
	CASE(side_view_is_nearer_the_path_tracer_with_the_field),
	CASE(heaps_with_the_sun_behind_the_eye_take_the_towers_light),
	CASE(half_covered_heaps_take_a_share_of_the_towers_light),
	CASE(heaps_lit_by_their_fields_alone_take_no_towers_work),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
