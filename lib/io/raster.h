/* raster.h - images in the formats GDAL encodes (GeoTIFF, JPEG), written
 * through GDAL into an open output (core/fileio.h), never georeferenced. */
#ifndef CS_RASTER_H
#define CS_RASTER_H

#include <stddef.h>

struct cs_outfile;

enum cs_sample { CS_SAMPLE_U8, CS_SAMPLE_U16, CS_SAMPLE_F32 };

/* Encodes width x height pixels of nbands interleaved samples of one type
 * (rows top to bottom) with GDAL's driver ("GTiff", "JPEG") and its
 * creation options (NULL-terminated "KEY=VALUE" list, or NULL) into of.
 * Bands 1..3 are marked red, green, blue when nbands >= 3; band_names
 * (nbands names, or NULL) become the band descriptions.  The bytes depend
 * only on the pixels and the options.  name labels messages. */
int cs_raster_write_to(struct cs_outfile *of, const char *name, const char *driver,
		       int width, int height, int nbands, enum cs_sample type,
		       const void *pixels, const char *const *options,
		       const char *const *band_names);

#endif
