/* fuzz_dem - terrainprep's DEM path through GDAL on small rasters
 * (terrain/reproject.h): open, choose the CRSs, warp to a small metric
 * grid, georeference.  The first byte picks the file name the rest is
 * opened under (GDAL's SRTM driver takes its georeferencing from the
 * name); only the drivers of the DEM formats terrainprep(1) documents,
 * and the in-memory and virtual ones the warp needs (MEM, VRT), stay
 * registered. */
#include "terrain/reproject.h"

#include <gdal.h>
#include <cpl_conv.h>
#include <cpl_vsi.h>

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const char *const names[] = {
	"/vsimem/fuzz/N43W080.hgt", "/vsimem/fuzz/dem.asc", "/vsimem/fuzz/dem.dt0",
	"/vsimem/fuzz/dem.tif", "/vsimem/fuzz/dem.xyz",
};
static const char *const keep[] = {"GTiff", "AAIGrid", "DTED", "SRTMHGT", "XYZ", "MEM", "VRT"};

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	(void)argc;
	(void)argv;
	/* let the library register GDAL's drivers (once), then drop the rest */
	const char *none[] = {"/vsimem/fuzz/none.tif"};
	struct cs_reproject_opts o = {.inputs = none, .ninputs = 1, .stdin_name = "stdin"};
	struct cs_reproject *rp = NULL;
	(void)cs_reproject_open(&o, &rp);
	cs_reproject_free(rp);
	for (int i = GDALGetDriverCount() - 1; i >= 0; i--) {
		GDALDriverH d = GDALGetDriver(i);
		const char *n = GDALGetDriverShortName(d);
		int k = 0;
		while (k < (int)(sizeof keep / sizeof keep[0]) && strcmp(n, keep[k]) != 0)
			k++;
		if (k == (int)(sizeof keep / sizeof keep[0]))
			GDALDeregisterDriver(d), GDALDestroyDriver(d);
	}
	CPLSetConfigOption("GDAL_PAM_ENABLED", "NO");
	return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 1 || size > 200000)
		return 0;
	const char *path = names[data[0] % (sizeof names / sizeof names[0])];
	VSILFILE *f = VSIFileFromMemBuffer(path, (GByte *)data + 1, size - 1, FALSE);
	if (f == NULL)
		return 0;
	VSIFCloseL(f);
	/* a header that claims a raster of more than 2^22 samples (a 200 kB
	 * file can: one compressed strip, a sparse tile index) asks the warp
	 * for work in proportion, a legitimate cost and not a parser's bug:
	 * left out, as inputs over 200 kB are */
	GDALDatasetH ds = GDALOpenEx(path, GDAL_OF_RASTER | GDAL_OF_READONLY, NULL, NULL, NULL);
	double samples = ds ? (double)GDALGetRasterXSize(ds) * GDALGetRasterYSize(ds) : 0.0;
	if (ds)
		GDALClose(ds);
	if (samples > 4194304.0) {
		VSIUnlink(path);
		return 0;
	}
	const char *in[] = {path};
	struct cs_reproject_opts o = {.inputs = in, .ninputs = 1, .stdin_name = "stdin",
				      .size_long = 24};
	struct cs_reproject *rp = NULL;
	struct cs_terrain t;
	memset(&t, 0, sizeof t);
	char resampling[32];
	if (cs_reproject_open(&o, &rp) == 0 &&
	    cs_reproject_warp(rp, &t, resampling, sizeof resampling) == 0) {
		if (t.width < 1 || t.height < 1 || t.width > 24 || t.height > 24)
			abort(); /* the grid asked for */
		(void)cs_reproject_georeference(rp, &t);
	}
	cs_reproject_free(rp);
	cs_terrain_free(&t);
	VSIUnlink(path);
	return 0;
}
