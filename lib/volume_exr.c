/* OpenEXR reading and writing of the noise volume, through the OpenEXR C API
 * (OpenEXRCore).  All I/O goes through our own callbacks: writes into a
 * cs_outfile temporary, reads from a memory buffer, so a truncated file is
 * an ordinary short read and the core never prints. */
#include "volume.h"

#include "err.h"
#include "fileio.h"
#include "half.h"

#include <openexr.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define MAX_FILE_BYTES ((size_t)1 << 33) /* 8 GiB: larger is not a volume */

/* The core reports errors through this callback; we keep the last message
 * of this thread to attach to our own. */
static _Thread_local char exr_msg[512];

static void on_exr_error(exr_const_context_t ctxt, exr_result_t code,
			 const char *msg)
{
	(void)ctxt;
	snprintf(exr_msg, sizeof exr_msg, "%s (%s)", msg ? msg : "",
		 exr_get_default_error_message(code));
}

static int64_t write_cb(exr_const_context_t ctxt, void *user, const void *buf,
			uint64_t sz, uint64_t off, exr_stream_error_func_ptr_t err)
{
	struct cs_outfile *of = user;
	const char *p = buf;
	uint64_t left = sz;
	while (left > 0) {
		ssize_t w = pwrite(of->fd, p, left, (off_t)off);
		if (w < 0 && errno == EINTR)
			continue;
		if (w <= 0) {
			err(ctxt, EXR_ERR_WRITE_IO, "write failed: %s",
			    strerror(errno));
			return -1;
		}
		p += w;
		off += (uint64_t)w;
		left -= (uint64_t)w;
	}
	return (int64_t)sz;
}

struct mem_src {
	const unsigned char *data;
	size_t len;
};

static int64_t read_cb(exr_const_context_t ctxt, void *user, void *buf,
		       uint64_t sz, uint64_t off, exr_stream_error_func_ptr_t err)
{
	(void)ctxt;
	(void)err;
	const struct mem_src *m = user;
	if (off >= m->len)
		return 0;
	uint64_t n = m->len - off < sz ? m->len - off : sz;
	memcpy(buf, m->data + off, n);
	return (int64_t)n;
}

static int64_t size_cb(exr_const_context_t ctxt, void *user)
{
	(void)ctxt;
	return (int64_t)((const struct mem_src *)user)->len;
}

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

#define EXR_TRY(call, what)                                                   \
	do {                                                                  \
		exr_result_t r_ = (call);                                     \
		if (r_ != EXR_ERR_SUCCESS) {                                  \
			rc = cs_error(CS_EIO, "%s: %s: %s", name, what,        \
				      exr_msg[0] ? exr_msg                    \
						 : exr_get_default_error_message(r_)); \
			goto done;                                            \
		}                                                             \
	} while (0)

int cs_volume_write_exr(const struct cs_volume *v, const char *path,
			int use_float)
{
	const char *name = strcmp(path, "-") == 0 ? "standard output" : path;
	int rc = CS_OK;
	exr_context_t f = NULL;
	exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
	int enc_live = 0;
	uint16_t *halves = NULL;
	struct cs_outfile of;

	exr_msg[0] = '\0';
	if (v->data == NULL || v->nx != v->ny)
		return cs_error(CS_EINVAL, "volume is empty or not square");
	if ((long)v->nx * v->nz > 0x7fffffffL)
		return cs_error(CS_EINVAL, "volume too large for one image");
	rc = cs_outfile_open(&of, path);
	if (rc != CS_OK)
		return rc;

	exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
	init.error_handler_fn = on_exr_error;
	init.user_data = &of;
	init.write_fn = write_cb;
	EXR_TRY(exr_start_write(&f, name, EXR_WRITE_FILE_DIRECTLY, &init),
		"cannot start writing");
	int part = 0;
	EXR_TRY(exr_add_part(f, "noise", EXR_STORAGE_SCANLINE, &part), "add part");
	int width = v->nx, height = v->nx * v->nz;
	EXR_TRY(exr_initialize_required_attr_simple(f, part, width, height,
						    EXR_COMPRESSION_ZIP),
		"header");
	exr_pixel_type_t ptype = use_float ? EXR_PIXEL_FLOAT : EXR_PIXEL_HALF;
	static const char *const names[4] = {"R", "G", "B", "A"};
	for (int c = 0; c < 4; c++)
		EXR_TRY(exr_add_channel(f, part, names[c], ptype,
					EXR_PERCEPTUALLY_LINEAR, 1, 1),
			"add channel");

	char buf[512];
	exr_attr_v3i_t size = {.x = v->nx, .y = v->ny, .z = v->nz};
	EXR_TRY(exr_attr_set_int(f, part, "cloudscapeFormat", CS_VOLUME_FORMAT),
		"attribute");
	EXR_TRY(exr_attr_set_v3i(f, part, "cloudscapeVolumeSize", &size),
		"attribute");
	EXR_TRY(exr_attr_set_int(f, part, "cloudscapeSeed",
				 (int32_t)v->recipe.seed),
		"attribute");
	cs_noise_recipe_format(&v->recipe, buf, sizeof buf);
	EXR_TRY(exr_attr_set_string(f, part, "cloudscapeRecipe", buf),
		"attribute");
	format_periods(v, buf, sizeof buf);
	EXR_TRY(exr_attr_set_string(f, part, "cloudscapePeriod", buf),
		"attribute");
	EXR_TRY(exr_write_header(f), "cannot write header");

	int32_t spc = 0;
	EXR_TRY(exr_get_scanlines_per_chunk(f, part, &spc), "chunk size");
	if (!use_float) {
		halves = malloc((size_t)spc * (size_t)width * 4u * sizeof *halves);
		if (halves == NULL) {
			rc = cs_error(CS_ENOMEM, "out of memory");
			goto done;
		}
	}
	for (int y = 0; y < height; y += spc) {
		exr_chunk_info_t ci;
		EXR_TRY(exr_write_scanline_chunk_info(f, part, y, &ci), "chunk");
		if (!enc_live)
			EXR_TRY(exr_encoding_initialize(f, part, &ci, &enc), "encoder");
		else
			EXR_TRY(exr_encoding_update(f, part, &ci, &enc), "encoder");
		const float *rows = v->data + (size_t)ci.start_y * width * 4;
		if (!use_float)
			for (size_t i = 0; i < (size_t)ci.height * width * 4; i++)
				halves[i] = cs_float_to_half(rows[i]);
		for (int k = 0; k < enc.channel_count; k++) {
			exr_coding_channel_info_t *ch = &enc.channels[k];
			int c = chan_index(ch->channel_name);
			if (use_float) {
				ch->encode_from_ptr = (const uint8_t *)(rows + c);
				ch->user_bytes_per_element = 4;
				ch->user_data_type = EXR_PIXEL_FLOAT;
			} else {
				ch->encode_from_ptr = (const uint8_t *)(halves + c);
				ch->user_bytes_per_element = 2;
				ch->user_data_type = EXR_PIXEL_HALF;
			}
			ch->user_pixel_stride = 4 * ch->user_bytes_per_element;
			ch->user_line_stride = width * ch->user_pixel_stride;
		}
		if (!enc_live) {
			EXR_TRY(exr_encoding_choose_default_routines(f, part, &enc),
				"encoder");
			enc_live = 1;
		}
		EXR_TRY(exr_encoding_run(f, part, &enc), "cannot write pixels");
	}
	if (enc_live) {
		exr_encoding_destroy(f, &enc);
		enc_live = 0;
	}
	EXR_TRY(exr_finish(&f), "cannot finish file");
	rc = cs_outfile_commit(&of);
	free(halves);
	return rc;
done:
	if (enc_live)
		exr_encoding_destroy(f, &enc);
	if (f)
		exr_finish(&f);
	cs_outfile_abort(&of);
	free(halves);
	return rc;
}

#undef EXR_TRY
#define EXR_TRY(call, what)                                                   \
	do {                                                                  \
		exr_result_t r_ = (call);                                     \
		if (r_ != EXR_ERR_SUCCESS) {                                  \
			rc = cs_error(CS_EDATA, "%s: %s: %s", name, what,      \
				      exr_msg[0] ? exr_msg                    \
						 : exr_get_default_error_message(r_)); \
			goto done;                                            \
		}                                                             \
	} while (0)

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

int cs_volume_read_exr_mem(const void *data, size_t len, const char *name,
			   struct cs_volume *v)
{
	int rc = CS_OK;
	exr_context_t f = NULL;
	exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
	int dec_live = 0;
	uint16_t *halves = NULL;
	struct mem_src src = {data, len};

	memset(v, 0, sizeof *v);
	exr_msg[0] = '\0';
	exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
	init.error_handler_fn = on_exr_error;
	init.user_data = &src;
	init.read_fn = read_cb;
	init.size_fn = size_cb;
	init.flags = EXR_CONTEXT_FLAG_SILENT_HEADER_PARSE;
	EXR_TRY(exr_start_read(&f, name, &init), "not a readable OpenEXR file");

	int parts = 0;
	EXR_TRY(exr_get_count(f, &parts), "part count");
	if (parts != 1)
		BAD("expected a single-part image, found %d parts", parts);
	exr_storage_t st;
	EXR_TRY(exr_get_storage(f, 0, &st), "storage");
	if (st != EXR_STORAGE_SCANLINE)
		BAD("expected a scanline image (tiled and deep are not noise volumes)");

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
	if (width != size.x || height != (long)size.x * size.z)
		BAD("image is %ldx%ld but cloudscapeVolumeSize %dx%dx%d needs %dx%ld",
		    width, height, size.x, size.y, size.z, size.x,
		    (long)size.x * size.z);
	int32_t seed = -1;
	if (exr_attr_get_int(f, 0, "cloudscapeSeed", &seed) != EXR_ERR_SUCCESS)
		BAD("missing attribute cloudscapeSeed");
	if (seed < 0)
		BAD("cloudscapeSeed %d is negative", seed);
	char recipe[512], period[512], want[512];
	if (get_string_attr(f, 0, "cloudscapeRecipe", recipe, sizeof recipe) < 0)
		BAD("missing attribute cloudscapeRecipe");
	if (get_string_attr(f, 0, "cloudscapePeriod", period, sizeof period) < 0)
		BAD("missing attribute cloudscapePeriod");

	rc = cs_volume_new(v, size.x, size.z);
	if (rc != CS_OK)
		goto done;
	v->recipe.seed = (uint32_t)seed;
	if (cs_noise_recipe_parse(recipe, &v->recipe) != CS_OK) {
		rc = cs_error(CS_EDATA, "%s: %s", name, cs_errmsg());
		goto done;
	}
	format_periods(v, want, sizeof want);
	if (strcmp(period, want) != 0)
		BAD("cloudscapePeriod \"%.150s\" disagrees with the recipe and size (\"%.150s\")",
		    period, want);

	int32_t spc = 0;
	EXR_TRY(exr_get_scanlines_per_chunk(f, 0, &spc), "chunk size");
	if (spc < 1 || spc > 256)
		BAD("unexpected %d scanlines per chunk", spc);
	if (ptype == EXR_PIXEL_HALF) {
		halves = malloc((size_t)spc * (size_t)width * 4u * sizeof *halves);
		if (halves == NULL) {
			rc = cs_error(CS_ENOMEM, "out of memory");
			goto done;
		}
	}
	for (long y = 0; y < height; y += spc) {
		exr_chunk_info_t ci;
		EXR_TRY(exr_read_scanline_chunk_info(f, 0, (int)y, &ci),
			"truncated or corrupt pixel data");
		if (ci.start_y != y || ci.height < 1 || ci.height > spc ||
		    y + ci.height > height || ci.width != width)
			BAD("inconsistent chunk at scanline %ld", y);
		if (!dec_live)
			EXR_TRY(exr_decoding_initialize(f, 0, &ci, &dec), "decoder");
		else
			EXR_TRY(exr_decoding_update(f, 0, &ci, &dec), "decoder");
		float *rows = v->data + (size_t)y * width * 4;
		for (int k = 0; k < dec.channel_count; k++) {
			exr_coding_channel_info_t *ch = &dec.channels[k];
			int c = chan_index(ch->channel_name);
			if (ptype == EXR_PIXEL_FLOAT) {
				ch->decode_to_ptr = (uint8_t *)(rows + c);
				ch->user_bytes_per_element = 4;
				ch->user_data_type = EXR_PIXEL_FLOAT;
			} else {
				ch->decode_to_ptr = (uint8_t *)(halves + c);
				ch->user_bytes_per_element = 2;
				ch->user_data_type = EXR_PIXEL_HALF;
			}
			ch->user_pixel_stride = 4 * ch->user_bytes_per_element;
			ch->user_line_stride = (int32_t)width * ch->user_pixel_stride;
		}
		if (!dec_live) {
			EXR_TRY(exr_decoding_choose_default_routines(f, 0, &dec),
				"decoder");
			dec_live = 1;
		}
		EXR_TRY(exr_decoding_run(f, 0, &dec), "truncated or corrupt pixel data");
		if (ptype == EXR_PIXEL_HALF)
			for (size_t i = 0; i < (size_t)ci.height * width * 4; i++)
				rows[i] = cs_half_to_float(halves[i]);
	}
	for (size_t i = 0; i < (size_t)width * height * 4; i++)
		if (!(v->data[i] == v->data[i] && v->data[i] - v->data[i] == 0.0f))
			BAD("non-finite value at pixel %zu", i / 4);
done:
	if (dec_live)
		exr_decoding_destroy(f, &dec);
	if (f)
		exr_finish(&f);
	free(halves);
	if (rc != CS_OK)
		cs_volume_free(v);
	return rc;
}

int cs_volume_read_exr(const char *path, struct cs_volume *v)
{
	unsigned char *data = NULL;
	size_t len = 0;
	memset(v, 0, sizeof *v);
	int rc = cs_read_all(path, MAX_FILE_BYTES, &data, &len);
	if (rc != CS_OK)
		return rc;
	rc = cs_volume_read_exr_mem(data, len,
				    strcmp(path, "-") == 0 ? "standard input" : path, v);
	free(data);
	return rc;
}
