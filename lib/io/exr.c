#include "io/exr.h"

#include "core/err.h"
#include "core/fileio.h"
#include "core/half.h"
#include "core/pool.h"

#include <errno.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/stat.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static _Thread_local char exr_msg[512];

static void on_exr_error(exr_const_context_t ctxt, exr_result_t code,
			 const char *msg)
{
	(void)ctxt;
	snprintf(exr_msg, sizeof exr_msg, "%s (%s)", msg ? msg : "",
		 exr_get_default_error_message(code));
}

const char *cs_exr_message(exr_result_t code)
{
	return exr_msg[0] ? exr_msg : exr_get_default_error_message(code);
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
			err(ctxt, EXR_ERR_WRITE_IO, "write failed: %s", strerror(errno));
			return -1;
		}
		p += w;
		off += (uint64_t)w;
		left -= (uint64_t)w;
	}
	return (int64_t)sz;
}

static int64_t read_cb(exr_const_context_t ctxt, void *user, void *buf,
		       uint64_t sz, uint64_t off, exr_stream_error_func_ptr_t err)
{
	(void)ctxt;
	(void)err;
	const struct cs_exr_mem *m = user;
	if (off >= m->len)
		return 0;
	uint64_t n = m->len - off < sz ? m->len - off : sz;
	memcpy(buf, m->data + off, n);
	return (int64_t)n;
}

static int64_t size_cb(exr_const_context_t ctxt, void *user)
{
	(void)ctxt;
	return (int64_t)((const struct cs_exr_mem *)user)->len;
}

void cs_exr_reader_init(exr_context_initializer_t *init, struct cs_exr_mem *src)
{
	exr_context_initializer_t def = EXR_DEFAULT_CONTEXT_INITIALIZER;
	*init = def;
	init->error_handler_fn = on_exr_error;
	init->user_data = src;
	init->read_fn = read_cb;
	init->size_fn = size_cb;
	init->flags = EXR_CONTEXT_FLAG_SILENT_HEADER_PARSE;
	exr_msg[0] = '\0';
}

#define TRY(call, what) CS_EXR_CHECK(call, CS_EIO, name, what, fail)

static int set_attr(exr_context_t f, const struct cs_exr_attr *a)
{
	switch (a->type) {
	case CS_EXR_INT:
		return exr_attr_set_int(f, 0, a->name, a->i[0]);
	case CS_EXR_STRING:
		return exr_attr_set_string(f, 0, a->name, a->s);
	case CS_EXR_DOUBLE:
		return exr_attr_set_double(f, 0, a->name, a->d);
	case CS_EXR_FLOAT:
		return exr_attr_set_float(f, 0, a->name, (float)a->d);
	case CS_EXR_V3I: {
		exr_attr_v3i_t v = {.x = a->i[0], .y = a->i[1], .z = a->i[2]};
		return exr_attr_set_v3i(f, 0, a->name, &v);
	}
	}
	return EXR_ERR_INVALID_ARGUMENT;
}

/* Why a chunk could not be coded, kept by the worker that tried (its
 * messages are its thread's own) for the calling thread to report. */
struct chunk_error {
	int rc;
	char msg[512];
};

static void chunk_failed(struct chunk_error *e, int rc)
{
	e->rc = rc;
	snprintf(e->msg, sizeof e->msg, "%s", cs_errmsg());
}

/* The workers for nchunks chunks on nthreads threads (<= 0: one per
 * processor). */
static int chunk_workers(int nthreads, long nchunks)
{
	long n = nthreads > 0 ? nthreads : cs_pool_cpus();
	n = n < nchunks ? n : nchunks;
	return (int)(n < CS_POOL_MAX_THREADS ? n : CS_POOL_MAX_THREADS);
}

/* One chunk of an image being written: its bytes once compressed. */
struct enc_chunk {
	void *data;
	size_t size;
	struct chunk_error err;
};

/* A worker's encoder and the planar block it converts a chunk into. */
struct enc_worker {
	exr_encode_pipeline_t enc;
	int live, routines;
	void *scratch;
};

/* The chunks of one image, compressed in parallel (encode_task) and then
 * written in order by the calling thread: the file is the same bytes
 * whatever the number of threads. */
struct enc_job {
	exr_context_t f;
	const char *name;
	int width, height, spc, nch;
	const struct cs_exr_channel *ch;
	size_t block; /* floats: one channel, one chunk */
	struct enc_worker *wk;
	struct enc_chunk *out;
	int first; /* the batch's first chunk: task 0 is chunk first */
};

/* Converts and compresses chunk task (scanlines task * spc on) with the
 * worker's encoder, leaving the bytes to write in out[task]: the core's
 * own pipeline without its last two steps (the wait for the chunk's turn
 * and the write).  Compression reads the context only. */
static void encode_task(void *user, int task, int worker)
{
	struct enc_job *j = user;
	struct enc_worker *w = &j->wk[worker];
	task += j->first;
	struct enc_chunk *o = &j->out[task];
	exr_context_t f = j->f;
	const char *name = j->name;
	int width = j->width, rc = CS_OK;
	exr_msg[0] = '\0';
	exr_chunk_info_t ci;
	TRY(exr_write_scanline_chunk_info(f, 0, task * j->spc, &ci), "chunk");
	if (!w->live) {
		TRY(exr_encoding_initialize(f, 0, &ci, &w->enc), "encoder");
		w->live = 1; /* (destroyed with the context, whatever follows) */
	} else {
		TRY(exr_encoding_update(f, 0, &ci, &w->enc), "encoder");
	}
	size_t n = (size_t)ci.height * (size_t)width;
	for (int k = 0; k < w->enc.channel_count; k++) {
		exr_coding_channel_info_t *e = &w->enc.channels[k];
		int c = 0;
		while (c < j->nch && strcmp(j->ch[c].name, e->channel_name) != 0)
			c++;
		const struct cs_exr_channel *src_ch = &j->ch[c];
		const float *src = src_ch->data + (size_t)ci.start_y * width * src_ch->stride;
		unsigned char *dst = (unsigned char *)w->scratch + (size_t)c * j->block * sizeof(float);
		if (src_ch->is_float) {
			float *fd = (float *)dst;
			for (size_t i = 0; i < n; i++)
				fd[i] = src[i * src_ch->stride];
			e->user_bytes_per_element = 4;
			e->user_data_type = EXR_PIXEL_FLOAT;
		} else {
			uint16_t *hd = (uint16_t *)dst;
			for (size_t i = 0; i < n; i++)
				hd[i] = cs_float_to_half_sat(src[i * src_ch->stride]);
			e->user_bytes_per_element = 2;
			e->user_data_type = EXR_PIXEL_HALF;
		}
		e->encode_from_ptr = dst;
		e->user_pixel_stride = e->user_bytes_per_element;
		e->user_line_stride = width * e->user_bytes_per_element;
	}
	if (!w->routines) {
		TRY(exr_encoding_choose_default_routines(f, 0, &w->enc), "encoder");
		w->routines = 1;
	}
	w->enc.yield_until_ready_fn = NULL;
	w->enc.write_fn = NULL;
	TRY(exr_encoding_run(f, 0, &w->enc), "cannot compress pixels");
	o->size = w->enc.compressed_bytes;
	o->data = malloc(o->size ? o->size : 1);
	if (o->data == NULL) {
		rc = cs_error(CS_ENOMEM, "out of memory");
		goto fail;
	}
	memcpy(o->data, w->enc.compressed_buffer, o->size);
	return;
fail:
	chunk_failed(&o->err, rc);
}

/* Frees the workers' encoders and blocks and the compressed chunks (the
 * encoders with the context, before it is finished). */
static void free_workers(struct enc_job *j, exr_context_t f, int nworkers)
{
	for (int k = 0; j->wk != NULL && k < nworkers; k++) {
		if (j->wk[k].live)
			exr_encoding_destroy(f, &j->wk[k].enc);
		free(j->wk[k].scratch);
	}
	free(j->wk);
	j->wk = NULL;
}

/* Writes the image once, with the given compression, into the (empty)
 * temporary of, its chunks compressed on nthreads threads. */
static int write_once(struct cs_outfile *of, const char *name, int width,
		      int height, const struct cs_exr_channel *ch, int nch,
		      const struct cs_exr_attr *attrs, int nattrs,
		      exr_compression_t compression, int nthreads)
{
	int rc = CS_OK;
	exr_context_t f = NULL;
	struct enc_job job = {0};
	int nchunks = 0, nworkers = 0;

	exr_msg[0] = '\0';
	exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
	init.error_handler_fn = on_exr_error;
	init.user_data = of;
	init.write_fn = write_cb;
	TRY(exr_start_write(&f, name, EXR_WRITE_FILE_DIRECTLY, &init), "cannot start writing");
	int part = 0;
	TRY(exr_add_part(f, "image", EXR_STORAGE_SCANLINE, &part), "add part");
	TRY(exr_initialize_required_attr_simple(f, part, width, height, compression),
	    "header");
	for (int c = 0; c < nch; c++)
		TRY(exr_add_channel(f, part, ch[c].name,
				    ch[c].is_float ? EXR_PIXEL_FLOAT : EXR_PIXEL_HALF,
				    EXR_PERCEPTUALLY_LINEAR, 1, 1),
		    "add channel");
	for (int a = 0; a < nattrs; a++)
		TRY(set_attr(f, &attrs[a]), "attribute");
	TRY(exr_write_header(f), "cannot write header");

	int32_t spc = 0;
	TRY(exr_get_scanlines_per_chunk(f, part, &spc), "chunk size");
	nchunks = (height + spc - 1) / spc;
	nworkers = chunk_workers(nthreads, nchunks);
	job = (struct enc_job){f, name, width, height, spc, nch, ch, (size_t)spc * (size_t)width,
			       calloc((size_t)nworkers, sizeof *job.wk),
			       calloc((size_t)nchunks, sizeof *job.out), 0};
	if (job.wk == NULL || job.out == NULL) {
		rc = cs_error(CS_ENOMEM, "out of memory");
		goto fail;
	}
	for (int k = 0; k < nworkers; k++) {
		job.wk[k].scratch = malloc(job.block * (size_t)nch * sizeof(float));
		if (job.wk[k].scratch == NULL) {
			rc = cs_error(CS_ENOMEM, "out of memory");
			goto fail;
		}
	}
	/* in batches of 8 chunks a worker, so that a large image is not held
	 * whole compressed; each written in order, the first chunk that failed
	 * saying why */
	for (int b = 0; rc == CS_OK && b < nchunks; b += 8 * nworkers) {
		int end = nchunks - b < 8 * nworkers ? nchunks : b + 8 * nworkers;
		job.first = b;
		rc = cs_pool_run(end - b, nworkers, encode_task, &job, NULL, NULL, NULL);
		for (int t = b; rc == CS_OK && t < end; t++) {
			if (job.out[t].err.rc != CS_OK) {
				rc = cs_error(job.out[t].err.rc, "%s", job.out[t].err.msg);
				break;
			}
			TRY(exr_write_scanline_chunk(f, part, t * spc, job.out[t].data,
						     job.out[t].size),
			    "cannot write pixels");
			free(job.out[t].data);
			job.out[t].data = NULL;
		}
	}
	if (rc != CS_OK)
		goto fail;
	free_workers(&job, f, nworkers);
	TRY(exr_finish(&f), "cannot finish file");
fail:
	free_workers(&job, f, nworkers);
	for (int t = 0; job.out != NULL && t < nchunks; t++)
		free(job.out[t].data);
	free(job.out);
	if (f)
		exr_finish(&f);
	return rc;
}

/* Reads the temporary back and compares every channel with what was meant
 * to be written (half channels: with the rounding to half). */
static int verify(const struct cs_outfile *of, const char *name, int width,
		  int height, const struct cs_exr_channel *ch, int nch, int nthreads)
{
	struct stat st;
	if (fstat(of->fd, &st) < 0 || st.st_size <= 0)
		return cs_error(CS_EIO, "%s: cannot read back what was written", name);
	size_t len = (size_t)st.st_size;
	unsigned char *data = malloc(len);
	if (data == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	int rc = CS_OK;
	if (pread(of->fd, data, len, 0) != (ssize_t)len)
		rc = cs_error(CS_EIO, "%s: cannot read back what was written", name);
	const char *names[16];
	for (int c = 0; c < nch; c++)
		names[c] = ch[c].name;
	int w = 0, h = 0;
	float *px = NULL;
	if (rc == CS_OK)
		rc = cs_exr_read_channels_threads(data, len, name, names, nch, nthreads, &w, &h,
						  &px);
	if (rc == CS_OK && (w != width || h != height))
		rc = CS_EDATA;
	for (size_t i = 0; rc == CS_OK && i < (size_t)width * height; i++)
		for (int c = 0; c < nch && rc == CS_OK; c++) {
			float want = ch[c].data[i * ch[c].stride], got = px[i * nch + c];
			if (!ch[c].is_float)
				want = cs_half_to_float(cs_float_to_half_sat(want));
			if (memcmp(&want, &got, sizeof want) != 0 && !(want != want && got != got))
				rc = CS_EDATA;
		}
	free(px);
	free(data);
	return rc;
}

int cs_exr_write_to(struct cs_outfile *of, const char *name, int width, int height,
		    const struct cs_exr_channel *ch, int nch,
		    const struct cs_exr_attr *attrs, int nattrs, int nthreads)
{
	if (width < 1 || height < 1 || nch < 1 || nch > 16)
		return cs_error(CS_EINVAL, "cannot write a %dx%d image of %d channels",
				width, height, nch);
	/* OpenEXR 3.1's ZIP encoder can store a 16-scanline chunk that does not
	 * compress as garbage (seen with smooth float heights), so every file
	 * is read back and compared; if it is wrong, it is written again with
	 * ZIPS (one scanline a chunk), which does not have the fault. */
	static const exr_compression_t tries[2] = {EXR_COMPRESSION_ZIP, EXR_COMPRESSION_ZIPS};
	int rc = CS_OK;
	for (int k = 0; k < 2; k++) {
		if (ftruncate(of->fd, 0) < 0)
			return cs_error(CS_EIO, "%s: cannot write: %s", name, strerror(errno));
		rc = write_once(of, name, width, height, ch, nch, attrs, nattrs, tries[k],
				nthreads);
		if (rc != CS_OK)
			return rc;
		rc = verify(of, name, width, height, ch, nch, nthreads);
		if (rc == CS_OK)
			return CS_OK;
		if (rc != CS_EDATA)
			return rc;
		rc = cs_error(CS_EIO, "%s: the OpenEXR library wrote data that does not read back",
			      name);
	}
	return rc;
}

int cs_exr_write(const char *path, int width, int height,
		 const struct cs_exr_channel *ch, int nch,
		 const struct cs_exr_attr *attrs, int nattrs, int nthreads)
{
	const char *name = strcmp(path, "-") == 0 ? "standard output" : path;
	if (width < 1 || height < 1 || nch < 1 || nch > 16)
		return cs_error(CS_EINVAL, "cannot write a %dx%d image of %d channels",
				width, height, nch);
	struct cs_outfile of;
	int rc = cs_outfile_open(&of, path);
	if (rc != CS_OK)
		return rc;
	rc = cs_exr_write_to(&of, name, width, height, ch, nch, attrs, nattrs, nthreads);
	if (rc == CS_OK)
		return cs_outfile_commit(&of);
	cs_outfile_abort(&of);
	return rc;
}

#undef TRY
#define TRY(call, what) CS_EXR_CHECK(call, CS_EDATA, name, what, done)

#define MAX_READ_PIXELS ((long)1 << 28) /* 1 GiB of floats */

/* The most bytes of pixel data a file of len bytes can hold, by the best
 * ratio its compression can reach: deflate (ZIP, ZIPS) at most 1032:1
 * (RFC 1951: a 258-byte match in one ~2-bit code), PXR24 that on 24 of 32
 * bits, RLE 64:1 (a 2-byte run of at most 128 bytes), PIZ's Huffman runs
 * (255 values of 16 bits in >= 10 bits) about 410:1, B44's 3-byte flat
 * block of 32 bytes; DWA's DCT runs are not bounded as simply: 65536:1.
 * A header that claims more is hostile or corrupt, and refused before
 * anything is allocated for it. */
size_t cs_exr_max_pixel_bytes(size_t len, int compression)
{
	size_t ratio;
	switch ((exr_compression_t)compression) {
	case EXR_COMPRESSION_NONE: ratio = 1; break;
	case EXR_COMPRESSION_RLE: ratio = 64; break;
	case EXR_COMPRESSION_ZIPS:
	case EXR_COMPRESSION_ZIP: ratio = 1032; break;
	case EXR_COMPRESSION_PIZ: ratio = 512; break;
	case EXR_COMPRESSION_PXR24: ratio = 1376; break;
	case EXR_COMPRESSION_B44:
	case EXR_COMPRESSION_B44A: ratio = 11; break;
	default: ratio = 65536; break;
	}
	return len > SIZE_MAX / ratio ? SIZE_MAX : len * ratio;
}

/* A worker's decoder and the blocks it decodes a chunk into. */
struct dec_worker {
	exr_decode_pipeline_t dec;
	int live, routines;
	uint8_t *skip;      /* scratch for the channels not asked for */
	uint8_t *stage;     /* nch planar blocks, one per channel asked for */
};

/* One read of cs_exr_read_channels() in progress: the file, the result,
 * and its workers, each decoding whole chunks (the context reads only
 * from memory, from any thread). */
struct chunk_reader {
	const char *name;
	const char *const *channels;
	int nch;
	size_t len;         /* bytes of the whole file */
	exr_context_t f;
	long w, h;
	int32_t spc;        /* scanlines per chunk */
	float *px;          /* w * h * nch floats, the result */
	size_t block;       /* bytes: one channel, one chunk */
	int nthreads;       /* asked for; nworkers: used */
	int nworkers;
	struct dec_worker *wk;
	struct chunk_error *err; /* per chunk */
};

/* Opens the file in src as r->f; it must be a single-part scanline image. */
static int open_scanline(struct chunk_reader *r, struct cs_exr_mem *src)
{
	int rc = CS_OK;
	const char *name = r->name;
	exr_context_initializer_t init;
	cs_exr_reader_init(&init, src);
	TRY(exr_start_read(&r->f, name, &init), "not a readable OpenEXR file");
	int parts = 0;
	TRY(exr_get_count(r->f, &parts), "part count");
	exr_storage_t st = EXR_STORAGE_LAST_TYPE;
	if (parts == 1)
		TRY(exr_get_storage(r->f, 0, &st), "storage");
	if (parts != 1 || st != EXR_STORAGE_SCANLINE)
		rc = cs_error(CS_EDATA, "%s: expected a single-part scanline image", name);
done:
	return rc;
}

/* Checks that every channel asked for is there, unsubsampled, half or float. */
static int check_channels(const struct chunk_reader *r)
{
	int rc = CS_OK;
	const char *name = r->name;
	const exr_attr_chlist_t *chl = NULL;
	TRY(exr_get_channels(r->f, 0, &chl), "channel list");
	if (r->nch < 1 || r->nch > 16)
		return cs_error(CS_EINVAL, "%s: cannot read %d channels", name, r->nch);
	for (int c = 0; c < r->nch; c++) {
		int found = 0;
		for (int i = 0; i < chl->num_channels; i++) {
			const exr_attr_chlist_entry_t *e = &chl->entries[i];
			if (strcmp(e->name.str, r->channels[c]) != 0)
				continue;
			found = e->x_sampling == 1 && e->y_sampling == 1 &&
				(e->pixel_type == EXR_PIXEL_FLOAT || e->pixel_type == EXR_PIXEL_HALF);
			if (!found)
				return cs_error(CS_EDATA,
						"%s: channel %s is subsampled or not half/float",
						name, r->channels[c]);
		}
		if (!found)
			return cs_error(CS_EDATA, "%s: no channel %s", name, r->channels[c]);
	}
done:
	return rc;
}

/* Bytes of one pixel of the channels asked for, as stored (half 2, float 4). */
static int wanted_pixel_bytes(const struct chunk_reader *r, size_t *bytes)
{
	int rc = CS_OK;
	const char *name = r->name;
	const exr_attr_chlist_t *chl = NULL;
	TRY(exr_get_channels(r->f, 0, &chl), "channel list");
	*bytes = 0;
	for (int i = 0; i < chl->num_channels; i++)
		for (int c = 0; c < r->nch; c++)
			if (strcmp(chl->entries[i].name.str, r->channels[c]) == 0)
				*bytes += chl->entries[i].pixel_type == EXR_PIXEL_HALF ? 2 : 4;
done:
	return rc;
}

/* Reads the image size and chunk height and allocates the result and the
 * decoding blocks, once the header's size is one the file can hold. */
static int alloc_buffers(struct chunk_reader *r)
{
	int rc = CS_OK;
	const char *name = r->name;
	exr_attr_box2i_t dw;
	exr_compression_t comp = EXR_COMPRESSION_NONE;
	size_t pxbytes = 0;
	TRY(exr_get_data_window(r->f, 0, &dw), "data window");
	TRY(exr_get_compression(r->f, 0, &comp), "compression");
	long w = (long)dw.max.x - dw.min.x + 1, h = (long)dw.max.y - dw.min.y + 1;
	if (dw.min.x != 0 || dw.min.y != 0 || w < 1 || h < 1 || w * h > MAX_READ_PIXELS)
		return cs_error(CS_EDATA, "%s: unsupported data window (%d,%d)-(%d,%d)%s",
				name, dw.min.x, dw.min.y, dw.max.x, dw.max.y,
				w >= 1 && h >= 1 && w * h > MAX_READ_PIXELS ?
				" (more than 268435456 pixels)" : "");
	rc = wanted_pixel_bytes(r, &pxbytes);
	if (rc != CS_OK)
		return rc;
	size_t claim = (size_t)w * (size_t)h * pxbytes;
	size_t can = cs_exr_max_pixel_bytes(r->len, comp);
	if (claim > can)
		return cs_error(CS_EDATA, "%s: the header claims %ldx%ld pixels (%.3g MB of "
				"pixel data) but a file of %zu bytes can hold at most %.3g MB "
				"(corrupt or hostile header)", name, w, h, claim / 1e6,
				r->len, can / 1e6);
	r->w = w;
	r->h = h;
	r->px = malloc((size_t)w * (size_t)h * (size_t)r->nch * sizeof *r->px);
	if (r->px == NULL)
		return cs_error(CS_ENOMEM, "%s: out of memory for %ldx%ld pixels", name, w, h);
	TRY(exr_get_scanlines_per_chunk(r->f, 0, &r->spc), "chunk size");
	if (r->spc < 1 || r->spc > 256)
		return cs_error(CS_EDATA, "%s: unexpected %d scanlines per chunk",
				name, r->spc);
	/* a chunk never holds more rows than the image */
	r->block = (size_t)w * (size_t)(r->spc < h ? r->spc : h) * 4;
	long nchunks = (h + r->spc - 1) / r->spc;
	r->nworkers = chunk_workers(r->nthreads, nchunks);
	r->wk = calloc((size_t)r->nworkers, sizeof *r->wk);
	r->err = calloc((size_t)nchunks, sizeof *r->err);
	if (r->wk == NULL || r->err == NULL)
		return cs_error(CS_ENOMEM, "%s: out of memory for %ldx%ld pixels", name, w, h);
	for (int k = 0; k < r->nworkers; k++) {
		r->wk[k].skip = malloc(r->block);
		r->wk[k].stage = malloc(r->block * (size_t)r->nch);
		if (r->wk[k].skip == NULL || r->wk[k].stage == NULL)
			return cs_error(CS_ENOMEM, "%s: out of memory for %ldx%ld pixels",
					name, w, h);
	}
done:
	return rc;
}

/* Points each channel of the decoder at its staging block (the wanted ones)
 * or the scratch block (the others), to be decoded in its own type.  We
 * convert ourselves: OpenEXR 3.1's converting unpacker garbles interleaved
 * half-to-float output and crashes on a NULL destination. */
static void route_channels(const struct chunk_reader *r, struct dec_worker *wk)
{
	for (int k = 0; k < wk->dec.channel_count; k++) {
		exr_coding_channel_info_t *c = &wk->dec.channels[k];
		int want = 0;
		while (want < r->nch && strcmp(c->channel_name, r->channels[want]) != 0)
			want++;
		c->decode_to_ptr = want < r->nch ? wk->stage + (size_t)want * r->block
						  : wk->skip;
		c->user_bytes_per_element = c->bytes_per_element;
		c->user_data_type = c->data_type;
		c->user_pixel_stride = c->bytes_per_element;
		c->user_line_stride = (int32_t)r->w * c->bytes_per_element;
	}
}

/* Converts the staged channels of the chunk of rows rows at scanline y
 * into the interleaved floats of the result. */
static void convert_chunk(const struct chunk_reader *r, const struct dec_worker *wk, long y,
			  int32_t rows)
{
	const long w = r->w;
	const int nch = r->nch;
	for (int k = 0; k < wk->dec.channel_count; k++) {
		const exr_coding_channel_info_t *c = &wk->dec.channels[k];
		if (c->decode_to_ptr == wk->skip)
			continue;
		int want = (int)((c->decode_to_ptr - wk->stage) / (ptrdiff_t)r->block);
		size_t n = (size_t)rows * (size_t)w;
		float *dst = r->px + (size_t)y * w * nch + want;
		for (size_t i = 0; i < n; i++) {
			float v;
			if (c->bytes_per_element == 2) {
				uint16_t hv;
				memcpy(&hv, c->decode_to_ptr + i * 2, 2);
				v = cs_half_to_float(hv);
			} else {
				memcpy(&v, c->decode_to_ptr + i * 4, 4);
			}
			dst[i * (size_t)nch] = v;
		}
	}
}

/* Decodes the chunk that starts at scanline y into the result with the
 * worker's decoder. */
static int decode_chunk(const struct chunk_reader *r, struct dec_worker *wk, long y)
{
	int rc = CS_OK;
	const char *name = r->name;
	exr_chunk_info_t ci;
	TRY(exr_read_scanline_chunk_info(r->f, 0, (int)y, &ci),
	    "truncated or corrupt pixel data");
	if (ci.start_y != y || ci.height < 1 || y + ci.height > r->h || ci.width != r->w)
		return cs_error(CS_EDATA, "%s: inconsistent chunk at scanline %ld", name, y);
	if (!wk->live) {
		TRY(exr_decoding_initialize(r->f, 0, &ci, &wk->dec), "decoder");
		wk->live = 1; /* (destroyed with the context, whatever follows) */
	} else {
		TRY(exr_decoding_update(r->f, 0, &ci, &wk->dec), "decoder");
	}
	route_channels(r, wk);
	if (!wk->routines) {
		TRY(exr_decoding_choose_default_routines(r->f, 0, &wk->dec), "decoder");
		wk->routines = 1;
	}
	TRY(exr_decoding_run(r->f, 0, &wk->dec), "truncated or corrupt pixel data");
	convert_chunk(r, wk, y, ci.height);
done:
	return rc;
}

static void decode_task(void *user, int task, int worker)
{
	struct chunk_reader *r = user;
	exr_msg[0] = '\0';
	int rc = decode_chunk(r, &r->wk[worker], (long)task * r->spc);
	if (rc != CS_OK)
		chunk_failed(&r->err[task], rc);
}

int cs_exr_read_channels_threads(const void *data, size_t len, const char *name,
				 const char *const *channels, int nch, int nthreads,
				 int *width, int *height, float **pixels)
{
	struct chunk_reader r = {
		.name = name, .channels = channels, .nch = nch, .len = len,
		.nthreads = nthreads,
	};
	struct cs_exr_mem src = {data, len};

	*pixels = NULL;
	int rc = open_scanline(&r, &src);
	if (rc == CS_OK)
		rc = check_channels(&r);
	if (rc == CS_OK)
		rc = alloc_buffers(&r);
	int nchunks = rc == CS_OK ? (int)((r.h + r.spc - 1) / r.spc) : 0;
	if (rc == CS_OK)
		rc = cs_pool_run(nchunks, r.nworkers, decode_task, &r, NULL, NULL, NULL);
	/* in order: the first chunk that failed says why */
	for (int t = 0; rc == CS_OK && t < nchunks; t++)
		if (r.err[t].rc != CS_OK)
			rc = cs_error(r.err[t].rc, "%s", r.err[t].msg);
	if (rc == CS_OK) {
		*width = (int)r.w;
		*height = (int)r.h;
		*pixels = r.px;
		r.px = NULL;
	}
	for (int k = 0; r.wk != NULL && k < r.nworkers; k++) {
		if (r.wk[k].live)
			exr_decoding_destroy(r.f, &r.wk[k].dec);
		free(r.wk[k].skip);
		free(r.wk[k].stage);
	}
	if (r.f)
		exr_finish(&r.f);
	free(r.wk);
	free(r.err);
	free(r.px);
	return rc;
}

int cs_exr_read_channels(const void *data, size_t len, const char *name,
			 const char *const *channels, int nch, int *width,
			 int *height, float **pixels)
{
	return cs_exr_read_channels_threads(data, len, name, channels, nch, 1, width, height,
					    pixels);
}

int cs_exr_read_float_channel(const void *data, size_t len, const char *name,
			      const char *channel, int *width, int *height,
			      float **pixels)
{
	return cs_exr_read_channels(data, len, name, &channel, 1, width, height, pixels);
}
