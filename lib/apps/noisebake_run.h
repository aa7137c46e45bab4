/* noisebake.h - the noisebake program as a library call. */
#ifndef CS_NOISEBAKE_H
#define CS_NOISEBAKE_H

#include "noise/volume.h"

#include <stdint.h>

#define CS_PREVIEW_MAX_SLICES 64

struct cs_noisebake_opts {
	int size, depth;                 /* voxels: size x size x depth */
	struct cs_noise_recipe recipe;
	int use_float;                   /* 32-bit float EXR channels */
	int threads;                     /* <= 0: all processors */
	const char *output;              /* EXR path or "-", or NULL */
	const char *preview;             /* PNG path or "-", or NULL */
	int slices[CS_PREVIEW_MAX_SLICES];
	int nslices;                     /* 0: four evenly spaced slices */
	char channels[5];                /* preview rows, from "RGBA" */
	cs_progress_fn progress;
	void *progress_user;
	double bake_seconds;             /* out: wall time spent baking */
};

/* Defaults: 128^3, default recipe, half, all threads, preview RGBA. */
void cs_noisebake_defaults(struct cs_noisebake_opts *o);

/* Bakes the volume and writes the requested outputs. */
int cs_noisebake_run(struct cs_noisebake_opts *o);

/* A contact sheet: one row per channel in channels (letters of "RGBA"), one
 * column per slice, each tile nx x nx grey (value 0..1 -> 0..255), with a
 * 2-pixel white gap.  *pixels is malloc'ed for the caller. */
int cs_volume_contact_sheet(const struct cs_volume *v, const int *slices,
			    int nslices, const char *channels, uint8_t **pixels,
			    int *width, int *height);

#endif
