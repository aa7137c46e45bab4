/* render.h - the renderer's interface: quality settings, the scene it
 * renders, one ray, one frame.
 *
 * Where things are (all in lib/render/): the presets in quality.c, the
 * camera in camera.c, phase functions in phase.h, the march through the
 * cloud shells and the integrator in integrator.c, the light march toward
 * the sun in light_march.c, aerial perspective in haze.c, ground and
 * terrain shading in ground.c, a whole frame over the CPU pool in frame.c.
 *
 * World frame: east-north-up at sea level below the scene origin, metres;
 * the Earth is a sphere centred at (0, 0, -earth_radius_m) (core/sphere.h).
 * Radiance is in kcd/m^2 per linear-sRGB channel (see sky.h). */
#ifndef CS_RENDER_H
#define CS_RENDER_H

#include "core/pool.h"
#include "render/camera.h"
#include "render/cloud.h"
#include "render/phase.h"
#include "terrain/heightfield.h"

struct cs_cpt;
#include "render/sky.h"
#include "core/geo.h" /* CS_EARTH_RADIUS_M */
#include "core/vec.h"

#include <stdint.h>

#define CS_SCENE_MAX_LAYERS 24 /* near layers and those of the far sites */
#define CS_SKY_DEPTH_M 1e10 /* Z of a ray that meets neither cloud nor ground */

struct cs_render_settings {
	int steps;             /* view samples across a layer's thickness */
	int max_steps;         /* most samples in one crossing of a layer */
	int light_steps;       /* samples toward the sun */
	int ms_octaves;        /* 1: single scattering; 2..4: + multiple-scattering octaves */
	int ambient;           /* sky light on the clouds: 1 on, 0 off */
	double jitter;         /* 0: step midpoints; 1: a per-pixel random offset */
	uint32_t seed;         /* for the jitter hash */
	double min_transmittance; /* a ray stops when it sees less than this */
	int haze_steps;        /* samples of the clouds' shadows in the haze
				  (crepuscular rays) over the first 20 km;
				  0: their area mean only */
	int march;             /* CS_MARCH_*: how view samples are placed */
	int light_march;       /* CS_LIGHT_*: how light samples are placed */
	int source_every;      /* 2: a cloudy view sample's light (the light
				  march, the column above, the diffuse light)
				  found at every other one of a crossing, the
				  one between taking the mean of its
				  neighbours' (the presets but the
				  reference); 0 or 1: at each */
	double tower_cell_m;   /* the towers' diffused light (tower_light.c):
				  its lattice's spacing, m, 50..5000; 0:
				  none (the march's model alone) */
	int heap_towers;       /* 1: the heaps of cumulus take the towers'
				  light too (cs_tower_share); 0: the
				  march's model of them alone */
	int ground_sky;        /* CS_GROUND_SKY_*: the diffuse light on the
				  ground (and water) under clouds */
	int deck_lattice;      /* CS_DECK_*: whether a thick deck lit by
				  light fields takes the light that diffuses
				  between its columns from a lattice
				  (cs_deck_lattice, tower_cell_m apart) */
};

/* A thick deck's light (cs_render_settings.deck_lattice). */
enum {
	CS_DECK_COLUMNS,   /* its light fields' independent columns alone */
	CS_DECK_DIFFUSION, /* scaled by the lattice's diffusion against the
			      columns', a face toward a gap taking the sky's
			      and the ground's light */
	CS_DECK_EXCHANGE   /* the same, a face toward a gap taking what its
			      rays gather from the faces of cloud across it
			      (the towers' exchange) */
};

/* The diffuse light on the ground under clouds (cs_render_settings.ground_sky,
 * deck.sky_ground). */
enum {
	CS_GROUND_SKY_COLUMNS, /* the deck's: the area mean of its slab columns
				  (deck.sky_below); where rain or snow falls
				  under the clouds (and no fog), the field
				  (below), whose
				  light the precipitation takes: lit by the
				  area's mean, the capture's rain hour was
				  +138 % against the path tracer at medium */
	CS_GROUND_SKY_DOME,    /* the frame's: the area mean of the sky the
				  renderer draws over the ground, traced with
				  its own rays (cs_ground_sky_dome) */
	CS_GROUND_SKY_FIELD    /* the same sky's light as it varies over the
				  ground (cs_ground_sky_field) */
};

/* The view march (cs_render_settings.march). */
enum {
	CS_MARCH_STANDARD, /* steps of a layer's thickness over steps, the
			      source integrated over each step against its
			      transmittance, steps growing along long crossings */
	CS_MARCH_NAIVE,    /* the same steps, a plain sum S sigma dt at each
			      step's start, no cap: the constant-step shader
			      this project grew from, as a baseline */
	CS_MARCH_SKIP,     /* standard, but empty space probed every 4 steps
			      and the 3 between skipped while it stays empty */
	CS_MARCH_ADAPTIVE  /* standard, but a step whose sample is deeper than
			      CS_ADAPTIVE_TAU marched again in up to
			      CS_ADAPTIVE_PARTS parts: adaptive to density */
};
#define CS_ADAPTIVE_TAU 0.5
#define CS_ADAPTIVE_PARTS 4
/* The light march (cs_render_settings.light_march). */
enum {
	CS_LIGHT_UNIFORM,   /* equal steps toward the sun */
	CS_LIGHT_QUADRATIC, /* samples at (k + 1/2)^2 / n^2 of the path: dense
			       near the point, where its own cloud shades it */
	CS_LIGHT_GEOMETRIC, /* steps growing geometrically from the point: the
			       first about the layer's thickness over n, as a
			       vertical path's, however long the path (a low sun) */
	CS_LIGHT_CONE,      /* the geometric steps, each sample moved sideways
			       in the horizontal by up to CS_CONE_TAN of its
			       distance (Schneider 2015's cone), on the CPU
			       only */
	CS_LIGHT_CACHE,     /* the optical depth toward the sun looked up in
			       a volume built once a frame (struct
			       cs_light_cache), the geometric steps in a layer
			       that has none */
	CS_LIGHT_AUTO       /* the cache where it pays: a layer's volume is
			       built only where the frame has a pixel for
			       CS_AUTO_CELLS_PER_PIXEL of its cells, the
			       geometric steps elsewhere */
};
/* Whether light march m looks depths up in the light cache where a layer
 * has one. */
#define CS_LIGHT_CACHED(m) ((m) == CS_LIGHT_CACHE || (m) == CS_LIGHT_AUTO)
/* CS_LIGHT_AUTO's rule: a volume is built where the frame has a pixel
 * for every 32 of its cells.  Its build costs the same whatever the
 * frame's size.  At medium on 2 threads (160x90 to 640x360) the cache
 * paid for itself from about 8 cells a pixel in the default scene (its
 * million-cell volumes from 480x270), 30 under a cumulonimbus, and 70 or
 * more under altocumulus or inside a cloud, where most view samples are
 * lit: 32 loses at most 0.05 s against the better choice there */
#define CS_AUTO_CELLS_PER_PIXEL 32.0
#define CS_CONE_TAN 0.2

/* The named presets: "low", "medium", "high", "reference".  0 or CS_EINVAL. */
int cs_render_quality(const char *name, struct cs_render_settings *s);
/* Validates settings ranges; 0 or CS_EINVAL naming the field. */
int cs_render_settings_check(const struct cs_render_settings *s);
/* Whether s can render on a GPU (cs_cuda_render): the adaptive march and
 * the cone light march are the CPU's only.  0 or CS_EINVAL. */
int cs_render_settings_gpu_check(const struct cs_render_settings *s);

/* What a scene simulates (cs_scene.effects). */
enum {
	CS_FX_SUN = 1,           /* direct sunlight (sun above the horizon) */
	CS_FX_SKY = 2,           /* sky background and sky light */
	CS_FX_CLOUDS = 4,        /* at least one layer with coverage */
	CS_FX_GROUND = 8,        /* ground shading */
	CS_FX_HAZE = 16,         /* aerial perspective from visibility */
	CS_FX_RAIN = 32,         /* rain below raining layers */
	CS_FX_CLOUD_SHADOWS = 64, /* clouds shadowing the ground */
	CS_FX_TERRAIN = 128,     /* a heightfield instead of flat ground */
	CS_FX_DECK = 256,        /* light under the clouds: the sky light below and
				    inside the layers is what they transmit */
	CS_FX_FOG = 512,         /* fog: a grey medium from the ground up */
	CS_FX_SNOW = 1024,       /* falling snow (with or instead of rain) */
	CS_FX_HALO = 2048,       /* the 22-degree halo in cirrostratus */
	CS_FX_SHAFTS = 4096,     /* clouds' shadows in the haze: crepuscular rays */
	CS_FX_MOON = 8192,       /* the Moon is the key light (the sun is down) */
	CS_FX_STARS = 16384,     /* stars in the clear night sky */
	CS_FX_WATER = 32768,     /* open water on the terrain: sky reflection
				    and sun glint (render/water.h) */
	/* the key light, sun_dir and sun_illuminance: the sun or the Moon */
	CS_FX_KEY = CS_FX_SUN | CS_FX_MOON
};

/* The code a renderer is built with.  On a CPU every effect's; a GPU
 * kernel may be built for a set of them (CS_FX_BUILT, render_cuda.cu): a
 * scene without the others renders the same through code without theirs,
 * which the GPU runs faster (its registers and its instruction cache).
 * CS_FX_IS(sc, fx): the scene has one of the effects fx and their code is
 * built; CS_BUILT(fx): the code for fx is built, where the per-sample
 * code reads an effect from the scene's state instead of its flags (the
 * fog's extinction, the terrain, its water, the towers of cumulonimbus
 * and cumulus). */
#ifndef CS_FX_BUILT
#define CS_FX_BUILT 0xffffffffu
#endif
#define CS_BUILT(fx) ((CS_FX_BUILT & (unsigned)(fx)) != 0u)
#define CS_FX_IS(sc, fx) (((unsigned)(sc)->effects & CS_FX_BUILT & (unsigned)(fx)) != 0u)
/* what CS_FX_BUILT holds besides the effects: the towers' light
 * (cs_deck.tilt_weight), the light marched where a layer has no light
 * cache (cs_render_settings.light_march), and the light found at every
 * other sample (source_every 2) */
#define CS_BUILT_TOWERS (1u << 24)
#define CS_BUILT_LIGHT_MARCH (1u << 25)
#define CS_BUILT_SOURCE_EVERY2 (1u << 26)

/* How far along a ray the clouds' shadows in the haze are sampled, m;
 * beyond, their area mean. */
#define CS_SHAFTS_RANGE_M 20000.0
/* Crepuscular rays are simulated with the sun (or Moon) lower than this:
 * a high sun's shadows in the haze run steeply down, seen end-on, and
 * their area mean is all that shows. */
#define CS_SHAFTS_MAX_ELEVATION_DEG 30.0

/* The share of the light a cirrostratus scatters that goes into its
 * 22-degree halo (hexagonal crystals with clean faces are a minority of
 * the ice in real cirrus). */
#define CS_HALO_SHARE 0.08

/* Fog: visibility below 1 km (WMO).  Its top is that of a layer resting on
 * the ground (the weather state's fog layer) or 300 m up; the air above it
 * is taken to have a visibility of 10 km. */
#define CS_FOG_VISIBILITY_M 1000.0
/* The Preetham sky is used up to this turbidity: beyond it the model's
 * luminance patterns stop resembling real skies (Zotti, Wilkie &
 * Purgathofer 2007, "A Critical Review of the Preetham Skylight Model")
 * and its sky turns yellow-white and too bright; the aerosol of a hazier
 * day is the haze medium's, which takes the full visibility, and the sun's
 * beam is attenuated by the full turbidity. */
#define CS_SKY_MAX_TURBIDITY 4.0
/* And from this turbidity: below it the model's diffuse light grows as the
 * air clears (its Perez coefficients and zenith luminance were fitted for
 * turbidities of 2 and more, Preetham, Shirley & Smits 1999): the
 * horizontal illuminance of its dome under a sun 52 deg up is 24.9 klux
 * at 2, 26.0 at 1.9, 29.8 at 1.8 and 50.5 at 1.7, the GHI of a clear sky
 * at 100 km visibility (turbidity 1.34, clamped to 1.7) came out at
 * 1242 W/m2, more than the 1037 W/m2 at the top of the atmosphere.  The
 * beam still takes the full turbidity, clamped to 1.7 (cs_sky_init_beam). */
#define CS_SKY_MIN_TURBIDITY 2.0
#define CS_FOG_DEPTH_M 300.0
#define CS_FOG_AIR_VISIBILITY_M 10000.0

/* The name of one effect bit as --stats prints it ("sun", "deck"...), or
 * NULL past the last. */
const char *cs_effect_name(unsigned bit);

/* The light field inside fog (fog.c): the radiance of a plane-parallel
 * layer of droplets over a Lambertian ground, lit from above by the sky
 * (or what comes through the clouds) and the sun's beam, with multiple
 * scattering, by Fourier modes of the azimuth.  Levels k =
 * 0..CS_FOG_LEVELS-1 lie at heights depth (1 - k / (CS_FOG_LEVELS - 1))^2
 * above the ground, from the fog's top (0) to the ground, closer
 * together toward it (the light along the ground changes within metres of
 * it: below, nothing comes up from a dark ground; a metre up, a ray along
 * it has crossed kilometres of fog); table directions
 * m = 0..CS_FOG_DIRS-1 are directions of travel with vertical component
 * -1 + 2 m / (CS_FOG_DIRS - 1).  Radiances in kcd/m^2, irradiances in klux
 * (the units of sun_illuminance). */
#define CS_FOG_LEVELS 17
#define CS_FOG_DIRS 33
#define CS_FOG_SKY 17
#define CS_FOG_MODES 4
struct cs_fog_field {
	int on;
	int orders;    /* orders of scattering the solution took (most of any mode) */
	/* the source toward a direction: albedo times the phase function
	 * over the scattered light (not the sun's unscattered beam, whose
	 * single scattering the march adds with the full phase function), by
	 * Fourier mode n of the azimuth phi between the direction's and the
	 * sun's beam's (horizontal) directions of travel: the source is
	 * sum over n of (n ? 2 : 1) src[n] cos(n phi) */
	float src[CS_FOG_LEVELS][CS_FOG_DIRS][CS_FOG_MODES][3];
	double down[CS_FOG_LEVELS][3]; /* scattered light down on a horizontal plane */
	double up[CS_FOG_LEVELS][3];   /* and up */
};

/* What cs_fog_solve solves: the layer's optical depth, single-scattering
 * albedo and two-lobe phase function; the sun's beam at its top (on a
 * plane facing it) at cosine mu0 of its zenith angle (<= 0: none); the
 * radiance coming down at its top at |cosine| j / (CS_FOG_SKY - 1) of the
 * zenith angle, by Fourier mode n of the azimuth from the sun's beam's
 * direction of travel ((1 / 2 pi) times the integral of L cos(n phi)); the
 * ground's albedo. */
struct cs_fog_problem {
	double tau, albedo, g_forward, g_back, w_forward;
	double mu0, sun[3];
	/* of sun, the part whose first scattering the field keeps too (the
	 * forward peak's light of the layers over a deck, deck.sun_lobe:
	 * the march's own term scatters only the beam that comes through
	 * them unscattered); 0 for the fog */
	double sun_field[3];
	double sky_down[CS_FOG_SKY][CS_FOG_MODES][3];
	double albedo_ground[3];
};

/* Solves p into *out; CS_EINVAL for an optical depth outside [0, 1e4] or
 * an albedo outside [0, 1]. */
int cs_fog_solve(const struct cs_fog_problem *p, struct cs_fog_field *out);
/* Solves p[0..n) into out[0..n) (n at most CS_FOG_MAX_PROBLEMS), the same
 * bits as n calls of cs_fog_solve, on nthreads of the CPU pool (<= 0: one
 * per processor): each problem's Fourier modes and colours are solved
 * apart, and the quadrature's phase matrices are set up once for the
 * problems that share a phase function and mu0 with the one before (the
 * deck's depths).  CS_OK, CS_EINVAL (as cs_fog_solve, or n above
 * CS_FOG_MAX_PROBLEMS; then no field is on) or CS_ENOMEM.  n <= 0: CS_OK,
 * nothing done. */
#define CS_FOG_MAX_PROBLEMS 16
int cs_fog_solve_n(const struct cs_fog_problem *p, int n, struct cs_fog_field *out, int nthreads);

/* The azimuthal mean of the two-lobe phase function (1/sr) between
 * directions of cosines mu and nu (exact: elliptic integrals). */
double cs_fog_phase_mean(double mu, double nu, double g_forward, double g_back,
			 double w_forward);

/* The light under and inside the cloud layers (deck.c), from the
 * two-stream transmittance of the layers' column optical depths over an
 * area around the site: irradiances in klux, radiances in kcd/m^2. */
#define CS_DECK_FIELDS 2
#define CS_DECK_FIELD_COVER 0.5 /* a layer of more cover is lit by light fields */
#define CS_DECK_FIELD_FULL 0.7  /* and the least lit by them alone */
/* a layer this thin for the beam (tau_in / mu0) or less too, at any cover */
#define CS_DECK_FIELD_THIN 1.0
#define CS_DECK_FIELD_THIN_END 3.0 /* and one this thick or more by its cover alone */
#define CS_DECK_DEPTHS 4 /* light fields a layer: optical depths tau_in / 16, / 4, 1, 2 */
#define CS_DECK_FIELD_TAU_MAX 128.0 /* and at most this (the solution's time grows with it) */
#define CS_DECK_AREA_M 24000.0 /* the side of the square the deck's means are over: a forecast grid cell or two */
#define CS_DECK_TILT_TAU0 2.0 /* the tilted columns' thinnest field: 2, 8, 32, 128 */
#define CS_DECK_TILT_FULL 0.2 /* a cumulonimbus or cumulus of this cover or less is lit by them alone */
#define CS_DECK_TILT_NONE 0.5 /* and one of this cover or more not at all */
#define CS_DECK_HEAP_TILT_NONE 0.8 /* a cumulus's heaps: none from this cover (fog.c) */
struct cs_deck {
	int on;                      /* 0: the clear-sky ambient everywhere */
	double mu0;                  /* sine of the sun's elevation (>= 0) */
	double g;                    /* the phase function's mean cosine */
	double sky_below[3];         /* radiance of the diffuse light under all
					layers (cosine mean; irradiance / pi),
					the columns' area mean: what lights the
					haze (and the rain, under fog), the fog's
					solution and the ground the towers see,
					where the frame traces no field */
	double sky_ground[3];        /* the diffuse light the ground and water
					take under them (cosine mean), read by
					nothing else: sky_below, or with
					CS_GROUND_SKY_DOME the frame's dome's
					(cs_light_cache_build) */
	double ground_below[3];      /* radiance of ground light from below
					(albedo 0.2, lit by what comes through) */
	double direct_below;         /* area mean of the sun's beam transmittance
					through all layers */
	double sun_top[CS_SCENE_MAX_LAYERS][3]; /* sun's beam on a horizontal
						   plane at a layer's top, klux */
	double dif_top[CS_SCENE_MAX_LAYERS][3]; /* diffuse irradiance there, klux */
	/* and the light that the top and all under it send up and the layers
	 * wholly over it send back down, over and over, klux: the area's
	 * means of their reflectances Ru and Ro, (sun_top + dif_top)
	 * Ro Ru / (1 - Ro Ru), Ro Ru at most 0.99; 0 where no layer is wholly
	 * over the top, and where the top lies inside a deck of another
	 * layer (more than CS_DECK_FIELD_COVER), whose light is its own
	 * fields'.  A layer's light fields take it (cs_scene_deck_fields);
	 * the march's model of a broken layer's light (cs_deck_top_shade,
	 * cloud_ambient) and the towers' lattice do not: against the path
	 * tracer at 240x135, the capture's rain hour -16.3 % without it,
	 * +1.0 % with the fields', +1.6 % with the model's too; its
	 * overcast hour +3.8, +8.5 and +13.7 % (before sun_lobe) */
	double top_extra[CS_SCENE_MAX_LAYERS][3];
	/* Of the sun's light that reaches the top (sun_top and the part of
	 * dif_top that the layers over it scattered), what their phase
	 * function's forward peak keeps along the beam, klux: its beam
	 * through their depth scaled by delta-M similarity (Wiscombe 1977),
	 * e_sun mu0 exp(-(1 - chi2) tau / mu0), chi2 the phase's second
	 * moment, at most all of the sun's light that comes through and at
	 * least its unscattered beam, the area's mean; sun_top where nothing
	 * is over it.  A layer's light fields take it as the sun's beam
	 * (their own first scattering of its part over sun_top:
	 * cs_fog_problem.sun_field) and the rest of dif_top, with top_extra,
	 * as the sky's light from every side: against the path tracer at
	 * 240x135, the capture's overcast afternoon (cumulus of 59 % under
	 * altostratus of 99 % under cirrostratus) +8.5 % with all of dif_top
	 * from every side, +2.3 % with this (relative MSE 0.043 -> 0.024);
	 * its rain hour +1.0 and +0.3 %; but the nimbostratus of 70 % of its
	 * rain hour under its cirrostratus alone (96x54) -14.6 and -20.1 % */
	double sun_lobe[CS_SCENE_MAX_LAYERS][3];
	/* the layers over each layer's top (cs_layer_share_above > 0), one
	 * bit a layer: their local columns shade it (cs_deck_top_shade) */
	unsigned over_mask[CS_SCENE_MAX_LAYERS];
	double tau_in[CS_SCENE_MAX_LAYERS];     /* in-cloud column optical depth */
	double tau_lo[CS_SCENE_MAX_LAYERS];     /* the least and the most of the */
	double tau_hi[CS_SCENE_MAX_LAYERS];     /* in-cloud columns it is the mean of */
	/* the light from above inside a layer with only the ground below it,
	 * at its base, times this: the ground's return, reflected back down by
	 * the cloud over and over, 1 / (1 - albedo (1 - Td(tau_in))); 1 for
	 * layers over other layers */
	double ground_gain[CS_SCENE_MAX_LAYERS][3];
	/* the albedo for diffuse light of what lies under a layer's in-cloud
	 * columns, their mean: the ground (wet where it rains) and the column
	 * of rain or snow over it (cs_rain_column); the plain ground for a
	 * layer no column met.  ground_gain and the layer's light fields
	 * take it: 16 mm/h of rain under nimbostratus of full cover, seen
	 * from the ground 5 deg up, +6.8 % against the path tracer at high
	 * with it, -13.1 % with the plain ground (test_reference) */
	double albedo_in[CS_SCENE_MAX_LAYERS][3];
	/* of a layer under the open sky (none above it), the share of the
	 * sky's light in it that comes along the ray from the sky behind it,
	 * not from the dome: the phase's forward weight times exp(-tau_in)
	 * (thin veils; 0 under other layers) */
	double sky_through[CS_SCENE_MAX_LAYERS];
	/* and the share of its scattering that keeps that light in its
	 * direction, left in the sky's beam (the path's Tsky): the forward
	 * lobe's weight (the lobe, some 25 degrees wide, is narrow against
	 * how the sky's radiance varies), times the share of the sky's light
	 * that reaches the layer's inside through the lobe, by delta-M
	 * similarity (Wiscombe 1977) exp(-(1 - chi2) tau_in), chi2 = sum
	 * w g^2 the phase's second moment (0.78) */
	double sky_forward[CS_SCENE_MAX_LAYERS];
	/* the share of the clouds' phase function that takes light arriving
	 * from below (travelling up) into a direction of travel whose vertical
	 * component is -1 + 2 k / (CS_DECK_SHARES - 1) (k = 0..32) */
	double below_share[33];
	/* the light fields (cs_fog_solve) of the first CS_DECK_FIELDS layers
	 * of more than CS_DECK_FIELD_COVER, then of those thinner for the
	 * beam than CS_DECK_FIELD_THIN_END (the others keep the march's
	 * model), whose diffuse light the march reads from them
	 * (cs_deck_field_source): for each, the plane-parallel fields of
	 * slabs of optical depths field_tau, tau_in / 16, tau_in / 4, tau_in
	 * and 2 tau_in, none beyond CS_DECK_FIELD_TAU_MAX; a depth that no
	 * column measured over the area reaches, or equal to the one before,
	 * is a copy of the nearest solved one; field_of[i] is layer i's, or
	 * -1 */
	struct cs_fog_field field[CS_DECK_FIELDS][CS_DECK_DEPTHS];
	double field_tau[CS_DECK_FIELDS][CS_DECK_DEPTHS];
	int field_of[CS_SCENE_MAX_LAYERS];
	/* the share of a layer's diffuse light that its fields give (the
	 * rest the march's model): 0 at CS_DECK_FIELD_COVER, rising linearly
	 * to 1 at CS_DECK_FIELD_FULL, so that the light does not jump as a
	 * layer's cover passes a threshold; and, whatever the cover, 1 for a
	 * layer whose in-cloud depth over mu0 (the beam's slant depth
	 * through it) is CS_DECK_FIELD_THIN or less, falling linearly to 0
	 * at CS_DECK_FIELD_THIN_END (the larger of the two; fog.c) */
	double field_weight[CS_SCENE_MAX_LAYERS];
	/* for each set of fields, the share of diffusion's scaling that a
	 * column deeper than the deepest field takes (cs_deck_field_source):
	 * 0 at CS_DECK_FIELD_FULL cover, rising linearly to 1 at full cover
	 * (a broken deck's thick cells take light through their sides, which
	 * the columns do not count) */
	double field_deep[CS_DECK_FIELDS];
	/* Tilted columns (cs_deck_tilt_source): the light fields of slabs
	 * facing the key light, lit by its beam square on and by nothing
	 * else, of optical depths tilt_tau (CS_DECK_TILT_TAU0 times 4^k),
	 * from which the towers of cumulonimbus and the heaps of cumulus
	 * take their sun's diffuse light, for the share tilt_weight[i] of
	 * layer i's: 1 up to
	 * CS_DECK_TILT_FULL cover, falling linearly to 0 at
	 * CS_DECK_TILT_NONE (a cumulus's at CS_DECK_HEAP_TILT_NONE; the rest
	 * the march's model, and above half cover the layer's own fields);
	 * 0 for every other genus, and for
	 * every layer without a key light up or the deck (a frame reads
	 * cs_tower_share, which keeps a cumulus's for heap_towers) */
	struct cs_fog_field tilt[CS_DECK_DEPTHS];
	double tilt_tau[CS_DECK_DEPTHS];
	double tilt_weight[CS_SCENE_MAX_LAYERS];
};
#define CS_DECK_SHARES 33

/* A layer's optical depth toward the sun, built once a frame for
 * CS_LIGHT_CACHE (cs_light_cache_build).  The layer's density repeats
 * across the wind every period_across_m and along it every
 * period_along_m (the least common multiple of its tiles); so does the
 * depth from a point up to the layer's top along the sun's direction, and
 * one period of it is kept in sheared axes: column (i, j) is the sun's ray
 * that meets the layer's base at (i du, j dv) along and across the wind
 * (as cs_cloud_extinction moves them), its level k at the height base +
 * k dh, nh + 1 levels from the base to the top, and depth[(j nu + i)
 * (nh + 1) + k] the optical depth from there to the top along the ray.
 * Flat: a point's height above the ground's sphere is its altitude, and
 * the sun's direction is the site's (at 50 km from the site it turns by
 * 0.45 deg). */
struct cs_light_cache {
	const float *depth;        /* NULL: none (the layer is marched) */
	int nu, nv, nh;
	double du_m, dv_m, dh_m;
	double shear_u, shear_v;   /* along and across per metre of height
				      toward the sun */
	double path_per_m;         /* the ray's length per metre of height */
};

/* The ground's diffuse light as it varies under the clouds
 * (CS_GROUND_SKY_FIELD, cs_ground_sky_field): the cosine-weighted mean
 * radiance of the sky the renderer draws at the points of a square grid
 * 2 m above the flat ground, as deck.sky_ground is the dome's; where it
 * rains or snows a second plane of the same points 1 m under the raining
 * layer's base, the top of the precipitation's column, which it lights
 * (radiometry.c's sky_alt_m).  The ground and the precipitation take
 * their plane bilinear between the points, and beyond the outer ones
 * fading to its mean over fade_m. */
struct cs_ground_field {
	const float *rgb;   /* planes x n x n points of 3, rows south to north; NULL: none */
	int n;
	int planes;         /* 1; 2 where it rains or snows: in memory first the
			       ground plane, its rays from 2 m above the flat
			       ground through the precipitation, then the top
			       plane, the light at the precipitation's top, which
			       lights its column (0 is taken for 1) */
	double x0_m, y0_m;  /* the first point's east and north */
	double step_m;      /* between neighbours */
	double fade_m;
	double mean[3];     /* the (ground) plane's points' mean before the blur */
	double top_mean[3]; /* the top plane's */
};

struct cs_scene {
	double earth_radius_m;
	double ground_alt_m;          /* flat ground: the sphere at this altitude */
	double ground_albedo[3];
	const struct cs_hfield *terrain; /* or NULL: flat ground everywhere;
					    else flat ground only outside it */
	const uint8_t *terrain_color; /* sRGB 8-bit RGB over the terrain grid, or NULL */
	int terrain_color_w, terrain_color_h;
	const float *terrain_water;   /* 1 where the terrain's sample is water
					 (its grid, w x h), or NULL */
	double water_mss;             /* the water's mean square slope (wind) */
	const struct cs_cpt *terrain_cpt; /* height -> colour, or NULL */
	int nlayers;
	struct cs_cloud_layer layers[CS_SCENE_MAX_LAYERS];
	double cloud_depth_scale;     /* the factor on the sheets' extinction
					 that the forecast's beam asked for
					 (cs_scene_fit_beam); 1: none */
	double sky_level_scale;       /* the factor on the Preetham sky's
					 radiance (CS_SKY_LEVEL_INEICHEN; 1
					 for CS_SKY_LEVEL_PREETHAM) */
	const struct cs_volume *noise;
	cs_v3 sun_dir;                /* unit, toward the sun */
	double sun_illuminance[3];    /* irradiance on a plane facing the sun */
	double ambient_up[3];         /* sky radiance (cosine mean) from above */
	double ambient_down[3];       /* from below (ground light) */
	struct cs_sky sky;            /* used when effects has CS_FX_SKY */
	double haze_beta0_per_m;      /* aerosol extinction at sea level */
	double haze_scale_height_m;
	double fog_beta_per_m;        /* fog extinction, constant below fog_top_m */
	double fog_top_m;
	struct cs_fog_field fog;      /* the light in it, when fog_beta_per_m > 0 */
	double rain_extinction_per_m; /* grey extinction of falling rain, in a shaft */
	double rain_top_m;            /* rain falls from here to the ground */
	int rain_layer;               /* the raining layer: shafts under its cells */
	double precip_albedo;         /* of rain 0.9, of snow 1, mixed between */
	double ground_wet;            /* albedo factor of the ground, < 1 when wet */
	double albedo;                /* single-scattering albedo of cloud */
	double g_forward, g_back, w_forward; /* two-lobe Henyey-Greenstein */
	struct cs_deck deck;          /* used when effects has CS_FX_DECK */
	struct cs_sky moon_sky;       /* the daylight sky for the Moon's place */
	double moon_scale;            /* its light relative to the sun's */
	cs_v3 star_frame[3];          /* local east, north, up in equatorial axes */
	unsigned effects;
	/* CS_LIGHT_CACHE's volumes, per layer; cs_render_image builds them
	 * for its frame (a scene handed to it has none): the depth toward
	 * the sun, and the vertical column's (shear 0, a metre of path a
	 * metre of height: the depth from a point up to the layer's top, the
	 * column above a sample that its diffuse light takes) */
	struct cs_light_cache light_cache[CS_SCENE_MAX_LAYERS];
	struct cs_light_cache column_cache[CS_SCENE_MAX_LAYERS];
	/* the key light's diffused light in the towers of a cumulonimbus or
	 * the heaps of a cumulus (cs_tower_share > 0), per
	 * unit irradiance facing it (tower_light.c): the fluence, W/m^2 per
	 * W/m^2, on an unsheared lattice; in a deck (cs_deck_lattice) the
	 * ratio of the fluence to that of independent columns, 1 or more;
	 * depth NULL where none */
	struct cs_light_cache tower_light[CS_SCENE_MAX_LAYERS];
	struct cs_ground_field ground_field; /* CS_GROUND_SKY_FIELD's, for a frame */
};

/* Optical extinction (1/m) of rain falling at rate_mm_h, from the
 * Marshall-Palmer drop sizes (1948): N(D) = N0 exp(-L D), N0 = 8000 /m^3/mm,
 * L = 4.1 R^-0.21 /mm, and extinction efficiency 2 for drops much larger
 * than the wavelength: sigma = 2 (pi/4) N0 2 / L^3 = 0.365 R^0.63 per km. */
double cs_rain_extinction(double rate_mm_h);

/* Optical extinction (1/m) of snow falling at rate_mm_h of water: 3.9 per
 * km per mm/h, from Koschmieder's 3.912 / visibility and the snowfall
 * intensity classes by visibility of the U.S. Federal Meteorological
 * Handbook No. 1 (moderate snow, 1 mm/h, about 1 km; heavy, 2.5 mm/h, 0.4
 * km).  Rasmussen et al. (1999) measured the relation to scatter by a
 * factor of 3 to 10 with the crystals' kind: this is its middle. */
double cs_snow_extinction(double rate_mm_h);

/* The sky's absolute level (cloudrender --sky-level): Preetham's model's
 * own, or the Ineichen-Perez clear sky's diffuse light
 * (cs_clear_sky_dome_scale), the pattern and colour Preetham's either way. */
enum cs_sky_level { CS_SKY_LEVEL_PREETHAM = 0, CS_SKY_LEVEL_INEICHEN };

/* The night (night.c): with the sun below -6 deg and the Moon up, the
 * Moon becomes the key light (CS_FX_MOON, sun_dir, sun_illuminance; ambient light
 * gains the moonlit sky); below -12 deg the stars come out.  Call after
 * the sky and ambient light are set; with CS_SKY_LEVEL_INEICHEN the
 * moonlit sky's level is a clear sky's for the aerosol's optical depth at
 * 550 nm and the altitude (m), as the day's (cs_clear_sky_dome_scale). */
void cs_scene_night(struct cs_scene *sc, double time_utc, double lat_deg, double lon_deg,
		    double sun_elevation_deg, double turbidity, enum cs_sky_level level,
		    double aod550, double altitude_m);
/* The sky's radiance along d, moonlit sky included, and the sun's and
 * Moon's discs; the stars (kcd/m^2). */
CS_HD void cs_scene_sky(const struct cs_scene *sc, cs_v3 d, double rgb[3]);
CS_HD void cs_scene_disk(const struct cs_scene *sc, cs_v3 d, double rgb[3]);
CS_HD void cs_scene_stars(const struct cs_scene *sc, cs_v3 d, double rgb[3]);

/* Total (direct + diffuse) transmittance of a plane-parallel cloud of
 * optical depth tau (water droplets: asymmetry 0.85, albedo 0.99999, a
 * black ground) for the sun's beam at cosine mu0 of its zenith angle, and
 * for diffuse light: from slab_table.h (adding-doubling), interpolated;
 * at most 1, the beam's at least the direct exp(-tau / mu0).  A thick
 * cloud transmits like 1 / tau, and a low sun's beam less than a high
 * one's (about (1 + 2 mu0) / 3 of it: the escape function), the diffuse
 * light about 7/9 of an overhead sun's. */
CS_HD double cs_slab_beam_transmittance(double tau, double mu0);
CS_HD double cs_slab_diffuse_transmittance(double tau);
/* Both at once (one table row found). */
CS_HD void cs_slab_transmittances(double tau, double mu0, double *beam, double *diffuse);
/* x within [0, 1]; 0 for NaN. */
CS_HD static inline double cs_clamp01(double x)
{
	return !(x > 0.0) ? 0.0 : x < 1.0 ? x : 1.0;
}
/* Twice the extrapolation length of diffusion through a thick slab, in
 * optical depth, for a phase function of mean cosine g (at most 0.99):
 * 1.42 / (0.75 (1 - g)), so that its transmittance falls like
 * 1 / (tau + 2z) (12.6 for the droplets' 0.85); what slab_table.h's
 * transmittances are extended by beyond its last depth and the deck's
 * deepest light field scaled by (haze.c). */
CS_HD static inline double cs_slab_extrapolation_2z(double g)
{
	g = g < 0.99 ? g : 0.99;
	return 1.42 / (0.75 * (1.0 - g));
}
/* The escape function of an optically thick cloud: the radiance of the
 * diffuse light leaving its boundary at cosine mu to the normal, over the
 * flux leaving / pi, K(mu) = 3/7 (1 + 2 mu) (Eddington; Chandrasekhar's
 * exact sqrt(3)/4 H(mu) within 5 %): 3/7 along the surface, 9/7 along the
 * normal, 1 on the mean (2 int K mu dmu = 1).  mu is clamped to [0, 1]. */
CS_HD double cs_slab_escape(double mu);
/* The share of an isotropic sky's light that a plane of outward normal n
 * (vertical component nz) receives, against a horizontal plane facing up:
 * its view factor of the upper hemisphere, (1 + nz) / 2; the ground below
 * the horizon sends it the rest.  nz is clamped to [-1, 1]. */
CS_HD double cs_face_sky_share(double nz);
/* The share of layer li's diffuse light that its towers' light gives (its
 * tilted columns and diffused light) in a frame of settings s:
 * deck.tilt_weight[li], but 0 for cumulus unless s->heap_towers. */
CS_HD double cs_tower_share(const struct cs_scene *sc, const struct cs_render_settings *s, int li);
/* Whether layer li is a deck whose light fields take the light that
 * diffuses sideways between its columns from a lattice (tower_light.c,
 * sc->tower_light[li] the ratio): lit by light fields (deck.field_of),
 * of more than CS_DECK_FIELD_COVER cover, no towers' share, and a
 * diffusing medium: its in-cloud transport depth (1 - g) tau_in at
 * least CS_DECK_LATTICE_TRANSPORT (not a veil: the rain hour's
 * cirrostratus of full cover took a lattice of 900000 nodes for a ratio
 * of 1, and the fair hour's cirrus, lit by its fields for its thinness,
 * came out 5 to 10 % too dark with its ratio under 1). */
#define CS_DECK_LATTICE_TRANSPORT 1.0
CS_HD int cs_deck_lattice(const struct cs_scene *sc, int li);
/* The power of the lattice's ratio that scales a deck's fields' light
 * (tower_light.c, deck_ratio): the diffusion on the lattice counts too
 * little of what a thick cell takes in through its sides.  Under the
 * 70 % nimbostratus of tests/scenes' broken-deck-below, looking straight
 * up from 25 points 1.5 to 4.6 km apart (the path tracer, 8x8 pixels of
 * 256 paths), the light the fields lacked was about the ratio squared
 * (the ratio 1.47 to 1.63 where it was largest, 2.1 to 2.9 wanted), and
 * toward the horizon no more than the ratio itself.  Chosen on the test
 * views of test_reference (the same deck over another noise, 16x9, 2 x
 * 128 paths; 60, 70, 90 and 100 % cover, 15 and 40 deg up, toward the
 * sun and away, 600 m thick): the mean of their |bias| was 8.8 % at 1,
 * 5.2 % at 1.25, 6.8 % at 1.5 and 11.9 % at 1.75; test_reference fails
 * at 1 and at 1.5. */
#define CS_DECK_LATTICE_POWER 1.25

/* Fills sc->deck from the scene's layers, sun and clear-sky ambient (call
 * after those are set); sets CS_FX_DECK when there are layers.  Its light
 * fields are solved on nthreads of the CPU pool (<= 0: one per processor):
 * the same fields for any number. */
void cs_scene_deck_light(struct cs_scene *sc, int nthreads);

/* The light fields of the scene's layers of at least half cover (fog.c:
 * sc->deck.field, field_of), from the deck's light at their tops, and,
 * with a cumulonimbus or cumulus, the tilted columns' (sc->deck.tilt) (call at the
 * end of cs_scene_deck_light, which does); a layer whose field cannot be
 * made (out of memory) keeps the march's model of the diffuse light. */
void cs_scene_deck_fields(struct cs_scene *sc, int nthreads);
/* The tilted columns' fields that the heaps of cumulus take where a
 * frame's settings light them as towers (cs_tower_share) and that the
 * scene's build left unsolved (it solves them for cumulonimbus only):
 * whether they are wanted, and their solution into sc (where it fails,
 * out of memory, no layer keeps a towers' share).  cs_light_cache_build
 * solves them into its copy; call cs_scene_tilt_fields before reading
 * the scene's light outside a frame (cs_irradiance_at). */
int cs_scene_tilt_wanted(const struct cs_scene *sc, const struct cs_render_settings *s);
void cs_scene_tilt_fields(struct cs_scene *sc, const struct cs_render_settings *s, int nthreads);

/* Fills sc->fog (fog.c) from the scene's fog, sky, sun, deck and ground
 * (call after those are set; cleared without fog), solved on nthreads as
 * cs_scene_deck_light's fields; CS_ENOMEM. */
int cs_scene_fog_light(struct cs_scene *sc, int nthreads);

struct cs_render_stats {
	uint64_t pixels, density_samples, light_samples, rays_terminated_early,
		layer_crossings, terrain_cells;
	uint64_t cache_cells; /* the light cache's volumes' cells (in light_samples too) */
	int cache_volumes;    /* the light cache's volumes built for the frame */
	int ground_lit;       /* what lit the frame's ground: enum cs_ground_lit */
};

/* Transmittance of the clouds from p toward the sun (1 without clouds or
 * sun): what makes cloud shadows on the ground.  Marched through every
 * layer by the settings' rule (the cache's modes: geometric steps; never
 * the cache's depths) with their light steps, at least CS_SHADOW_STEPS,
 * and where the longest of those steps through a layer would be longer
 * than CS_SHADOW_STEP_M, equal steps of at most that length (no fewer
 * than before, at most CS_SHADOW_STEPS_MAX). */
#define CS_SHADOW_STEPS 32
#define CS_SHADOW_STEP_M 400.0 /* equal steps where one would be longer */
#define CS_SHADOW_STEPS_MAX 1024 /* (409.6 km: more than any path, 150 km at most) */
CS_HD double cs_render_sun_transmittance(const struct cs_scene *sc,
				   const struct cs_render_settings *s, cs_v3 p,
				   struct cs_render_stats *st);

struct cs_ray_result {
	double rgb[3];          /* radiance toward the eye */
	double transmittance;   /* through the clouds only (1 = clear) */
	double depth_m;         /* first cloud or ground hit, or CS_SKY_DEPTH_M */
};

/* Radiance along one ray from origin o in unit direction d.  jitter_u in
 * [0, 1) offsets the samples (0.5 = midpoints).  Never NaN or Inf. */
CS_HD void cs_render_ray(const struct cs_scene *sc, const struct cs_render_settings *s,
		   cs_v3 o, cs_v3 d, double jitter_u, struct cs_render_stats *st,
		   struct cs_ray_result *out);

/* Ground irradiance from the renderer's light transport, W/m^2
 * (radiometry.c): the sun's beam on a plane facing it, the diffuse light
 * on a horizontal plane, and their sum on it. */
struct cs_irradiance {
	double ghi_w_m2, dni_w_m2, dhi_w_m2;
};

/* At world point p (horizontal plane), from 192 rays over the sky's
 * hemisphere and the light march toward the sun. */
void cs_irradiance_at(const struct cs_scene *sc, const struct cs_render_settings *s,
		      cs_v3 p, struct cs_irradiance *out, struct cs_render_stats *st);
/* The side of the square whose mean irradiance stands for a forecast's
 * grid cell (cloudrender --stats), m. */
#define CS_IRRADIANCE_AREA_M 10000.0
/* The mean over n x n points 2 m above the ground (the terrain where the
 * scene has it) on a square of side size_m centred at the scene origin (a
 * forecast's grid cell). */
void cs_irradiance_area(const struct cs_scene *sc, const struct cs_render_settings *s,
			double size_m, int n, struct cs_irradiance *out,
			struct cs_render_stats *st);
/* The diffuse light on the ground under the clouds as the renderer draws
 * the sky (CS_GROUND_SKY_DOME): the cosine-weighted mean radiance (diffuse
 * irradiance / pi) of CS_GROUND_DOME_RAYS rays over the sky's hemisphere
 * from each of CS_GROUND_DOME_POINTS^2 points 2 m above the flat ground
 * (where it rains or snows, 1 m under the raining layer's base, as the
 * field's) on the deck's square (CS_DECK_AREA_M), the sun's
 * disc left to the beam as cs_irradiance_at leaves it, the terrain and the
 * stars taken away (a terrain's horizon is its ambient occlusion's); one
 * row of points a task on nthreads of the CPU pool, summed in order (the
 * same for any thread count).  Its rays are not in the frame's
 * statistics.  CS_OK, CS_ENOMEM or the pool's error. */
#define CS_GROUND_DOME_POINTS 32
#define CS_GROUND_DOME_RAYS 4 /* 2 x 2 strata of the cosine-weighted hemisphere */
int cs_ground_sky_dome(const struct cs_scene *sc, const struct cs_render_settings *s, int nthreads,
		       double rgb[3]);
/* The ground's diffuse light over the frame's ground (CS_GROUND_SKY_FIELD)
 * into *out, for cs_ground_light to read (out->rgb malloc'd: the caller
 * frees it, cs_light_cache_free for a frame's scene): a grid of
 * CS_GROUND_FIELD_POINTS^2 points over the deck's square (CS_DECK_AREA_M)
 * around the camera (on a lattice of the world: the point nearest under
 * the camera its middle, (n/2, n/2)), each the cosine-weighted mean
 * radiance of its rays over the sky (cs_ground_sky_dome's, in m x m
 * strata turned by the R2 sequence from point to point); one ray a point,
 * and up to CS_GROUND_FIELD_RAYS more shared out by the point's share of
 * the frame's ground (the camera's rays through every 4th pixel each way,
 * each to its four points by bilinear weights; each point's count rounded
 * down to a square, at most 4096), so that the ground the frame shows
 * most, around the camera, is lit by the most rays; then each point the
 * mean of its and its 8 neighbours' rays, weighted [1 2 1] x [1 2 1] (a
 * point of many rays keeps nearly its own light).  The mean of the
 * points' own values (before the blur) is the area's (out->mean; under
 * rain or snow the ground plane's, out->top_mean the top's).  One
 * row of points a task on nthreads of the CPU pool, each point's rays in
 * order: the same for any thread count.  Its rays are not in the frame's
 * statistics.  Where rain or snow falls it has two planes (struct
 * cs_ground_field), traced in turn: the top plane, the light under the
 * clouds, its rays from 1 m under the precipitation's top seeing none of
 * it, which lights the column's top; then the ground plane, its rays from
 * 2 m above the ground through the precipitation lit by the top plane;
 * each with the rays above.  Where the
 * scene has haze under clouds, which the field lights (cs_ground_sky) and
 * its rays see, a first pass of one ray a point lights it for the (top)
 * plane's, whose light the ground plane's haze takes.  CS_OK, CS_ENOMEM
 * or the pool's error (then *out is empty). */
#define CS_GROUND_FIELD_POINTS 64 /* 375 m apart */
#define CS_GROUND_FIELD_RAYS 8192
struct cs_camera;
int cs_ground_sky_field(const struct cs_scene *sc, const struct cs_render_settings *s,
			const struct cs_camera *cam, int nthreads, struct cs_ground_field *out);
/* The point (i, j) of cs_irradiance_area's n x n grid. */
cs_v3 cs_irradiance_area_point(const struct cs_scene *sc, double size_m, int n, int i, int j);
/* W/m^2 at p from the beam (on a plane facing the sun) and the diffuse
 * light (on a horizontal plane) in klux, by the efficacies below. */
void cs_irradiance_from_klux(const struct cs_scene *sc, cs_v3 p, double dni_klux,
			     double dhi_klux, struct cs_irradiance *out);
/* Luminous efficacy of daylight, lm/W (Littlefair 1988): of the sun's beam
 * at a sun elevation, and of diffuse light at a share of clear sky 0..1. */
double cs_beam_efficacy_lm_w(double elevation_deg);
double cs_diffuse_efficacy_lm_w(double clear_fraction);

/* The clear sky's irradiance (W/m^2) by Ineichen & Perez (2002), "A new
 * airmass independent formulation for the Linke turbidity coefficient",
 * Solar Energy 73(3), as pvlib's clearsky.ineichen: at an apparent sun
 * zenith (deg), an absolute (pressure-corrected) air mass, a Linke
 * turbidity at air mass 2, a site altitude (m) and the sun's irradiance
 * above the atmosphere; perez_enhancement nonzero multiplies the GHI by
 * exp(0.01 m^1.8) for the air mass m (Perez et al. 2002, Solar Energy
 * 73(5): pvlib's perez_enhancement, off by default there as unsure at
 * high air mass).  DNI is held to the model's bound from its GHI; all 0
 * with the sun down. */
void cs_clear_sky_ineichen(double zenith_deg, double air_mass_abs, double linke_turbidity,
			   double altitude_m, double dni_extra_w_m2, int perez_enhancement,
			   struct cs_irradiance *out);
/* The Linke turbidity at air mass 2 of an atmosphere with an aerosol
 * optical depth at 550 nm, a precipitable water (cm) and an altitude (m):
 * Ineichen (2008), "Conversion function between the Linke turbidity and
 * the atmospheric water vapor and aerosol content", Solar Energy 82. */
double cs_linke_turbidity(double aod550, double water_cm, double altitude_m);
/* Precipitable water of the U.S. Standard Atmosphere (1976), cm: the
 * forecasts carry none. */
#define CS_STANDARD_WATER_CM 1.42
/* Total solar irradiance at 1 au (Kopp & Lean 2011), W/m^2. */
#define CS_SOLAR_CONSTANT_W_M2 1361.0
/* Below this sun elevation the clear sky's level keeps its factor at it
 * (the clear-sky model is fitted to a sun above the horizon's haze; the
 * twilight sky dims by its own law, sky.c). */
#define CS_CLEAR_SKY_MIN_ELEVATION_DEG 10.0
/* The factor on the sky's radiance (cs_sky_scale_dome) that makes its
 * diffuse illuminance on a horizontal plane, cloudless, the clear-sky
 * model's DHI (cs_clear_sky_ineichen with the Perez enhancement, its Linke
 * turbidity by cs_linke_turbidity from the aerosol's optical depth at
 * 550 nm and the standard water) times the clear sky's diffuse efficacy;
 * the sky as cs_sky_init_beam makes it for the sun (or Moon) at sun_dir
 * and the turbidities given, at an altitude (m), under a source of
 * dni_extra_w_m2 above the atmosphere.  For a sun under
 * CS_CLEAR_SKY_MIN_ELEVATION_DEG, the factor at that elevation and the
 * same azimuth.  1 where either side has no diffuse light. */
double cs_clear_sky_dome_scale(cs_v3 sun_dir, double sky_turbidity, double beam_turbidity,
			       double aod550, double altitude_m, double dni_extra_w_m2);

/* Renders the image into out: 5 floats per pixel (R, G, B, alpha, Z), rows
 * top to bottom, on the CPU pool.  Deterministic for any nthreads (<= 0:
 * all processors).  progress may cancel: CS_ECANCELED. */
int cs_render_image(const struct cs_scene *sc, const struct cs_camera *cam,
		    const struct cs_render_settings *s, int nthreads,
		    cs_progress_fn progress, void *user, float *out,
		    struct cs_render_stats *stats);

/* Builds the light caches of sc's layers (struct cs_light_cache) for
 * CS_LIGHT_CACHE with s's light steps, on the CPU pool: for each layer of
 * clouds of one site whose density has periods, under a key light 15 deg
 * up or more (else the layer is marched), and for CS_LIGHT_AUTO only those
 * of at most CS_AUTO_CELLS_PER_PIXEL cells for each of the frame's pixels
 * (its width times its height); *evaluations: the density
 * evaluations it took.  The caches sc held are forgotten first, not freed
 * (sc is a copy of a scene: cs_render_image's, the GPU's).  Also the
 * vertical columns' volumes where the light fields and the ambient light
 * are on (sc->column_cache).  Last, the ground's light
 * (sc->deck.sky_ground): the columns' (sky_below), or with
 * CS_GROUND_SKY_DOME under clouds and without fog the dome's
 * (cs_ground_sky_dome), traced with the volumes just built; the field of
 * CS_GROUND_SKY_FIELD needs a camera: cs_frame_scene builds it.  CS_OK,
 * CS_ENOMEM or the pool's error (then none is left built and *evaluations
 * is 0). */
int cs_light_cache_build(struct cs_scene *sc, const struct cs_render_settings *s, double pixels,
			 int nthreads, uint64_t *evaluations);
/* How many light cache volumes sc holds (sun's and columns'). */
int cs_light_cache_volumes(const struct cs_scene *sc);
/* Frees sc's light caches (none: nothing). */
void cs_light_cache_free(struct cs_scene *sc);

/* Whether any of the camera's rays meets the ground or the terrain: the
 * rays of its edges (a fisheye's rim), the bottom row first, and its
 * centre's. */
struct cs_camera;
int cs_camera_sees_ground(const struct cs_scene *sc, const struct cs_camera *cam);
/* What lit a frame's ground and water (cs_render_stats.ground_lit), and
 * where CS_GROUND_SKY_DOME asked for the dome but it was not traced, why:
 * under clouds the columns' light (deck.sky_below) in every case but the
 * dome's; with fog, the ground in it takes the fog's light field. */
enum cs_ground_lit {
	CS_GROUND_LIT_COLUMNS,       /* CS_GROUND_SKY_COLUMNS */
	CS_GROUND_LIT_COLUMNS_FOG,   /* the same with fog, whose light field
					lights the ground in it */
	CS_GROUND_LIT_DOME,          /* the frame's dome (cs_ground_sky_dome) */
	CS_GROUND_LIT_CLEAR,         /* no deck (no clouds): the clear sky's
					ambient, whatever the settings */
	CS_GROUND_LIT_CLEAR_FOG,     /* the same with fog */
	CS_GROUND_LIT_FOG,           /* the dome or the field asked for under
					clouds and fog: the columns' (the
					fog's light is solved from them) */
	CS_GROUND_LIT_UNSEEN,        /* the dome or the field asked for; the
					frame sees no ground */
	CS_GROUND_LIT_FIELD,         /* the frame's field (cs_ground_sky_field) */
	CS_GROUND_LIT_FIELD_AIR,     /* the field asked for; the frame sees no
					ground, but its haze or rain under the
					clouds takes the field's light */
	CS_GROUND_LIT_DOME_AIR,      /* the same for the dome */
	CS_GROUND_LIT_FIELD_PRECIP   /* the columns asked for, but rain or snow
					falls under the clouds: the field,
					which the precipitation takes
					(cs_ground_sky), and the ground under
					it with it */
};
/* Its words for -v ("the field's", "the columns', none traced (the frame
 * sees no ground)"); "?" for a value out of range. */
const char *cs_ground_lit_name(int ground_lit);

/* Whether a frame of sc with settings s reads volumes built for it
 * (cs_light_cache_build): the ground's dome or field, the light caches, or the
 * towers' diffused light
 * (sc->tower_light: a layer with a towers' share, cs_tower_share, under a
 * key light, with the diffuse light on and s->tower_cell_m > 0). */
int cs_frame_volumes_needed(const struct cs_scene *sc, const struct cs_render_settings *s);
/* The scene a frame of sc through cam with settings s renders, for the
 * CPU (cs_render_image) and the GPU alike: *out NULL where the frame
 * needs no volumes of its own (sc as it is), else a copy of sc with them
 * built (cs_light_cache_build, then with CS_GROUND_SKY_FIELD, or with
 * CS_GROUND_SKY_COLUMNS where rain or snow falls under the clouds and
 * there is no fog, the ground's field for cam, cs_ground_sky_field, and
 * deck.sky_ground its
 * mean; the ground's dome or field only where the camera sees ground,
 * cs_camera_sees_ground, or where the scene has haze or rain under
 * clouds, which they light too, cs_scene_air_lit: elsewhere the pixels
 * are the same either way), for
 * cs_frame_scene_free; *evaluations the build's, *ground_lit
 * what lights its ground (enum cs_ground_lit).  CS_OK, CS_ENOMEM or the
 * build's error (then *out is NULL). */
int cs_frame_scene(const struct cs_scene *sc, const struct cs_camera *cam,
		   const struct cs_render_settings *s, int nthreads, struct cs_scene **out,
		   uint64_t *evaluations, int *ground_lit);
/* The share of layer j's column over layer i's top (deck.c): 1 where j
 * lies wholly above i, the part of its thickness above i's top where j's
 * base is above i's base but below its top (a cumulus whose top reaches
 * into a nimbostratus, lit as under the open sky before: on the
 * capture's rain hour the picture without its rain was +43 % against the
 * path tracer, and without that cumulus -27 %), else 0 (j below i, or i
 * inside j). */
double cs_layer_share_above(const struct cs_scene *sc, int j, int i);
/* The light at layer li's top over the point (x, y) (world metres), in
 * klux on a horizontal plane: the key light's beam into sun, the diffuse
 * light into dif, through the columns there of the layers over it
 * (deck.over_mask: their column caches where cached and built, else
 * steps samples each, counted into *samples) and, for the key light's,
 * through tau_key, their optical depth along its slant path to the point
 * (the light march's, all of their path; the column's where negative or
 * NaN).  Returned, the luminance of their sum over that of the area's
 * mean at the top (deck.sun_top + dif_top; 1 where that mean is nearly
 * 0).  For a layer with none over it, the mean's light and 1. */
CS_HD double cs_deck_top_shade(const struct cs_scene *sc, int li, double x, double y, int steps,
			       int cached, double tau_key, double sun[3], double dif[3],
			       uint64_t *samples);
/* Whether the scene has haze or rain (or snow) under clouds, which the
 * ground's light lights (cs_ground_sky) and its rays see. */
int cs_scene_air_lit(const struct cs_scene *sc);
/* Frees cs_frame_scene's copy and its volumes (NULL: nothing). */
void cs_frame_scene_free(struct cs_scene *sc);

/* The towers' diffused light (tower_light.c): whether a frame of sc with
 * settings s reads it, and its build into sc->tower_light for each layer
 * with a towers' share (cs_tower_share), and for each thick deck
 * (cs_deck_lattice) where s->deck_lattice is not CS_DECK_COLUMNS, with
 * the exchange only under CS_DECK_EXCHANGE, lattice cells about
 * s->tower_cell_m (the fluence per unit irradiance of the key light
 * facing it), the lattice's
 * extinction, the beam and the exchange's rays on nthreads of the CPU
 * pool; a cell that would make more than 2e7 nodes is grown until they
 * fit.  CS_OK, CS_ENOMEM or the pool's error. */
int cs_tower_light_wanted(const struct cs_scene *sc, const struct cs_render_settings *s);
int cs_tower_light_build(struct cs_scene *sc, const struct cs_render_settings *s, int nthreads,
			 uint64_t *evaluations);

/* The diffusion equation -div(D grad phi) + sigma_a phi = source in the
 * nodes of cloud (sigma_tr > 0) of a lattice of nu x nv x nk nodes,
 * periodic along u and v, node (i, j, k) at index (j nu + i) nk + k;
 * D = 1 / (3 sigma_tr) (1/m); source in watts a node's volume (half a
 * level at k = 0 and nk - 1).  At a face of cloud toward clear air or
 * out of the layer (k = 0, nk - 1), Marshak's condition with the light
 * coming in, W/m^2: j_in[0] from above, ground_in[j nu + i] from below
 * (j_in[1] everywhere where ground_in is NULL), on a wall half each;
 * with exchange, at a face toward a clear node of the lattice, what that
 * node sees instead over 48 directions: the sky, the ground, the horizon
 * (half each: also where a direction meets cloud within its first two
 * cells, so that a gap narrower than three cells exchanges nothing), and
 * the light leaving the faces of cloud the directions meet; the
 * directions traced on nthreads of the CPU pool.  phi gets the
 * fluence, W/m^2 (a clear node the mean of its cloud neighbours', or
 * 2 (j_in[0] + j_in[1])); *iterations BiCGSTAB's count.  CS_OK,
 * CS_ENOMEM, the pool's error, or CS_EINVAL for a lattice whose faces
 * outnumber 32-bit indices (6 nodes >= 2^31). */
int cs_diffusion_solve(int nu, int nv, int nk, double du_m, double dv_m, double dh_m,
		       const float *sigma_tr, const float *sigma_a, const double *source,
		       const double j_in[2], const double *ground_in, int exchange, int nthreads,
		       float *phi, int *iterations);
/* exchange's CS_DIFFUSE_COLUMNS: no light between neighbouring columns,
 * each column its own slab (no sideways faces, no exchange), solved
 * directly (*iterations 1): the independent columns a deck's lattice
 * sets its light against (cs_deck_lattice) */
#define CS_DIFFUSE_COLUMNS 2

/* The build of the per-pixel code cs_render_image runs on this CPU
 * (cpu/kernel.c, -O3): "avx512" where the CPU has x86-64-v4, else "avx2"
 * where it has AVX2, else "base"; the environment's CLOUDSCAPE_KERNEL, one
 * of these words, names the best to take.  All give the same bits. */
const char *cs_render_kernel_name(void);

/* out[i] = cs_cloud_extinction(l, noise, xyz[3i], xyz[3i+1], xyz[3i+2])
 * for i < n, computed by the same build of the per-pixel code that
 * cs_render_image runs on this CPU (cs_render_kernel_name; the same bits
 * as cs_cloud_extinction): what make bench's density figure measures. */
void cs_render_extinction(const struct cs_cloud_layer *l, const struct cs_volume *noise, int n,
			  const double *xyz, double *out);

/* Altitude above sea level of a world point. */
CS_HD double cs_scene_altitude(const struct cs_scene *sc, cs_v3 p);

#endif
