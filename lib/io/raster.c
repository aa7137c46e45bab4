#include "io/raster.h"

#include "core/err.h"
#include "core/fileio.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_vsi.h>
#include <gdal.h>

#include <pthread.h>
#include <stdio.h>
#include <string.h>

static pthread_once_t once = PTHREAD_ONCE_INIT;
static pthread_mutex_t encode_lock = PTHREAD_MUTEX_INITIALIZER;

static void register_drivers(void)
{
	GDALAllRegister();
}

/* GDAL's first failure message of a call, kept instead of printed. */
struct log {
	char msg[256];
};

static void CPL_STDCALL on_error(CPLErr cls, CPLErrorNum no, const char *msg)
{
	(void)no;
	struct log *l = CPLGetErrorHandlerUserData();
	if (cls >= CE_Failure && l->msg[0] == '\0')
		snprintf(l->msg, sizeof l->msg, "%s", msg ? msg : "");
}

static int encode(const char *name, const char *driver, const char *mem, int width,
		  int height, int nbands, enum cs_sample type, const void *pixels,
		  const char *const *options, const char *const *band_names, struct log *l)
{
	static const GDALDataType types[3] = {GDT_Byte, GDT_UInt16, GDT_Float32};
	static const int bytes[3] = {1, 2, 4};
	GDALDriverH out = GDALGetDriverByName(driver);
	GDALDriverH memdrv = GDALGetDriverByName("MEM");
	if (out == NULL || memdrv == NULL)
		return cs_error(CS_EIO, "%s: GDAL has no %s driver", name, driver);
	GDALDatasetH src = GDALCreate(memdrv, "", width, height, nbands, types[type], NULL);
	if (src == NULL)
		return cs_error(CS_ENOMEM, "%s: %s", name, l->msg[0] ? l->msg : "out of memory");
	int b = bytes[type];
	CPLErr e = GDALDatasetRasterIO(src, GF_Write, 0, 0, width, height, (void *)pixels,
				       width, height, types[type], nbands, NULL, b * nbands,
				       (GSpacing)b * nbands * width, b);
	for (int i = 0; i < nbands && e == CE_None; i++) {
		GDALRasterBandH band = GDALGetRasterBand(src, i + 1);
		if (nbands >= 3 && i < 3)
			GDALSetRasterColorInterpretation(band, (GDALColorInterp)(GCI_RedBand + i));
		if (band_names)
			GDALSetDescription(band, band_names[i]);
	}
	GDALDatasetH dst = NULL;
	if (e == CE_None)
		dst = GDALCreateCopy(out, mem, src, FALSE, (char **)options, NULL, NULL);
	GDALClose(src);
	if (dst)
		GDALClose(dst); /* flushes the file */
	if (dst == NULL || l->msg[0])
		return cs_error(CS_EIO, "%s: GDAL's %s driver: %s", name, driver,
				l->msg[0] ? l->msg : "cannot encode");
	return CS_OK;
}

int cs_raster_write_to(struct cs_outfile *of, const char *name, const char *driver,
		       int width, int height, int nbands, enum cs_sample type,
		       const void *pixels, const char *const *options,
		       const char *const *band_names)
{
	if (width < 1 || height < 1 || nbands < 1 || nbands > 16)
		return cs_error(CS_EINVAL, "cannot write a %dx%d image of %d bands",
				width, height, nbands);
	pthread_once(&once, register_drivers);
	struct log l = {""};
	CPLPushErrorHandlerEx(on_error, &l);
	char *pam = CPLStrdup(CPLGetThreadLocalConfigOption("GDAL_PAM_ENABLED", ""));
	CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", "NO"); /* no .aux.xml */
	char mem[96];
	snprintf(mem, sizeof mem, "/vsimem/cloudscape-raster-%p", (void *)of);
	/* one encode at a time: GDAL's drivers fill in shared state (the JPEG
	 * driver its creation options) the first time they are asked, unlocked,
	 * and a series writes frames on several threads (ThreadSanitizer) */
	pthread_mutex_lock(&encode_lock);
	int rc = encode(name, driver, mem, width, height, nbands, type, pixels, options,
			band_names, &l);
	pthread_mutex_unlock(&encode_lock);
	vsi_l_offset n = 0;
	GByte *data = rc == CS_OK ? VSIGetMemFileBuffer(mem, &n, FALSE) : NULL;
	if (rc == CS_OK && data == NULL)
		rc = cs_error(CS_EIO, "%s: GDAL's %s driver wrote nothing", name, driver);
	if (rc == CS_OK)
		rc = cs_outfile_write(of, data, (size_t)n);
	VSIUnlink(mem);
	CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", pam[0] ? pam : NULL);
	CPLFree(pam);
	CPLPopErrorHandler();
	return rc;
}
