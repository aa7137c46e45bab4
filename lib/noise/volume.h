/* volume.h - the tileable 3D noise volume (four channels, R G B A).
 *
 * Voxel (x, y, z) of channel c is data[((z * ny + y) * nx + x) * 4 + c].
 * The volume is periodic: voxel nx-1 neighbours voxel 0 on every axis. */
#ifndef CS_VOLUME_H
#define CS_VOLUME_H

#include "core/hd.h"

#include "core/pool.h"

#include <stddef.h>
#include <stdint.h>

#define CS_VOLUME_FORMAT 1  /* the cloudscapeFormat attribute written */
#define CS_VOLUME_MAX_DIM 1024
/* The most voxels a volume file may hold (4 GiB of floats when read), and
 * the EXR reader's limit on its pixels: 512 x 512 x 1024, 1024 x 1024 x 256. */
#define CS_VOLUME_MAX_READ_VOXELS ((long)1 << 28)

/* How the channels were made (see man 5 cloudscape-noise).
 * R: Perlin-Worley base shape; G, B, A: inverted Worley fBm (detail). */
struct cs_noise_recipe {
	uint32_t seed;   /* 0..2147483647 */
	int freq[4];     /* lattice cells across the volume's x extent, per channel */
	int octaves[4];  /* fBm octaves per channel (R: Perlin; Worley part uses worley_octaves) */
	int worley_octaves; /* octaves of the Worley fBm inside R */
	double gain;     /* fBm amplitude ratio between octaves, (0, 1] */
};

struct cs_volume {
	int nx, ny, nz;          /* voxels; nx == ny */
	float *data;             /* 4 * nx * ny * nz floats, owned */
	struct cs_noise_recipe recipe;
};

/* The default recipe: R = Perlin-Worley freq 4 (Perlin 4 octaves, Worley 3),
 * G, B, A = Worley fBm freq 4, 8, 16 with 3 octaves; gain 0.5; seed 0. */
void cs_noise_recipe_default(struct cs_noise_recipe *r);

/* Validates a recipe; 0 or CS_EINVAL with a message naming the field. */
int cs_noise_recipe_check(const struct cs_noise_recipe *r);

/* Formats the recipe as "R=perlin-worley:4:4:3;G=worley-fbm:4:3;..." plus
 * ";gain=0.5" (the cloudscapeRecipe attribute).  Returns the length. */
int cs_noise_recipe_format(const struct cs_noise_recipe *r, char *buf,
			   size_t size);

/* Parses what cs_noise_recipe_format() wrote (seed is left unchanged). */
int cs_noise_recipe_parse(const char *s, struct cs_noise_recipe *r);

/* Lattice period in cells of channel c along each axis: freq along x and y,
 * max(1, round(freq * nz / nx)) along z, so that a thin volume still tiles. */
void cs_noise_period(const struct cs_noise_recipe *r, int c, int nx, int nz,
		     int period[3]);

/* Allocates an nx * nx * nz volume of zeros. */
int cs_volume_new(struct cs_volume *v, int nx, int nz);
void cs_volume_free(struct cs_volume *v);

/* Fills v (already allocated) from its recipe using nthreads threads (<= 0:
 * all online processors) of the CPU pool, one z slice a task; progress is
 * called from the calling thread and may cancel (CS_ECANCELED).  The result
 * does not depend on nthreads. */
int cs_volume_bake(struct cs_volume *v, int nthreads, cs_progress_fn progress,
		   void *user);

/* One channel sampled at (u, v, w) in volume periods (1.0 = one tile),
 * trilinear, periodic on every axis.  Any finite coordinate is valid. */
CS_HD float cs_volume_sample(const struct cs_volume *v, int channel, double u,
		       double vv, double w);

/* All four channels at once (one set of voxel lookups). */
CS_HD void cs_volume_sample4(const struct cs_volume *v, double u, double vv,
		       double w, float out[4]);

/* Writes the volume as an OpenEXR atlas (see man 5 cloudscape-noise):
 * nx wide, nx * nz high, channels A B G R, half (or 32-bit float when
 * use_float), ZIP, with the cloudscape* attributes.  path "-" = stdout.
 * Atomic: no partial file on failure.  Compressed on nthreads threads (<= 0:
 * one per processor), the same bytes for any number. */
int cs_volume_write_exr(const struct cs_volume *v, const char *path,
			int use_float, int nthreads);

struct cs_outfile;

/* cs_volume_write_exr() into an open output (core/fileio.h), not
 * committed; name labels messages. */
int cs_volume_write_exr_to(const struct cs_volume *v, struct cs_outfile *of,
			   const char *name, int use_float, int nthreads);

/* Reads and validates a volume written by cs_volume_write_exr() ("-" =
 * stdin), decoded on nthreads threads (<= 0: one per processor).  On
 * error v is left empty and the message says what is wrong. */
int cs_volume_read_exr(const char *path, struct cs_volume *v, int nthreads);

/* Same, from a memory buffer, on one thread; name is used in messages. */
int cs_volume_read_exr_mem(const void *data, size_t len, const char *name,
			   struct cs_volume *v);

#endif
