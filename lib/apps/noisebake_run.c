#include "apps/noisebake_run.h"

#include "core/err.h"
#include "io/image.h"
#include "core/fileio.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

void cs_noisebake_defaults(struct cs_noisebake_opts *o)
{
	memset(o, 0, sizeof *o);
	o->size = 128;
	o->depth = 0; /* = size */
	cs_noise_recipe_default(&o->recipe);
	strcpy(o->channels, "RGBA");
}

int cs_volume_contact_sheet(const struct cs_volume *v, const int *slices,
			    int nslices, const char *channels, uint8_t **pixels,
			    int *width, int *height)
{
	enum { GAP = 2 };
	int nch = (int)strlen(channels);
	if (nslices < 1 || nch < 1 || nch > 4)
		return cs_error(CS_EINVAL, "preview needs at least one slice and one channel");
	int chan[4];
	for (int r = 0; r < nch; r++) {
		const char *p = strchr("RGBA", channels[r]);
		if (p == NULL || channels[r] == '\0')
			return cs_error(CS_EINVAL, "preview channel '%c' is not one of R, G, B, A",
					channels[r]);
		chan[r] = (int)(p - "RGBA");
	}
	for (int i = 0; i < nslices; i++)
		if (slices[i] < 0 || slices[i] >= v->nz)
			return cs_error(CS_EINVAL, "preview slice %d is outside 0..%d",
					slices[i], v->nz - 1);
	int w = nslices * v->nx + (nslices - 1) * GAP;
	int h = nch * v->ny + (nch - 1) * GAP;
	uint8_t *pix = malloc((size_t)w * (size_t)h);
	if (pix == NULL)
		return cs_error(CS_ENOMEM, "out of memory for the preview");
	memset(pix, 255, (size_t)w * (size_t)h);
	for (int r = 0; r < nch; r++)
		for (int s = 0; s < nslices; s++)
			for (int y = 0; y < v->ny; y++)
				for (int x = 0; x < v->nx; x++) {
					float val = v->data[(((size_t)slices[s] * v->ny + y) * v->nx + x) * 4 + chan[r]];
					val = val < 0.0f ? 0.0f : val > 1.0f ? 1.0f : val;
					size_t at = (size_t)(r * (v->ny + GAP) + y) * w +
						    (size_t)(s * (v->nx + GAP) + x);
					pix[at] = (uint8_t)lrintf(val * 255.0f);
				}
	*pixels = pix;
	*width = w;
	*height = h;
	return CS_OK;
}

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

void cs_volume_channel_stats(const struct cs_volume *v, int c, double *lo,
			     double *hi, double *mean)
{
	size_t n = (size_t)v->nx * v->ny * v->nz;
	double l = INFINITY, h = -INFINITY, sum = 0.0;
	for (size_t i = 0; i < n; i++) {
		double x = v->data[i * 4 + c];
		l = x < l ? x : l;
		h = x > h ? x : h;
		sum += x;
	}
	*lo = l;
	*hi = h;
	*mean = sum / (double)n;
}

int cs_noisebake_run(const struct cs_noisebake_opts *o, struct cs_noisebake_result *r)
{
	memset(r, 0, sizeof *r);
	if (o->output == NULL && o->preview == NULL)
		return cs_error(CS_EINVAL, "nothing to write: give an output file or a preview");
	if (o->output && o->preview && strcmp(o->output, "-") == 0 &&
	    strcmp(o->preview, "-") == 0)
		return cs_error(CS_EINVAL, "the volume and the preview cannot both go to standard output");
	int depth = o->depth > 0 ? o->depth : o->size;
	int rc = cs_noise_recipe_check(&o->recipe);
	if (rc != CS_OK)
		return rc;

	int slices[CS_PREVIEW_MAX_SLICES];
	int nslices = o->nslices;
	if (nslices > 0) {
		memcpy(slices, o->slices, sizeof(int) * (size_t)nslices);
	} else {
		nslices = depth < 4 ? depth : 4;
		for (int i = 0; i < nslices; i++)
			slices[i] = i * depth / nslices;
	}
	for (int i = 0; i < nslices; i++)
		if (slices[i] < 0 || slices[i] >= depth)
			return cs_error(CS_EINVAL, "preview slice %d is outside 0..%d",
					slices[i], depth - 1);

	size_t nch = strlen(o->channels);
	if (nch < 1 || nch > 4 || strspn(o->channels, "RGBA") != nch)
		return cs_error(CS_EINVAL, "preview channels '%s' must be letters of RGBA",
				o->channels);

	const char *paths[2];
	int npaths = 0, flags = o->no_clobber ? CS_OUT_NO_CLOBBER : 0;
	if (o->output)
		paths[npaths++] = o->output;
	if (o->preview)
		paths[npaths++] = o->preview;
	if ((rc = cs_outset_check(paths, npaths, flags)) != CS_OK)
		return rc;

	struct cs_volume v;
	rc = cs_volume_new(&v, o->size, depth);
	if (rc != CS_OK)
		return rc;
	v.recipe = o->recipe;
	double t0 = now_s();
	rc = cs_volume_bake(&v, o->threads, o->progress, o->progress_user);
	r->bake_seconds = now_s() - t0;
	r->nx = v.nx, r->ny = v.ny, r->nz = v.nz;
	struct cs_outset set;
	struct cs_outfile *of;
	cs_outset_init(&set, flags);
	if (rc == CS_OK && o->output && (rc = cs_outset_open(&set, o->output, &of)) == CS_OK)
		rc = cs_volume_write_exr_to(&v, of, strcmp(o->output, "-") == 0 ? "standard output"
										 : o->output,
					    o->use_float, o->threads);
	if (rc == CS_OK && o->preview) {
		uint8_t *pix = NULL;
		int w = 0, h = 0;
		rc = cs_volume_contact_sheet(&v, slices, nslices, o->channels,
					     &pix, &w, &h);
		if (rc == CS_OK)
			rc = cs_outset_open(&set, o->preview, &of);
		if (rc == CS_OK)
			rc = cs_png_write_to(of, strcmp(o->preview, "-") == 0 ? "standard output"
									      : o->preview,
					     w, h, 1, pix);
		free(pix);
	}
	if (rc == CS_OK)
		rc = cs_outset_commit(&set);
	cs_outset_abort(&set);
	cs_volume_free(&v);
	return rc;
}
