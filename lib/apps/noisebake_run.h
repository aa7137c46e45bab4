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
	int no_clobber;                  /* never replace an existing file */
	int slices[CS_PREVIEW_MAX_SLICES];
	int nslices;                     /* 0: four evenly spaced slices */
	char channels[5];                /* preview rows, from "RGBA" */
	cs_progress_fn progress;
	void *progress_user;
};

/* What a run produced. */
struct cs_noisebake_result {
	int nx, ny, nz;                  /* the volume baked, voxels */
	double bake_seconds;             /* wall time spent baking */
};

/* Defaults: 128^3, default recipe, half, all threads, preview RGBA. */
void cs_noisebake_defaults(struct cs_noisebake_opts *o);

/* Bakes the volume and writes the requested outputs, all together or none
 * (their places are checked before the bake).  Option mistakes
 * return CS_EINVAL; the system's CS_EIO or CS_ENOMEM. */
int cs_noisebake_run(const struct cs_noisebake_opts *o, struct cs_noisebake_result *r);

/* Channel c (0..3) of v: smallest, largest and mean value over every voxel. */
void cs_volume_channel_stats(const struct cs_volume *v, int c, double *lo,
			     double *hi, double *mean);

/* A contact sheet: one row per channel in channels (letters of "RGBA"), one
 * column per slice, each tile nx x nx grey (value 0..1 -> 0..255), with a
 * 2-pixel white gap.  *pixels is malloc'ed for the caller. */
int cs_volume_contact_sheet(const struct cs_volume *v, const int *slices,
			    int nslices, const char *channels, uint8_t **pixels,
			    int *width, int *height);

#endif
