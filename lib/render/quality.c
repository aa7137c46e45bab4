/* quality.c - the named quality presets and the settings' valid ranges.
 * What each preset costs and its error: man/cloudrender.1, QUALITY.
 * Chosen on the measured front (scripts/accuracy-study against the path
 * tracer, scripts/quality-study against the converged march): toward the
 * sun the error falls fastest, and light steps in fours fill the CPU
 * kernel's four lanes, so the presets spend on light steps what fewer
 * view steps save, down to where the view's jitter would show as grain
 * at a cloud's edge (16 and 20 show it, 24 barely when looked at twice
 * the size, 32 and 48 do not).  Medium
 * takes 24 view and 12 light steps: against 32 and 8 the study's
 * geometric mean relative MSE falls from 0.0144 to 0.0119 and its worst
 * ground irradiance from +50 to +28 %, the CPU renders 5 to 13 % faster
 * and an H200 as fast (cloudrender(1), QUALITY).  High
 * takes three multiple-scattering octaves, as medium does: since layers
 * of more than half cover take their multiple scattering from light
 * fields, not the octaves (which now add beside them only the light a
 * cell takes in through a nearer side than its column's top:
 * integrator.c, sample_source), a third octave brings the long view through
 * altocumulus from -5.7 to -2.1 % against the path tracer and the silver
 * lining from -4.7 to -1.1 %, the fair cumulus from +2.6 to +5.0 %, and
 * the geometric mean relative MSE of the study's nine scenes from 0.0125
 * to 0.0114 (two octaves had been nearer while a third over-lit the view
 * from inside stratocumulus of 90 % cover, +26 % against +18 %).  Low
 * keeps two.  Low, medium and high find a cloudy sample's light at
 * every other view sample (source_every 2): on the study's 13 scenes
 * on one thread high's relative MSE is the same (0.0114) in 31 % less
 * time, medium's 0.0119 -> 0.0123 and low's 0.0159 -> 0.0164 in 23 and
 * 17 % less; the default 1280x720 scene renders 20 % faster on the CPU
 * and 6 % on an H200 at medium (cloudrender(1), QUALITY).  The reference
 * keeps the light at every sample, and so do low, medium and high on a
 * GPU, where their light is cached: there every sample is the faster
 * (cs_cloudrender_settings).  Low, medium and high look the depths
 * toward the sun and up the column in the light cache where it has them
 * and where the frame is large enough to pay for them (CS_LIGHT_AUTO):
 * with the cache (CS_LIGHT_CACHE), on the study's scenes, the relative
 * MSE of low and medium is less
 * (0.01639 and 0.01228 -> 0.01537 and 0.01195), and the default 1280x720
 * scene renders in 0.63 of the time on the CPU, 0.60 on an H200 at
 * medium (cloudrender(1), QUALITY).  High marched its light until the
 * study at 320x180 (scripts/accuracy-study --size 320x180 --spp 32,
 * whose frames the cache pays for) put it off the front: there the
 * geometric march took 7.14 s for the 13 scenes at a relative MSE of
 * 0.01151, the cache where it pays 4.52 s and 0.01137 (one run, one
 * thread a render, 2 at once); the default 1280x720 scene 2.46 -> 1.49 s.  The cache's
 * volume, 120 m between its columns, holds high 4.5 dB further from the
 * converged march (50.5 against 55.0 dB, quality-study 640x360), but not
 * further from the path tracer, which the study measures.  The reference
 * marches (geometric).  Every preset solves a
 * cumulonimbus's diffused light on a lattice 400 m apart (tower_cell_m,
 * tower_light.c): 800 m merged the towers' edges with the gaps and lit
 * the side view +6.7 % against the path tracer at high with relative
 * MSE 0.181, worse than none (0.156); 400 m -4.1 % and 0.081; 200 m
 * -6.2 % and 0.073 in 7 times the time (1.2 against 0.16 s a frame
 * on 2 threads); at medium 600 m was worse than 400 on all five
 * cumulonimbus scenes measured, before the towers' faces exchanged their
 * light (cloudrender(1), REFERENCE).  High and the reference light the
 * heaps of cumulus as towers too (heap_towers): on the study's sixteen
 * scenes at 320x180 high measured 0.0138 in 5.91 s against 0.0152 in
 * 5.17 s without, cumulus with the sun behind the eye 0.031 against
 * 0.077; medium with them, 0.0143 in 3.83 s against 0.0159 in 3.46 s, is
 * on the CPU's front too, but the default scene at 1920x1080 on an H100
 * took 26.9 ms a frame against 6.3 (the towers' code in the kernel), so
 * low and medium keep the slab's columns (cloudrender(1), QUALITY).  High
 * and the reference light the ground under clouds by the sky the frame
 * draws as it varies over the ground (ground_sky, CS_GROUND_SKY_FIELD):
 * on the study's twelve scenes that see ground, 320x180, its mean bias
 * against the path tracer 2.3 % against 4.1 % by the area's mean
 * (CS_GROUND_SKY_DOME; 6.2 % by the columns, which an earlier release
 * measured), the relative MSE the same (0.01378 and 0.01379), for some
 * 11000 to 12000 rays a frame against 4096; medium keeps the columns:
 * its heaps' bases, a slab's, are too bright, and its dome with them
 * (cloudrender(1), Light), except where rain or snow falls under the
 * clouds, which takes the field's light (light_cache.c: lit by the
 * columns' area mean the capture's rain hour was +138 % at medium).  Every
 * preset gives thick decks the light that diffuses between their columns
 * (deck_lattice, the towers' lattice solved on them): the study's
 * broken-deck-below -39 -> -6 % at high.  High and the reference solve
 * it with the exchange between the faces across the gaps, the rain
 * hour's deck at 480x270 2.1 -> 4.1 s on one thread when it came; low
 * and medium without (CS_DECK_DIFFUSION, half the solve): at 320x180
 * broken-deck-below low -33.0 -> -0.6 %, medium -37.1 -> -6.9 %
 * (relative MSE 0.158 -> 0.038; 0.040 and -4.7 % with the exchange), in
 * 0.25 -> 0.57 s (0.90 s) on one thread; the capture's rain hour at
 * 480x270 medium 1.90 -> 2.21 s (2.58 s), -11.6 -> -5.5 % (-7.4 %)
 * against the path tracer (cloudrender(1), Light and QUALITY). */
#include "render/render.h"

#include "core/err.h"

#include <string.h>
#include <strings.h>

static const struct {
	const char *name;
	struct cs_render_settings s;
} presets[] = {
	{"low", {24, 96, 8, 2, 1, 1.0, 0, 0.02, 8, CS_MARCH_STANDARD, CS_LIGHT_AUTO, 2, 400.0, 0, CS_GROUND_SKY_COLUMNS, CS_DECK_DIFFUSION}},
	{"medium", {24, 192, 12, 3, 1, 1.0, 0, 0.01, 16, CS_MARCH_STANDARD, CS_LIGHT_AUTO, 2, 400.0, 0, CS_GROUND_SKY_COLUMNS, CS_DECK_DIFFUSION}},
	{"high", {48, 384, 16, 3, 1, 1.0, 0, 0.005, 32, CS_MARCH_STANDARD, CS_LIGHT_AUTO, 2, 400.0, 1, CS_GROUND_SKY_FIELD, CS_DECK_EXCHANGE}},
	{"reference",
	 {384, 1536, 24, 4, 1, 1.0, 0, 0.0005, 128, CS_MARCH_STANDARD, CS_LIGHT_GEOMETRIC, 1, 400.0, 1, CS_GROUND_SKY_FIELD, CS_DECK_EXCHANGE}},
};

int cs_render_quality(const char *name, struct cs_render_settings *s)
{
	for (size_t i = 0; i < sizeof presets / sizeof presets[0]; i++)
		if (strcasecmp(name, presets[i].name) == 0) {
			*s = presets[i].s;
			return CS_OK;
		}
	return cs_error(CS_EINVAL, "unknown quality '%s' (expected low, medium, high or reference)",
			name);
}

int cs_render_settings_check(const struct cs_render_settings *s)
{
	if (s->steps < 1 || s->steps > 100000)
		return cs_error(CS_EINVAL, "steps must be 1..100000, not %d", s->steps);
	if (s->max_steps < s->steps || s->max_steps > 1000000)
		return cs_error(CS_EINVAL, "max steps must be steps..1000000, not %d",
				s->max_steps);
	if (s->light_steps < 1 || s->light_steps > 10000)
		return cs_error(CS_EINVAL, "light steps must be 1..10000, not %d",
				s->light_steps);
	if (s->ms_octaves < 1 || s->ms_octaves > 4)
		return cs_error(CS_EINVAL, "multiple-scattering octaves must be 1..4");
	if (!(s->jitter >= 0.0 && s->jitter <= 1.0))
		return cs_error(CS_EINVAL, "jitter must be 0..1");
	if (s->heap_towers != 0 && s->heap_towers != 1)
		return cs_error(CS_EINVAL, "heap towers must be 0 or 1, not %d", s->heap_towers);
	if (s->deck_lattice < CS_DECK_COLUMNS || s->deck_lattice > CS_DECK_EXCHANGE)
		return cs_error(CS_EINVAL, "unknown deck lattice %d", s->deck_lattice);
	if (s->ground_sky < CS_GROUND_SKY_COLUMNS || s->ground_sky > CS_GROUND_SKY_FIELD)
		return cs_error(CS_EINVAL, "unknown ground sky %d", s->ground_sky);
	if (s->march < CS_MARCH_STANDARD || s->march > CS_MARCH_ADAPTIVE)
		return cs_error(CS_EINVAL, "unknown march %d", s->march);
	if (s->light_march < CS_LIGHT_UNIFORM || s->light_march > CS_LIGHT_AUTO)
		return cs_error(CS_EINVAL, "unknown light march %d", s->light_march);
	if (s->source_every < 0 || s->source_every > 2)
		return cs_error(CS_EINVAL, "the source's stride must be 1 or 2, not %d",
				s->source_every);
	if (s->haze_steps < 0 || s->haze_steps > 10000)
		return cs_error(CS_EINVAL, "haze steps must be 0..10000, not %d", s->haze_steps);
	if (!(s->tower_cell_m == 0.0 || (s->tower_cell_m >= 50.0 && s->tower_cell_m <= 5000.0)))
		return cs_error(CS_EINVAL, "the towers' cell must be 0 or 50..5000 m, not %g",
				s->tower_cell_m);
	if (!(s->min_transmittance >= 0.0 && s->min_transmittance < 1.0))
		return cs_error(CS_EINVAL, "minimum transmittance must be in [0, 1)");
	return CS_OK;
}

const char *cs_effect_name(unsigned bit)
{
	static const char *const names[] = {"sun", "sky", "clouds", "ground", "haze",
					    "rain", "cloud_shadows", "terrain", "deck", "fog", "snow", "halo", "shafts", "moon", "stars",
					    "water"};
	for (unsigned b = 0; b < sizeof names / sizeof names[0]; b++)
		if (bit == 1u << b)
			return names[b];
	return NULL;
}

int cs_render_settings_gpu_check(const struct cs_render_settings *s)
{
	if (s->march == CS_MARCH_ADAPTIVE)
		return cs_error(CS_EINVAL, "the adaptive march runs on the CPU only "
				"(on a GPU: the standard, naive or skip march)");
	if (s->light_march == CS_LIGHT_CONE)
		return cs_error(CS_EINVAL, "the cone light march runs on the CPU only "
				"(on a GPU: the geometric, uniform or quadratic light march or "
				"the light cache)");
	return CS_OK;
}
