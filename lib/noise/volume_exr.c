/* The noise volume as OpenEXR (see man 5 cloudscape-noise): written with
 * cs_exr_write(), read and validated here through the OpenEXR C API. */
#include "noise/volume.h"

#include "core/err.h"
#include "io/exr.h"
#include "core/fileio.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FILE_BYTES ((size_t)1 << 33) /* 8 GiB: larger is not a volume */

static int chan_index(const char *name)
{
	static const char *const names[4] = {"R", "G", "B", "A"};
	for (int c = 0; c < 4; c++)
		if (strcmp(name, names[c]) == 0)
			return c;
	return -1;
}

static void format_periods(const struct cs_volume *v, char *buf, size_t size)
{
	static const char names[4] = {'R', 'G', 'B', 'A'};
	size_t n = 0;
	buf[0] = '\0';
	for (int c = 0; c < 4 && n < size; c++) {
		int p[3];
		cs_noise_period(&v->recipe, c, v->nx, v->nz, p);
		n += (size_t)snprintf(buf + n, size - n, "%s%c=%dx%dx%d",
				      c ? ";" : "", names[c], p[0], p[1], p[2]);
	}
}

int cs_volume_write_exr(const struct cs_volume *v, const char *path,
			int use_float, int nthreads)
{
	struct cs_outfile of;
	int rc = cs_outfile_open(&of, path);
	if (rc != CS_OK)
		return rc;
	rc = cs_volume_write_exr_to(v, &of, strcmp(path, "-") == 0 ? "standard output" : path,
				    use_float, nthreads);
	if (rc == CS_OK)
		return cs_outfile_commit(&of);
	cs_outfile_abort(&of);
	return rc;
}

int cs_volume_write_exr_to(const struct cs_volume *v, struct cs_outfile *of,
			   const char *name, int use_float, int nthreads)
{
	if (v->data == NULL || v->nx != v->ny)
		return cs_error(CS_EINVAL, "volume is empty or not square");
	if ((long)v->nx * v->nz > 0x7fffffffL)
		return cs_error(CS_EINVAL, "volume too large for one image");
	char recipe[512], period[512];
	cs_noise_recipe_format(&v->recipe, recipe, sizeof recipe);
	format_periods(v, period, sizeof period);
	const struct cs_exr_attr attrs[] = {
		{"cloudscapeFormat", CS_EXR_INT, {CS_VOLUME_FORMAT, 0, 0}, NULL, 0},
		{"cloudscapeVolumeSize", CS_EXR_V3I, {v->nx, v->ny, v->nz}, NULL, 0},
		{"cloudscapeSeed", CS_EXR_INT, {(int)v->recipe.seed, 0, 0}, NULL, 0},
		{"cloudscapeRecipe", CS_EXR_STRING, {0, 0, 0}, recipe, 0},
		{"cloudscapePeriod", CS_EXR_STRING, {0, 0, 0}, period, 0},
	};
	struct cs_exr_channel ch[4];
	static const char *const names[4] = {"R", "G", "B", "A"};
	for (int c = 0; c < 4; c++)
		ch[c] = (struct cs_exr_channel){names[c], use_float, v->data + c, 4};
	return cs_exr_write_to(of, name, v->nx, v->nx * v->nz, ch, 4, attrs,
			       (int)(sizeof attrs / sizeof attrs[0]), nthreads);
}

#define EXR_TRY(call, what) CS_EXR_CHECK(call, CS_EDATA, name, what, done)

#define BAD(...)                                                              \
	do {                                                                  \
		char m_[600];                                                 \
		snprintf(m_, sizeof m_, __VA_ARGS__);                         \
		rc = cs_error(CS_EDATA, "%s: %s", name, m_);                  \
		goto done;                                                    \
	} while (0)

static int get_string_attr(exr_context_t f, int part, const char *attr,
			   char *out, size_t size)
{
	int32_t len = 0;
	const char *s = NULL;
	if (exr_attr_get_string(f, part, attr, &len, &s) != EXR_ERR_SUCCESS ||
	    s == NULL || len < 0 || (size_t)len >= size)
		return -1;
	memcpy(out, s, (size_t)len);
	out[len] = '\0';
	return 0;
}

/* Opens the file in src as *f; it must be a single-part scanline image. */
static int open_volume(exr_context_t *f, struct cs_exr_mem *src, const char *name)
{
	int rc = CS_OK;
	exr_context_initializer_t init;
	cs_exr_reader_init(&init, src);
	EXR_TRY(exr_start_read(f, name, &init), "not a readable OpenEXR file");

	int parts = 0;
	EXR_TRY(exr_get_count(*f, &parts), "part count");
	if (parts != 1)
		BAD("expected a single-part image, found %d parts", parts);
	exr_storage_t st;
	EXR_TRY(exr_get_storage(*f, 0, &st), "storage");
	if (st != EXR_STORAGE_SCANLINE)
		BAD("expected a scanline image (tiled and deep are not noise volumes)");
done:
	return rc;
}

/* Checks that the channels are exactly R, G, B, A, unsubsampled, all half
 * or all float. */
static int check_rgba_channels(exr_context_t f, const char *name)
{
	int rc = CS_OK;
	const exr_attr_chlist_t *chl = NULL;
	EXR_TRY(exr_get_channels(f, 0, &chl), "channel list");
	int seen[4] = {0, 0, 0, 0};
	exr_pixel_type_t ptype = EXR_PIXEL_HALF;
	int typed = 0;
	char chnames[128] = "";
	for (int i = 0; i < chl->num_channels; i++) {
		const exr_attr_chlist_entry_t *e = &chl->entries[i];
		size_t n = strlen(chnames);
		snprintf(chnames + n, sizeof chnames - n, "%s%.20s", i ? "," : "",
			 e->name.str);
		int c = chan_index(e->name.str);
		if (c >= 0) {
			seen[c]++;
			if (e->x_sampling != 1 || e->y_sampling != 1)
				BAD("channel %s is subsampled", e->name.str);
			if (e->pixel_type != EXR_PIXEL_HALF &&
			    e->pixel_type != EXR_PIXEL_FLOAT)
				BAD("channel %s is not half or float", e->name.str);
			if (typed && e->pixel_type != ptype)
				BAD("channels R, G, B, A must share one pixel type");
			ptype = e->pixel_type;
			typed = 1;
		}
	}
	if (chl->num_channels != 4 || !seen[0] || !seen[1] || !seen[2] || !seen[3])
		BAD("expected channels A,B,G,R, found %s", chnames[0] ? chnames : "none");
done:
	return rc;
}

/* What the header of a noise volume says. */
struct vol_header {
	long width, height;         /* of the image */
	exr_attr_v3i_t size;        /* cloudscapeVolumeSize */
	int32_t seed;
	char recipe[512], period[512];
};

/* Reads the data window, cloudscapeFormat and cloudscapeVolumeSize into hd
 * and checks that they agree. */
static int read_volume_size(exr_context_t f, const char *name,
			    struct vol_header *hd)
{
	int rc = CS_OK;
	exr_attr_box2i_t dw;
	EXR_TRY(exr_get_data_window(f, 0, &dw), "data window");
	long width = (long)dw.max.x - dw.min.x + 1;
	long height = (long)dw.max.y - dw.min.y + 1;
	if (dw.min.x != 0 || dw.min.y != 0)
		BAD("data window must start at 0,0");

	int32_t fmt = 0;
	if (exr_attr_get_int(f, 0, "cloudscapeFormat", &fmt) != EXR_ERR_SUCCESS)
		BAD("missing attribute cloudscapeFormat (not a cloudscape noise volume)");
	if (fmt != CS_VOLUME_FORMAT)
		BAD("noise volume format %d is not supported (this build reads %d)",
		    fmt, CS_VOLUME_FORMAT);
	exr_attr_v3i_t size;
	if (exr_attr_get_v3i(f, 0, "cloudscapeVolumeSize", &size) != EXR_ERR_SUCCESS)
		BAD("missing attribute cloudscapeVolumeSize");
	if (size.x < 1 || size.x > CS_VOLUME_MAX_DIM || size.y != size.x ||
	    size.z < 1 || size.z > CS_VOLUME_MAX_DIM)
		BAD("cloudscapeVolumeSize %dx%dx%d is not a valid volume size",
		    size.x, size.y, size.z);
	if ((long)size.x * size.x * size.z > CS_VOLUME_MAX_READ_VOXELS)
		BAD("cloudscapeVolumeSize %dx%dx%d is more voxels than a volume may have (%ld)",
		    size.x, size.y, size.z, (long)CS_VOLUME_MAX_READ_VOXELS);
	if (width != size.x || height != (long)size.x * size.z)
		BAD("image is %ldx%ld but cloudscapeVolumeSize %dx%dx%d needs %dx%ld",
		    width, height, size.x, size.y, size.z, size.x,
		    (long)size.x * size.z);
	hd->width = width;
	hd->height = height;
	hd->size = size;
done:
	return rc;
}

/* Reads cloudscapeSeed, cloudscapeRecipe and cloudscapePeriod into hd. */
static int read_volume_recipe(exr_context_t f, const char *name,
			      struct vol_header *hd)
{
	int rc = CS_OK;
	hd->seed = -1;
	if (exr_attr_get_int(f, 0, "cloudscapeSeed", &hd->seed) != EXR_ERR_SUCCESS)
		BAD("missing attribute cloudscapeSeed");
	if (hd->seed < 0)
		BAD("cloudscapeSeed %d is negative", hd->seed);
	if (get_string_attr(f, 0, "cloudscapeRecipe", hd->recipe, sizeof hd->recipe) < 0)
		BAD("missing attribute cloudscapeRecipe");
	if (get_string_attr(f, 0, "cloudscapePeriod", hd->period, sizeof hd->period) < 0)
		BAD("missing attribute cloudscapePeriod");
done:
	return rc;
}

/* Sets v's size and recipe from the header (the recipe must give the
 * header's periods); allocates nothing: the pixels, read last, become the
 * data, once the EXR reader has checked the file can hold them. */
static int apply_volume_header(const struct vol_header *hd, const char *name,
			       struct cs_volume *v)
{
	int rc = CS_OK;
	memset(v, 0, sizeof *v);
	v->nx = v->ny = hd->size.x;
	v->nz = hd->size.z;
	cs_noise_recipe_default(&v->recipe);
	v->recipe.seed = (uint32_t)hd->seed;
	if (cs_noise_recipe_parse(hd->recipe, &v->recipe) != CS_OK)
		return cs_error(CS_EDATA, "%s: %s", name, cs_errmsg());
	char want[512];
	format_periods(v, want, sizeof want);
	if (strcmp(hd->period, want) != 0)
		BAD("cloudscapePeriod \"%.150s\" disagrees with the recipe and size (\"%.150s\")",
		    hd->period, want);
done:
	return rc;
}

/* Reads the pixels, all four channels in one pass, as floats, into v's
 * data; count floats, every one finite and at most VOXEL_MAX in
 * magnitude, so that no sum of eight of them weighted by at most 1 (the
 * trilinear sample) overflows a float (the fuzzer found two near
 * FLT_MAX sampled to infinity). */
#define VOXEL_MAX 1e30f
static int read_volume_pixels(const void *data, size_t len, const char *name,
			      size_t count, int nthreads, struct cs_volume *v)
{
	static const char *const rgba[4] = {"R", "G", "B", "A"};
	float *px = NULL;
	int w = 0, h = 0;
	int rc = cs_exr_read_channels_threads(data, len, name, rgba, 4, nthreads, &w, &h, &px);
	if (rc != CS_OK)
		return rc;
	v->data = px;
	if ((size_t)w * (size_t)h * 4 != count)
		BAD("%dx%d pixels where the header's volume needs %zu", w, h, count / 4);
	for (size_t i = 0; i < count; i++)
		if (!(v->data[i] == v->data[i] && v->data[i] - v->data[i] == 0.0f))
			BAD("non-finite value at pixel %zu", i / 4);
		else if (!(v->data[i] <= VOXEL_MAX && v->data[i] >= -VOXEL_MAX))
			BAD("value %g at pixel %zu beyond +-1e30", (double)v->data[i], i / 4);
done:
	return rc;
}

/* cs_volume_read_exr_mem, its pixels decoded on nthreads threads. */
static int read_exr_mem(const void *data, size_t len, const char *name, int nthreads,
			struct cs_volume *v)
{
	exr_context_t f = NULL;
	struct cs_exr_mem src = {data, len};
	struct vol_header hd;

	memset(v, 0, sizeof *v);
	int rc = open_volume(&f, &src, name);
	if (rc == CS_OK)
		rc = check_rgba_channels(f, name);
	if (rc == CS_OK)
		rc = read_volume_size(f, name, &hd);
	if (rc == CS_OK)
		rc = read_volume_recipe(f, name, &hd);
	if (rc == CS_OK)
		rc = apply_volume_header(&hd, name, v);
	if (rc == CS_OK)
		rc = read_volume_pixels(data, len, name,
					(size_t)hd.width * hd.height * 4, nthreads, v);
	if (f)
		exr_finish(&f);
	if (rc != CS_OK)
		cs_volume_free(v);
	return rc;
}

int cs_volume_read_exr_mem(const void *data, size_t len, const char *name,
			   struct cs_volume *v)
{
	return read_exr_mem(data, len, name, 1, v);
}

int cs_volume_read_exr(const char *path, struct cs_volume *v, int nthreads)
{
	unsigned char *data = NULL;
	size_t len = 0;
	memset(v, 0, sizeof *v);
	int rc = cs_read_all(path, MAX_FILE_BYTES, &data, &len);
	if (rc != CS_OK)
		return rc;
	rc = read_exr_mem(data, len, strcmp(path, "-") == 0 ? "standard input" : path,
			  nthreads, v);
	free(data);
	return rc;
}
