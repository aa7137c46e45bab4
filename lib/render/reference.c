/* reference.c - the reference integrator: an unbiased Monte Carlo
 * volumetric path tracer over the same scene as the fast integrator, to
 * measure what the fast one's approximations cost.
 *
 * The media are the clouds (the same density field, albedo and two-lobe
 * phase function), fog (the same droplets: the clouds' albedo and phase)
 * and rain or snow (grey, isotropic, the precipitation's albedo).  Free
 * paths are sampled by delta tracking (Woodcock et al. 1965) against a
 * piecewise-constant majorant: along a ray, each medium's bound (a layer's
 * extinction at density 1, the fog's and the rain's extinction) summed
 * over the stretches where the ray is inside its shell.  The sun (or the
 * Moon) is a directional light reached by next-event estimation, its
 * transmittance by ratio tracking (Novak, Selle & Jarosz 2014); the sky
 * is the environment (cs_scene_sky), reached by paths that leave the
 * media; the ground and the terrain reflect as Lambertian surfaces of the
 * albedo the fast integrator shades them with.  Paths end where they
 * leave the scene or by Russian roulette, which keeps the estimate
 * unbiased.
 *
 * Not simulated: the aerosol haze between the eye and the clouds (the
 * sky's radiance holds the clear air; compare with the haze medium off),
 * the 22-degree halo's share of cirrostratus scattering, and the
 * analytic light under the clouds (CS_FX_DECK), which this integrator
 * computes instead of approximating. */
#include "render/march.h"

#include "core/color.h"
#include "core/err.h"
#include "core/hash.h"
#include "core/sphere.h"
#include "render/reference.h"

#include <math.h>
#include <stdalign.h>
#include <stdlib.h>
#include <string.h>

/* splitmix64 (Steele, Lea & Flood 2014): a counter hashed to 64 bits */
struct rng {
	uint64_t s;
};

CS_HD static inline double rnd(struct rng *r)
{
	uint64_t z = (r->s += 0x9e3779b97f4a7c15ull);
	z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
	z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
	z ^= z >> 31;
	return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

enum medium { M_CLOUD, M_FOG, M_RAIN };

/* A stretch of a ray with a constant majorant, 1/m. */
struct seg {
	double t0, t1, maj;
};

enum { MAX_IV = 2 * CS_SCENE_MAX_LAYERS + 4, MAX_SEG = 2 * MAX_IV };

/* The largest extinction layer l can have. */
CS_HD static double layer_majorant(const struct cs_cloud_layer *l)
{
	if (l->kind == CS_LAYER_HOMOGENEOUS) {
		double a = l->homog_a, b = l->homog_a + l->homog_b;
		double m = a > b ? a : b;
		return m > 0.0 ? m : 0.0;
	}
	return l->extinction_per_m;
}

CS_HD static int has_fog(const struct cs_scene *sc)
{
	return (sc->effects & CS_FX_HAZE) && sc->fog_beta_per_m > 0.0;
}

/* The stretches of [0, tmax] along o + t d, sorted, each with the sum of
 * the majorants of the media whose shells hold it. */
CS_HD static int media_segments(const struct cs_scene *sc, cs_v3 o, cs_v3 d,
				double tmax, struct seg *out)
{
	struct seg iv[MAX_IV];
	int n = 0;
	double R = sc->earth_radius_m, a[2][2];
	for (int i = 0; i < sc->nlayers; i++) {
		double m = layer_majorant(&sc->layers[i]);
		int k = m > 0.0 ? cs_shell_intervals(sc, o, d, R + sc->layers[i].base_m,
						     R + sc->layers[i].top_m, tmax, a)
				: 0;
		for (int j = 0; j < k; j++)
			iv[n++] = (struct seg){a[j][0], a[j][1], m};
	}
	if (has_fog(sc)) {
		int k = cs_shell_intervals(sc, o, d, R + sc->ground_alt_m - 1000.0,
					   R + sc->fog_top_m, tmax, a);
		for (int j = 0; j < k; j++)
			iv[n++] = (struct seg){a[j][0], a[j][1], sc->fog_beta_per_m};
	}
	if ((sc->effects & (CS_FX_RAIN | CS_FX_SNOW)) && sc->rain_extinction_per_m > 0.0) {
		int k = cs_shell_intervals(sc, o, d, R + sc->ground_alt_m - 1.0,
					   R + sc->rain_top_m, tmax, a);
		for (int j = 0; j < k; j++)
			iv[n++] = (struct seg){a[j][0], a[j][1], sc->rain_extinction_per_m};
	}
	/* the boundaries, sorted (insertion sort: n is tiny) */
	double b[MAX_SEG];
	int nb = 0;
	for (int i = 0; i < n; i++)
		b[nb++] = iv[i].t0, b[nb++] = iv[i].t1;
	for (int i = 1; i < nb; i++)
		for (int j = i; j > 0 && b[j] < b[j - 1]; j--) {
			double t = b[j];
			b[j] = b[j - 1];
			b[j - 1] = t;
		}
	int ns = 0;
	for (int i = 0; i + 1 < nb; i++) {
		if (!(b[i + 1] > b[i]))
			continue;
		double mid = 0.5 * (b[i] + b[i + 1]), maj = 0.0;
		for (int j = 0; j < n; j++)
			if (iv[j].t0 <= mid && mid < iv[j].t1)
				maj += iv[j].maj;
		if (maj <= 0.0)
			continue;
		if (ns > 0 && out[ns - 1].t1 == b[i] && out[ns - 1].maj == maj)
			out[ns - 1].t1 = b[i + 1];
		else
			out[ns++] = (struct seg){b[i], b[i + 1], maj};
	}
	return ns;
}

/* The extinction of each medium at p, 1/m. */
CS_HD static void media_at(const struct cs_scene *sc, cs_v3 p, double sig[3])
{
	double alt = cs_scene_altitude(sc, p);
	int dom = 0;
	sig[M_CLOUD] = cs_extinction_at(sc, ~0u, p, alt, &dom);
	sig[M_FOG] = has_fog(sc) && alt < sc->fog_top_m ? sc->fog_beta_per_m : 0.0;
	sig[M_RAIN] = 0.0;
	if ((sc->effects & (CS_FX_RAIN | CS_FX_SNOW)) && alt < sc->rain_top_m &&
	    alt > sc->ground_alt_m - 1.0)
		sig[M_RAIN] = sc->rain_extinction_per_m * cs_rain_shaft(sc, p.x, p.y);
}

/* Tracking along o + t d up to tmax against the majorant: tentative
 * collisions at exponential distances, the media's extinction at each.
 * Delta tracking (T == NULL): returns 1 and the distance and medium of the
 * first real collision (chosen with probability sigma / majorant), 0 when
 * the ray gets through.  Ratio tracking (T != NULL): multiplies *T by
 * 1 - sigma / majorant at each, with Russian roulette once it is faint
 * (0 is returned when it ends the ray). */
CS_HD static int track(const struct cs_scene *sc, cs_v3 o, cs_v3 d, double tmax,
		       struct rng *r, uint64_t *evals, double *T, double *t_hit, enum medium *m)
{
	struct seg sg[MAX_SEG];
	int ns = media_segments(sc, o, d, tmax, sg);
	for (int i = 0; i < ns; i++) {
		double t = sg[i].t0;
		for (;;) {
			t -= log(1.0 - rnd(r)) / sg[i].maj;
			if (!(t < sg[i].t1))
				break;
			double sig[3];
			media_at(sc, v3_mad(o, d, t), sig);
			(*evals)++;
			double total = sig[0] + sig[1] + sig[2];
			if (T != NULL) {
				*T *= 1.0 - total / sg[i].maj;
				if (*T < 0.05) { /* Russian roulette on a faint shadow ray */
					if (rnd(r) < 0.5) {
						*T = 0.0;
						return 0;
					}
					*T *= 2.0;
				}
				continue;
			}
			double u = rnd(r) * sg[i].maj;
			if (u < total) {
				*t_hit = t;
				*m = u < sig[M_CLOUD] ? M_CLOUD : u < sig[M_CLOUD] + sig[M_FOG] ? M_FOG : M_RAIN;
				return 1;
			}
		}
	}
	return 0;
}

CS_HD static int free_flight(const struct cs_scene *sc, cs_v3 o, cs_v3 d, double tmax,
			     struct rng *r, struct cs_render_stats *st, double *t_hit,
			     enum medium *m)
{
	return track(sc, o, d, tmax, r, &st->density_samples, NULL, t_hit, m);
}

/* The transmittance from p along unit dir to the sky, by ratio tracking
 * (0 when the ground or the terrain is in the way). */
CS_HD static double transmittance(const struct cs_scene *sc, cs_v3 p, cs_v3 dir,
				  struct rng *r, struct cs_render_stats *st)
{
	int on_terrain;
	double tg = cs_find_ground(sc, p, dir, &on_terrain, st), T = 1.0, t;
	enum medium m;
	if (isfinite(tg))
		return 0.0;
	track(sc, p, dir, 1e7, r, &st->light_samples, &T, &t, &m);
	return T;
}

/* Samples a direction from Henyey-Greenstein with asymmetry g about the
 * direction of travel d (the inverse of its cumulative distribution). */
CS_HD static cs_v3 sample_hg(cs_v3 d, double g, double u1, double u2)
{
	double c;
	if (fabs(g) < 1e-4)
		c = 1.0 - 2.0 * u1;
	else {
		double f = (1.0 - g * g) / (1.0 - g + 2.0 * g * u1);
		c = (1.0 + g * g - f * f) / (2.0 * g);
	}
	c = c < -1.0 ? -1.0 : c > 1.0 ? 1.0 : c;
	double s = sqrt(1.0 - c * c), phi = 2.0 * CS_PI * u2;
	/* an orthonormal basis around d (Duff et al. 2017) */
	double sign = d.z >= 0.0 ? 1.0 : -1.0;
	double a = -1.0 / (sign + d.z), b = d.x * d.y * a;
	cs_v3 t1 = v3(1.0 + sign * d.x * d.x * a, sign * b, -sign * d.x);
	cs_v3 t2 = v3(b, sign + d.y * d.y * a, -d.y);
	cs_v3 w = v3_add(v3_scale(t1, s * cos(phi)), v3_scale(t2, s * sin(phi)));
	return v3_norm(v3_add(w, v3_scale(d, c)));
}

/* The cloud's phase function (1/sr) and a direction drawn from it. */
CS_HD static double cloud_phase(const struct cs_scene *sc, double cos_theta)
{
	return cs_phase_two_lobe(cos_theta, sc->g_forward, sc->g_back, sc->w_forward, 1.0);
}

CS_HD static cs_v3 cloud_sample(const struct cs_scene *sc, cs_v3 d, struct rng *r)
{
	double g = rnd(r) < sc->w_forward ? sc->g_forward : sc->g_back;
	double u1 = rnd(r);
	return sample_hg(d, g, u1, rnd(r));
}

/* A cosine-weighted direction about the unit normal n. */
CS_HD static cs_v3 sample_cosine(cs_v3 n, struct rng *r)
{
	double u1 = rnd(r), u2 = rnd(r);
	/* a uniform direction on the sphere added to the normal */
	double z = 1.0 - 2.0 * u1, s = sqrt(fmax(0.0, 1.0 - z * z)), phi = 2.0 * CS_PI * u2;
	cs_v3 v = v3_add(n, v3(s * cos(phi), s * sin(phi), z));
	double len = v3_len(v);
	return len > 1e-9 ? v3_scale(v, 1.0 / len) : n;
}

struct path_out {
	double L[3];
	int hit_cloud;   /* the first collision was with a cloud */
	double depth_m;  /* of the first collision or the ground, or CS_SKY_DEPTH_M */
};

/* Adds the sun's (or Moon's) light reaching p, weighted by f (the phase
 * or the surface's cosine / pi) and the path's throughput. */
CS_HD static void add_key_light(const struct cs_scene *sc, cs_v3 p, double f,
				const double thr[3], struct rng *r,
				struct cs_render_stats *st, double L[3])
{
	if (!(sc->effects & CS_FX_KEY) || !(f > 0.0))
		return;
	double T = transmittance(sc, p, sc->sun_dir, r, st);
	for (int k = 0; k < 3; k++)
		L[k] += thr[k] * f * T * sc->sun_illuminance[k];
}

/* One path; see_disk: whether a path that leaves at once sees the sun's
 * and Moon's discs and the stars (an eye does; an irradiance estimate, which
 * has the beam from next-event estimation, does not). */
CS_HD static void trace(const struct cs_scene *sc, const struct cs_reference_settings *s,
			cs_v3 o, cs_v3 d, uint64_t key, int see_disk, struct cs_render_stats *st,
			double L[3], int *hit_cloud, double *depth_m)
{
	struct rng r = {key};
	double thr[3] = {1.0, 1.0, 1.0};
	L[0] = L[1] = L[2] = 0.0;
	*hit_cloud = 0;
	*depth_m = CS_SKY_DEPTH_M;
	for (int bounce = 0;; bounce++) {
		int on_terrain;
		double tg = cs_find_ground(sc, o, d, &on_terrain, st);
		double t;
		enum medium m;
		if (free_flight(sc, o, d, isfinite(tg) ? tg : 1e7, &r, st, &t, &m)) {
			cs_v3 p = v3_mad(o, d, t);
			if (bounce == 0)
				*hit_cloud = m == M_CLOUD, *depth_m = t;
			double alb = m == M_RAIN ? sc->precip_albedo : sc->albedo;
			for (int k = 0; k < 3; k++)
				thr[k] *= alb;
			double cs = v3_dot(d, sc->sun_dir);
			add_key_light(sc, p, m == M_RAIN ? 1.0 / (4.0 * CS_PI) : cloud_phase(sc, cs),
				      thr, &r, st, L);
			o = p;
			if (m == M_RAIN) {
				double z = 1.0 - 2.0 * rnd(&r), sn = sqrt(fmax(0.0, 1.0 - z * z));
				double phi = 2.0 * CS_PI * rnd(&r);
				d = v3(sn * cos(phi), sn * sin(phi), z);
			} else
				d = cloud_sample(sc, d, &r);
		} else if (isfinite(tg)) {
			cs_v3 p = v3_mad(o, d, tg), n;
			double alb[3];
			if (bounce == 0)
				*depth_m = tg;
			cs_ground_surface(sc, p, on_terrain, &n, alb);
			/* leave the surface on the side the ray came from */
			p = v3_mad(p, n, 0.01);
			for (int k = 0; k < 3; k++)
				thr[k] *= alb[k];
			double cosi = v3_dot(n, sc->sun_dir);
			add_key_light(sc, p, cosi / CS_PI, thr, &r, st, L);
			o = p;
			d = sample_cosine(n, &r);
		} else {
			/* the sky; the sun's and Moon's discs and the stars only
			 * where the eye sees them directly (the key light is the
			 * next-event estimate) */
			double bg[3] = {0.0, 0.0, 0.0}, disk[3], stars[3];
			if (sc->effects & CS_FX_SKY) {
				cs_scene_sky(sc, d, bg);
				if (bounce == 0 && see_disk) {
					cs_scene_disk(sc, d, disk);
					cs_scene_stars(sc, d, stars);
					for (int k = 0; k < 3; k++)
						bg[k] += disk[k] + stars[k];
				}
			}
			for (int k = 0; k < 3; k++)
				L[k] += thr[k] * bg[k];
			return;
		}
		if (s->max_bounces > 0 && bounce + 1 >= s->max_bounces)
			return;
		/* Russian roulette on the throughput (at most 1): a path that
		 * survives carries a weight of at most 1 again, so no path's
		 * weight grows without bound (an unbiased, light-tailed
		 * estimate) */
		double q = thr[0] > thr[1] ? thr[0] : thr[1];
		q = q > thr[2] ? q : thr[2];
		if (q < 1.0) {
			if (!(rnd(&r) < q))
				return;
			for (int k = 0; k < 3; k++)
				thr[k] /= q;
		}
		if (bounce > 100000) /* a path this long holds no light worth the time */
			return;
	}
}

/* The key of a path: pixel, sample and seed hashed into the counter. */
CS_HD static uint64_t path_key(int i, int j, int k, uint32_t seed)
{
	uint64_t a = cs_hash3i(i, j, k, seed), b = cs_hash3i(k, i, j, seed ^ 0x5bd1e995u);
	return a << 32 | b;
}

CS_HD void cs_reference_path(const struct cs_scene *sc, const struct cs_reference_settings *s,
			     cs_v3 o, cs_v3 d, uint64_t key, struct cs_render_stats *st,
			     double L[3], int *hit_cloud, double *depth_m)
{
	trace(sc, s, o, d, key, 1, st, L, hit_cloud, depth_m);
}

void cs_reference_irradiance_at(const struct cs_scene *sc, const struct cs_reference_settings *s,
				cs_v3 p, int paths, struct cs_irradiance *out,
				struct cs_render_stats *st)
{
	cs_v3 up = v3_norm(v3(p.x, p.y, p.z + sc->earth_radius_m));
	struct rng r = {(uint64_t)cs_hash3i((int32_t)p.x, (int32_t)p.y, paths, s->seed) << 32 | 0x2545f491u};
	double beam = 0.0, dif = 0.0;
	int sun = (sc->effects & CS_FX_KEY) && v3_dot(sc->sun_dir, up) > 0.0;
	for (int k = 0; k < paths; k++) {
		if (sun)
			beam += transmittance(sc, p, sc->sun_dir, &r, st);
		double L[3], depth;
		int hit;
		cs_v3 d = sample_cosine(up, &r);
		trace(sc, s, p, d, path_key(k, 0x69727261, (int)(p.x + p.y), s->seed), 0, st, L, &hit,
		      &depth);
		dif += cs_luminance(L[0], L[1], L[2]);
	}
	double e_sun = cs_luminance(sc->sun_illuminance[0], sc->sun_illuminance[1], sc->sun_illuminance[2]);
	cs_irradiance_from_klux(sc, p, sun ? e_sun * beam / paths : 0.0, CS_PI * dif / paths, out);
}

void cs_reference_irradiance_area(const struct cs_scene *sc, const struct cs_reference_settings *s,
				  double size_m, int n, int paths, struct cs_irradiance *out,
				  struct cs_render_stats *st)
{
	struct cs_irradiance sum = {0.0, 0.0, 0.0};
	for (int j = 0; j < n; j++)
		for (int i = 0; i < n; i++) {
			struct cs_irradiance one;
			cs_reference_irradiance_at(sc, s, cs_irradiance_area_point(sc, size_m, n, i, j),
						   paths, &one, st);
			sum.ghi_w_m2 += one.ghi_w_m2 / (n * n);
			sum.dni_w_m2 += one.dni_w_m2 / (n * n);
			sum.dhi_w_m2 += one.dhi_w_m2 / (n * n);
		}
	*out = sum;
}

CS_HD void cs_reference_pixel_begin(struct cs_reference_pixel *a)
{
	memset(a, 0, sizeof *a);
	a->ground_depth = CS_SKY_DEPTH_M;
}

CS_HD void cs_reference_pixel_add(const struct cs_scene *sc, const struct cs_camera *cam,
				  const struct cs_reference_settings *s, int i, int j, int k0,
				  int k1, struct cs_reference_pixel *a, struct cs_render_stats *st)
{
	cs_v3 d;
	a->ok = cs_camera_ray(cam, i, j, &d);
	for (int k = k0; k < k1 && a->ok; k++) {
		double L[3], depth;
		int hit;
		cs_reference_path(sc, s, cam->pos, d, path_key(i, j, k, s->seed), st, L, &hit,
				  &depth);
		for (int c = 0; c < 3; c++)
			a->sum[c] += L[c];
		/* Welford's running variance of the luminance */
		double y = cs_luminance(L[0], L[1], L[2]), dy = y - a->mean;
		a->n++;
		a->mean += dy / a->n;
		a->m2 += dy * (y - a->mean);
		a->hits += hit;
		if (hit)
			a->depth_sum += depth, a->ndepth++;
		else if (depth < a->ground_depth)
			a->ground_depth = depth;
	}
	st->pixels += k0 == 0;
}

CS_HD void cs_reference_pixel_end(const struct cs_reference_pixel *a, float px[5], float *var)
{
	int ok = a->ok && a->n > 0;
	for (int c = 0; c < 3; c++)
		px[c] = ok ? (float)(a->sum[c] / a->n) : 0.0f;
	px[3] = ok ? (float)((double)a->hits / a->n) : 0.0f;
	px[4] = (float)(a->ndepth > 0 ? a->depth_sum / a->ndepth : a->ground_depth);
	if (var)
		*var = ok && a->n > 1 ? (float)(a->m2 / (a->n - 1) / a->n) : 0.0f;
}

int cs_reference_check(const struct cs_reference_settings *s)
{
	if (s->spp < 1 || s->spp > 1000000)
		return cs_error(CS_EINVAL, "samples per pixel must be 1..1000000, not %d", s->spp);
	if (s->max_bounces < 0)
		return cs_error(CS_EINVAL, "max bounces must be >= 0, not %d", s->max_bounces);
	return CS_OK;
}

enum { ROWS_PER_TASK = 2 };

struct worker_stats {
	alignas(64) struct cs_render_stats s;
};

struct ref_job {
	const struct cs_scene *sc;
	const struct cs_camera *cam;
	const struct cs_reference_settings *s;
	float *out, *var;
	struct worker_stats stats[CS_POOL_MAX_THREADS];
};

static void ref_rows(void *user, int task, int worker)
{
	struct ref_job *job = (struct ref_job *)user;
	const struct cs_camera *cam = job->cam;
	struct cs_render_stats st = {0};
	int r0 = task * ROWS_PER_TASK;
	int r1 = r0 + ROWS_PER_TASK < cam->height ? r0 + ROWS_PER_TASK : cam->height;
	for (int j = r0; j < r1; j++)
		for (int i = 0; i < cam->width; i++) {
			struct cs_reference_pixel acc;
			size_t at = (size_t)j * cam->width + i;
			cs_reference_pixel_begin(&acc);
			cs_reference_pixel_add(job->sc, cam, job->s, i, j, 0, job->s->spp, &acc, &st);
			cs_reference_pixel_end(&acc, job->out + at * 5, job->var ? job->var + at : NULL);
		}
	struct cs_render_stats *a = &job->stats[worker].s;
	a->pixels += st.pixels;
	a->density_samples += st.density_samples;
	a->light_samples += st.light_samples;
	a->terrain_cells += st.terrain_cells;
}

int cs_render_reference(const struct cs_scene *sc, const struct cs_camera *cam,
			const struct cs_reference_settings *s, int nthreads,
			cs_progress_fn progress, void *user, float *out, float *var,
			struct cs_render_stats *stats)
{
	int rc = cs_reference_check(s);
	if (rc != CS_OK)
		return rc;
	size_t size = (sizeof(struct ref_job) + 63) / 64 * 64;
	struct ref_job *job = (struct ref_job *)aligned_alloc(64, size);
	if (job == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	*job = (struct ref_job){.sc = sc, .cam = cam, .s = s, .out = out, .var = var};
	int tasks = (cam->height + ROWS_PER_TASK - 1) / ROWS_PER_TASK, workers = 0;
	rc = cs_pool_run(tasks, nthreads, ref_rows, job, progress, user, &workers);
	memset(stats, 0, sizeof *stats);
	for (int i = 0; i < workers; i++) {
		stats->pixels += job->stats[i].s.pixels;
		stats->density_samples += job->stats[i].s.density_samples;
		stats->light_samples += job->stats[i].s.light_samples;
		stats->terrain_cells += job->stats[i].s.terrain_cells;
	}
	free(job);
	if (rc == CS_ECANCELED)
		return cs_error(CS_ECANCELED, "rendering cancelled");
	return rc;
}
