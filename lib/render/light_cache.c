/* light_cache.c - CS_LIGHT_CACHE: each layer's optical depth toward the
 * sun, one period of it (struct cs_light_cache), built once a frame on
 * the CPU pool (with the towers' diffused light, tower_light.c), so that
 * a cloudy sample looks its light up instead of marching toward the sun
 * (on a GPU too: cuda/render_cuda.cu copies the volumes with the
 * scene). */
#include "render/render.h"
#include "render/camera.h"
#include "render/march.h"

#include "core/err.h"
#include "core/pool.h"

#include <math.h>
#include <stdlib.h>

/* A sun lower than this is marched: its paths through a layer are long
 * enough that the Earth's curve, which the cache's flat layers leave out,
 * bends them (15 deg: 3.9 times the thickness). */
#define CACHE_MIN_SUN_SIN 0.2588190451 /* sin 15 deg */
/* A volume's cells at most (16 MB of floats; --light-steps beyond 48
 * adds no more), and the columns' spacing across the wind that a field
 * larger than its light steps' share of cells may take up to them: a
 * cumulonimbus's 40 km period was 449 m between columns at medium, its
 * lit fringe's depth 1.75 times off on average against 0.49 for the
 * geometric march it replaced. */
#define MAX_CELLS 4000000.0
#define MAX_SPACING_M 200.0

struct build_job {
	const struct cs_scene *sc;
	const struct cs_cloud_layer *l;
	struct cs_light_cache *lc;
	float *depth;
};

/* Row j of the columns: each column's extinction at the middle of each
 * of its nh steps between levels (the per-pixel code's build,
 * cs_render_extinction), summed down from the top by the midpoint rule
 * along the ray.  (The trapezoid rule on the levels counted half a level
 * of full density at the sharp ramps of a stratus's base and top: its
 * depth came out 10 % too high at medium, 50 m levels.) */
static void build_row(void *user, int j, int worker)
{
	(void)worker;
	struct build_job *job = user;
	const struct cs_cloud_layer *l = job->l;
	const struct cs_light_cache *lc = job->lc;
	int nk = lc->nh + 1;
	double xyz[3 * 128], e[128];
	for (int i = 0; i < lc->nu; i++) {
		for (int k = 0; k < lc->nh; k++) {
			double rise = (k + 0.5) * lc->dh_m;
			/* along and across as cs_cloud_extinction moves them,
			 * back to east and north */
			double a = i * lc->du_m + rise * lc->shear_u + l->offset_along_m;
			double c = j * lc->dv_m + rise * lc->shear_v + l->offset_across_m;
			cs_cloud_axes_to_en(l, a, c, &xyz[3 * k], &xyz[3 * k + 1]);
			xyz[3 * k + 2] = l->base_m + rise;
		}
		cs_render_extinction(l, job->sc->noise, lc->nh, xyz, e);
		float *col = job->depth + ((size_t)j * (size_t)lc->nu + (size_t)i) * (size_t)nk;
		double d = 0.0, w = lc->dh_m * lc->path_per_m;
		col[lc->nh] = 0.0f;
		for (int k = lc->nh - 1; k >= 0; k--) {
			d += w * e[k];
			col[k] = (float)d;
		}
	}
}

/* The volume of layer l whose columns lean by (shear_u, shear_v) along
 * and across the wind per metre of height, path_per_m metres of ray a
 * metre of height, into *out (its depth NULL where the layer has none:
 * far weather, no periods, no cover); levels about dh_want apart (at
 * most 128 of them), columns within budget cells, stretched along the
 * wind as the field is, and no more than MAX_SPACING_M apart across it
 * while that fits in MAX_CELLS; none of more than most cells.  CS_OK,
 * CS_ENOMEM, or the pool's error. */
static int build_volume(const struct cs_scene *sc, const struct cs_cloud_layer *l, int nthreads,
			double dh_want, double budget, double most, double shear_u, double shear_v,
			double path_per_m, struct cs_light_cache *out, uint64_t *evaluations)
{
	*out = (struct cs_light_cache){0};
	double pa, pc, th = l->top_m - l->base_m;
	if (l->nfar > 0 || !(l->coverage > 0.0) || !(th > 0.0) || !cs_cloud_periods(l, &pa, &pc))
		return CS_OK;
	int nh = (int)ceil(th / dh_want);
	nh = nh < 4 ? 4 : nh > 128 ? 128 : nh;
	double st = l->stretch >= 1.0 ? l->stretch : 1.0, area = pa * pc * (nh + 1) / st;
	budget = budget < MAX_CELLS ? budget : MAX_CELLS;
	double dv = sqrt(area / budget);
	dv = dv > dh_want ? dv : dh_want;
	if (dv > MAX_SPACING_M) { /* the large fields (Cb, Ns, Cs): more cells */
		double least = sqrt(area / MAX_CELLS);
		dv = least > MAX_SPACING_M ? least : MAX_SPACING_M;
	}
	double nu = ceil(pa / (dv * st)), nv = ceil(pc / dv);
	/* (the columns rounded up to whole numbers: a little over MAX_CELLS) */
	if (nu * nv * (nh + 1) > 1.1 * MAX_CELLS)
		return CS_OK; /* a period too long for the cells (never for the genera) */
	if (nu * nv * (nh + 1) > most)
		return CS_OK; /* more than the frame pays for (CS_LIGHT_AUTO) */
	struct cs_light_cache c = {
		.nu = (int)nu, .nv = (int)nv, .nh = nh,
		.du_m = pa / nu, .dv_m = pc / nv, .dh_m = th / nh,
		.shear_u = shear_u, .shear_v = shear_v, .path_per_m = path_per_m,
	};
	size_t cells = (size_t)c.nu * (size_t)c.nv * (size_t)(nh + 1);
	float *depth = malloc(cells * sizeof *depth);
	if (depth == NULL)
		return cs_error(CS_ENOMEM, "out of memory for the light cache (%zu cells)", cells);
	struct build_job job = {sc, l, &c, depth};
	int rc = cs_pool_run(c.nv, nthreads, build_row, &job, NULL, NULL, NULL);
	if (rc != CS_OK) {
		free(depth);
		return rc;
	}
	c.depth = depth;
	*out = c;
	*evaluations += cells;
	return CS_OK;
}

/* What lights the ground of a frame of sc with settings s, the camera
 * aside (enum cs_ground_lit).  The dome's where it is asked for, under
 * clouds (a deck), with the sky's light on the ground, and without fog:
 * the fog's own light field lights the ground in it (cs_ground_light),
 * solved from the columns' light, which the ground over it keeps too,
 * lest it step in brightness at the fog's top. */
static int ground_lit(const struct cs_scene *sc, const struct cs_render_settings *s)
{
	int fog = sc->fog_beta_per_m > 0.0 && sc->fog.on;
	if (!sc->deck.on || !(sc->effects & CS_FX_SKY) || !(sc->effects & CS_FX_GROUND))
		return fog ? CS_GROUND_LIT_CLEAR_FOG : CS_GROUND_LIT_CLEAR;
	if (fog)
		return s->ground_sky == CS_GROUND_SKY_COLUMNS ? CS_GROUND_LIT_COLUMNS_FOG
							      : CS_GROUND_LIT_FOG;
	if (s->ground_sky == CS_GROUND_SKY_COLUMNS)
		return CS_FX_IS(sc, CS_FX_RAIN | CS_FX_SNOW) ? CS_GROUND_LIT_FIELD_PRECIP
							     : CS_GROUND_LIT_COLUMNS;
	return s->ground_sky == CS_GROUND_SKY_FIELD ? CS_GROUND_LIT_FIELD : CS_GROUND_LIT_DOME;
}

/* Whether ground_lit's value is a field's. */
static int lit_by_field(int lit)
{
	return lit == CS_GROUND_LIT_FIELD || lit == CS_GROUND_LIT_FIELD_AIR ||
	       lit == CS_GROUND_LIT_FIELD_PRECIP;
}

/* Whether the frame traces the ground's light (the dome or the field). */
static int ground_traced(const struct cs_scene *sc, const struct cs_render_settings *s)
{
	int lit = ground_lit(sc, s);
	return lit == CS_GROUND_LIT_DOME || lit_by_field(lit);
}

const char *cs_ground_lit_name(int ground_lit)
{
	static const char *const names[] = {
		[CS_GROUND_LIT_COLUMNS] = "the columns'",
		[CS_GROUND_LIT_DOME] = "the dome's",
		[CS_GROUND_LIT_FIELD] = "the field's",
		[CS_GROUND_LIT_COLUMNS_FOG] = "the columns' and the fog's",
		[CS_GROUND_LIT_CLEAR] = "the clear sky's (no clouds)",
		[CS_GROUND_LIT_CLEAR_FOG] = "the clear sky's and the fog's (no clouds over the fog)",
		[CS_GROUND_LIT_FOG] = ("the columns' and the fog's, none traced (fog: its light is "
				       "solved from the columns')"),
		[CS_GROUND_LIT_UNSEEN] = "the columns', none traced (the frame sees no ground)",
		[CS_GROUND_LIT_FIELD_AIR] = ("the field's, for the haze and the rain under the clouds "
					     "(the frame sees no ground)"),
		[CS_GROUND_LIT_DOME_AIR] = ("the dome's, for the haze and the rain under the clouds "
					    "(the frame sees no ground)"),
		[CS_GROUND_LIT_FIELD_PRECIP] = ("the field's (columns asked for, but rain or snow "
						"under the clouds takes the field's light)"),
	};
	if (ground_lit < 0 || ground_lit >= (int)(sizeof names / sizeof names[0]))
		return "?";
	return names[ground_lit];
}

int cs_light_cache_build(struct cs_scene *sc, const struct cs_render_settings *s, double pixels,
			 int nthreads, uint64_t *evaluations)
{
	*evaluations = 0;
	for (int c = 0; c < 3; c++) /* the columns' unless the dome's (below) */
		sc->deck.sky_ground[c] = sc->deck.sky_below[c];
	for (int n = 0; n < CS_SCENE_MAX_LAYERS; n++) { /* a copy's: not its to free */
		sc->light_cache[n] = (struct cs_light_cache){0};
		sc->column_cache[n] = (struct cs_light_cache){0};
		sc->tower_light[n] = (struct cs_light_cache){0};
	}
	sc->ground_field = (struct cs_ground_field){0};
	/* the heaps' tilted columns where the settings light them so */
	cs_scene_tilt_fields(sc, s, nthreads);
	cs_v3 sun = sc->sun_dir;
	int toward_sun = (sc->effects & CS_FX_KEY) && sun.z >= CACHE_MIN_SUN_SIN;
	/* the column above a sample (and below it, for the light fields):
	 * where the diffuse light is found, which takes it (sample_source) */
	int columns = sc->deck.on && s->ambient;
	/* levels about 50 m apart at 12 light steps (finer with more), and
	 * columns as close within 1/12 million cells a light step: a
	 * cumulus layer's period at 12 steps is 25 levels of 200 x 200
	 * columns 120 m apart.  On the study's scenes (scripts/accuracy-study,
	 * medium) columns 4 times as many came out no nearer the path tracer
	 * (geometric mean relative MSE 0.0123 against 0.01225), a quarter as
	 * many 0.01211, levels twice as far apart 0.0125 */
	if (!CS_LIGHT_CACHED(s->light_march))
		toward_sun = columns = 0;
	int ls = s->light_steps > 1 ? s->light_steps : 1;
	double dh_want = 600.0 / ls, budget = 83333.0 * ls;
	double most = s->light_march == CS_LIGHT_AUTO ? CS_AUTO_CELLS_PER_PIXEL * pixels : HUGE_VAL;
	int rc = CS_OK;
	for (int n = 0; n < sc->nlayers && rc == CS_OK; n++) {
		const struct cs_cloud_layer *l = &sc->layers[n];
		double su, sv; /* the sun's direction on the layer's axes */
		cs_cloud_en_to_axes(l, sun.x, sun.y, &su, &sv);
		if (toward_sun)
			rc = build_volume(sc, l, nthreads, dh_want, budget, most, su / sun.z, sv / sun.z,
					  1.0 / sun.z, &sc->light_cache[n], evaluations);
		if (rc == CS_OK && columns)
			rc = build_volume(sc, l, nthreads, dh_want, budget, most, 0.0, 0.0, 1.0,
					  &sc->column_cache[n], evaluations);
	}
	if (rc == CS_OK && cs_tower_light_wanted(sc, s)) {
		uint64_t tower = 0;
		rc = cs_tower_light_build(sc, s, nthreads, &tower);
		*evaluations += tower;
	}
	/* last, the ground's diffuse light from the sky as the frame draws it
	 * (with the caches and the towers' light just built) */
	if (rc == CS_OK && ground_lit(sc, s) == CS_GROUND_LIT_DOME)
		rc = cs_ground_sky_dome(sc, s, nthreads, sc->deck.sky_ground);
	if (rc != CS_OK) {
		cs_light_cache_free(sc);
		*evaluations = 0;
	}
	return rc;
}

/* Whether the camera's ray through pixel (i, j) meets the ground (or
 * the terrain), as the renderer finds it. */
static int pixel_sees_ground(const struct cs_scene *sc, const struct cs_camera *cam, int i, int j)
{
	cs_v3 d;
	int on_terrain;
	struct cs_render_stats st = {0};
	return cs_camera_ray(cam, i, j, &d) && isfinite(cs_find_ground(sc, cam->pos, d, &on_terrain, &st));
}

int cs_camera_sees_ground(const struct cs_scene *sc, const struct cs_camera *cam)
{
	int w = cam->width, h = cam->height;
	/* the image's edges, the bottom row first (nearly always the one that
	 * does): the ground's directions from a point are a cap around the
	 * nadir, which meets the frame at its edge unless the frame holds
	 * the nadir itself (below); a terrain's peak in view rises from
	 * ground seen below it, down to the edge */
	for (int i = 0; i < w; i++)
		if (pixel_sees_ground(sc, cam, i, h - 1) || pixel_sees_ground(sc, cam, i, 0))
			return 1;
	for (int j = 0; j < h; j++)
		if (pixel_sees_ground(sc, cam, 0, j) || pixel_sees_ground(sc, cam, w - 1, j))
			return 1;
	/* a fisheye's edge is its circle's rim: the pixels of its outer two
	 * rings, those of each row between the ring's inner and outer
	 * circles on either side */
	if (cam->projection == CS_PROJ_FISHEYE) {
		double r = (w < h ? w : h) * 0.5, ri = r - 2.0;
		for (int j = 0; j < h; j++) {
			double y = h * 0.5 - j - 0.5;
			if (fabs(y) > r)
				continue;
			double xo = sqrt(r * r - y * y), xi = fabs(y) < ri ? sqrt(ri * ri - y * y) : 0.0;
			for (int side = -1; side <= 1; side += 2) {
				/* pixel i's centre is at x = i + 0.5 - w / 2 */
				int i0 = (int)floor(w * 0.5 - 0.5 + (side < 0 ? -xo : xi));
				int i1 = (int)ceil(w * 0.5 - 0.5 + (side < 0 ? -xi : xo));
				for (int i = i0 < 0 ? 0 : i0; i <= i1 && i < w; i++) {
					double x = i + 0.5 - w * 0.5, rho = sqrt(x * x + y * y);
					if (rho > ri && rho <= r && pixel_sees_ground(sc, cam, i, j))
						return 1;
				}
			}
		}
	}
	/* and the centre: a frame that looks at the nadir */
	return pixel_sees_ground(sc, cam, w / 2, h / 2);
}

int cs_frame_volumes_needed(const struct cs_scene *sc, const struct cs_render_settings *s)
{
	return ground_traced(sc, s) || CS_LIGHT_CACHED(s->light_march) || cs_tower_light_wanted(sc, s) ||
	       cs_scene_tilt_wanted(sc, s);
}

int cs_scene_air_lit(const struct cs_scene *sc)
{
	return sc->deck.on && ((CS_FX_IS(sc, CS_FX_HAZE) && sc->haze_beta0_per_m > 0.0) ||
			       CS_FX_IS(sc, CS_FX_RAIN | CS_FX_SNOW));
}

int cs_frame_scene(const struct cs_scene *sc, const struct cs_camera *cam,
		   const struct cs_render_settings *s, int nthreads, struct cs_scene **out,
		   uint64_t *evaluations, int *ground)
{
	*out = NULL;
	*evaluations = 0;
	*ground = ground_lit(sc, s);
	/* no dome or field for a frame that sees no ground, unless the
	 * field lights its haze or rain under the clouds (cs_ground_sky,
	 * cs_rain_top_sky):
	 * nothing else takes their light */
	struct cs_render_settings fs = *s;
	if ((*ground == CS_GROUND_LIT_DOME || *ground == CS_GROUND_LIT_FIELD) &&
	    !cs_camera_sees_ground(sc, cam)) {
		if (cs_scene_air_lit(sc)) { /* (the same sky whether it sees ground or not) */
			*ground = *ground == CS_GROUND_LIT_FIELD ? CS_GROUND_LIT_FIELD_AIR
								  : CS_GROUND_LIT_DOME_AIR;
		} else {
			fs.ground_sky = CS_GROUND_SKY_COLUMNS;
			*ground = CS_GROUND_LIT_UNSEEN;
		}
	}
	if (!cs_frame_volumes_needed(sc, &fs))
		return CS_OK;
	struct cs_scene *copy = malloc(sizeof *copy);
	if (copy == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	*copy = *sc;
	int rc = cs_light_cache_build(copy, &fs, (double)cam->width * cam->height, nthreads,
				      evaluations);
	if (rc == CS_OK && lit_by_field(*ground)) {
		rc = cs_ground_sky_field(copy, &fs, cam, nthreads, &copy->ground_field);
		for (int c = 0; c < 3 && rc == CS_OK; c++)
			copy->deck.sky_ground[c] = copy->ground_field.mean[c];
		if (rc != CS_OK)
			cs_light_cache_free(copy);
	}
	if (rc != CS_OK) {
		free(copy);
		return rc;
	}
	*out = copy;
	return CS_OK;
}

void cs_frame_scene_free(struct cs_scene *sc)
{
	if (sc == NULL)
		return;
	cs_light_cache_free(sc);
	free(sc);
}

int cs_light_cache_volumes(const struct cs_scene *sc)
{
	int n = 0;
	for (int i = 0; i < CS_SCENE_MAX_LAYERS; i++)
		n += (sc->light_cache[i].depth != NULL) + (sc->column_cache[i].depth != NULL) +
		     (sc->tower_light[i].depth != NULL);
	return n;
}

void cs_light_cache_free(struct cs_scene *sc)
{
	for (int n = 0; n < CS_SCENE_MAX_LAYERS; n++) {
		free((void *)sc->light_cache[n].depth);
		free((void *)sc->column_cache[n].depth);
		free((void *)sc->tower_light[n].depth);
		sc->light_cache[n] = (struct cs_light_cache){0};
		sc->column_cache[n] = (struct cs_light_cache){0};
		sc->tower_light[n] = (struct cs_light_cache){0};
	}
	free((void *)sc->ground_field.rgb);
	sc->ground_field = (struct cs_ground_field){0};
}
