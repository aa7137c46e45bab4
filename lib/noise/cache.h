/* cache.h - the noise volumes cloudrender bakes in memory, kept on disk
 * between runs so that the default command does not bake the same volume
 * again.
 *
 * A file per volume in $XDG_CACHE_HOME/cloudscape (else
 * $HOME/.cache/cloudscape), named by a hash of what makes the volume (the
 * recipe, its seed, the size, the program's version and the file format)
 * and holding that description again, so a hash collision or a file of
 * another version is baked anew, never used.  Written to a temporary and
 * renamed: two processes baking the same volume at once each write a
 * whole file and the last rename wins; a reader sees a whole file or
 * none.  CLOUDSCAPE_NO_CACHE set to anything but "" or "0" turns it off. */
#ifndef CS_NOISE_CACHE_H
#define CS_NOISE_CACHE_H

#include "noise/volume.h"

/* Fills v (allocated by cs_volume_new with its recipe set) from the cache,
 * or bakes it (cs_volume_bake with nthreads) and stores it there.  The
 * cache is a help, never a failure: when it cannot be read or written the
 * volume is baked and *hit is 0.  *hit is 1 when the volume came from the
 * cache.  Returns what cs_volume_bake returns. */
int cs_noise_cache_bake(struct cs_volume *v, int nthreads, int *hit);

/* The cache directory (as above), or "" when the cache is off or there is
 * no home.  Returns the length. */
int cs_noise_cache_dir(char *buf, size_t size);

#endif
