/* kernels.h - the GPU's render kernels besides the one with every effect:
 * render_cuda.cu compiled again for a set of effects (CS_FX_BUILT,
 * render.h), one object each (the Makefile's CUDA_KERNELS names the same
 * ones).  A frame renders with the first whose set holds everything the
 * scene and the settings need (scene_needs in render_cuda.cu), else with
 * the kernel of every effect ("all").
 *
 * Why: the kernel of every effect is 1.7 MB of code, whose registers are
 * allocated for the rarest path; without the effects a scene lacks the
 * compiler drops their code, and the common scenes run faster
 * (cloudrender(1), GPU, has the figures).
 *
 * "plain": sun, sky, clouds of any genus but cumulonimbus towers (and
 * cumulus heaps with cs_render_settings.heap_towers) lit through their
 * tilted columns, flat ground with the clouds' shadows,
 * haze with the crepuscular rays of a low sun, the deck's light, the
 * light from the light cache at every sample (the low, medium and high
 * presets on a GPU).
 * "terrain": the same over a heightfield, with its water.
 * "weather": the same with fog, rain, snow and the halo.
 * (A kernel with a cumulonimbus's towers too, 999 KB of machine code
 * against every effect's 1.74 MB, rendered the study's cumulonimbus
 * side view 2 % faster on an H200: the towers' code is most of every
 * effect's kernel.  Those scenes keep it.) */
#ifndef CS_CUDA_KERNELS_H
#define CS_CUDA_KERNELS_H

#include "render/render.h"

/* CS_CUDA_FX_name: the effects kernel name is built for */
#define CS_CUDA_FX_plain                                                                       \
	(CS_FX_SUN | CS_FX_SKY | CS_FX_CLOUDS | CS_FX_GROUND | CS_FX_HAZE | CS_FX_CLOUD_SHADOWS | \
	 CS_FX_DECK | CS_FX_SHAFTS)
#define CS_CUDA_FX_terrain (CS_CUDA_FX_plain | CS_FX_TERRAIN | CS_FX_WATER)
#define CS_CUDA_FX_weather                                                                    \
	(CS_CUDA_FX_terrain | CS_FX_FOG | CS_FX_RAIN | CS_FX_SNOW | CS_FX_HALO)

/* X(name) for each, in the order they are tried */
#define CS_CUDA_KERNELS(X) X(plain) X(terrain) X(weather)

#endif
