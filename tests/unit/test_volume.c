#include "core/err.h"
#include "core/fileio.h"
#include "core/half.h"
#include "noise/noise.h"
#include "core/hash.h"
#include "apps/noisebake_run.h"
#include "test.h"
#include "noise/volume.h"

#include <openexr.h>

#include <dirent.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

static char tmpdir[256];

static const char *tmp(const char *name)
{
	static char path[512];
	snprintf(path, sizeof path, "%s/%s", tmpdir, name);
	return path;
}

static int bake_small(struct cs_volume *v, int n, int d, int threads)
{
	int rc = cs_volume_new(v, n, d);
	if (rc == CS_OK) {
		v->recipe.seed = 77;
		rc = cs_volume_bake(v, threads, NULL, NULL);
	}
	return rc;
}

static int count_files(const char *dir)
{
	DIR *d = opendir(dir);
	int n = 0;
	struct dirent *e;
	while (d && (e = readdir(d)) != NULL)
		n += e->d_name[0] != '.' || (e->d_name[1] != '\0' &&
					     strcmp(e->d_name, "..") != 0);
	if (d)
		closedir(d);
	return n;
}

static void recipe_formats_and_parses_back(void)
{
	struct cs_noise_recipe r, q;
	cs_noise_recipe_default(&r);
	r.freq[2] = 11;
	r.octaves[3] = 5;
	r.gain = 0.3;
	char buf[512];
	cs_noise_recipe_format(&r, buf, sizeof buf);
	cs_noise_recipe_default(&q);
	CHECK(cs_noise_recipe_parse(buf, &q) == CS_OK);
	CHECK(memcmp(q.freq, r.freq, sizeof r.freq) == 0);
	CHECK(memcmp(q.octaves, r.octaves, sizeof r.octaves) == 0);
	CHECK(q.gain == r.gain && q.worley_octaves == r.worley_octaves);
	CHECK(cs_noise_recipe_parse("R=perlin-worley:4:4", &q) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "unrecognised noise recipe");
	CHECK(cs_noise_recipe_parse("R=perlin-worley:0:4:3;G=worley-fbm:4:3;"
				    "B=worley-fbm:8:3;A=worley-fbm:16:3;gain=0.5",
				    &q) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "frequency of channel R");
}

/* The output bytes do not depend on the number of threads. */
static void bake_is_identical_for_any_thread_count(void)
{
	struct cs_volume a, b, c;
	CHECK(bake_small(&a, 16, 12, 1) == CS_OK);
	CHECK(bake_small(&b, 16, 12, 2) == CS_OK);
	CHECK(bake_small(&c, 16, 12, 7) == CS_OK);
	size_t n = 16u * 16u * 12u * 4u * sizeof(float);
	CHECK(memcmp(a.data, b.data, n) == 0);
	CHECK(memcmp(a.data, c.data, n) == 0);
	cs_volume_free(&a);
	cs_volume_free(&b);
	cs_volume_free(&c);
}

static double at(const struct cs_volume *v, int x, int y, int z, int c)
{
	return v->data[(((size_t)z * v->ny + y) * v->nx + x) * 4 + c];
}

/* The bake, a row of voxels at a time, holds what the noise's definition
 * gives at each voxel centre (noise.c's cs_perlin_worley3p and
 * cs_worley_fbm3p, which hash every lattice point), as floats, bit for
 * bit: on two shapes, rows of cells shared by several rows of voxels. */
static void bake_equals_the_definition(void)
{
	static const int shapes[2][2] = {{24, 10}, {32, 32}};
	long n = 0;
	for (int s = 0; s < 2; s++) {
		struct cs_volume v;
		CHECK(bake_small(&v, shapes[s][0], shapes[s][1], 2) == CS_OK);
		const struct cs_noise_recipe *r = &v.recipe;
		for (int c = 0; c < 4; c++) {
			int p[3];
			cs_noise_period(r, c, v.nx, v.nz, p);
			uint32_t seed = cs_hash3i((int32_t)r->seed, c, 0, 0x6e6f6973u);
			struct cs_fbm main = {r->octaves[c], 2, r->gain};
			struct cs_fbm wor = {r->worley_octaves, 2, r->gain};
			for (int z = 0; z < v.nz; z += 3)
				for (int y = 0; y < v.ny; y++)
					for (int x = 0; x < v.nx; x++) {
						double px = (x + 0.5) / v.nx * p[0];
						double py = (y + 0.5) / v.ny * p[1];
						double pz = (z + 0.5) / v.nz * p[2];
						float want = (float)(c == 0 ? cs_perlin_worley3p(px, py, pz, p, seed, &main, &wor)
									    : cs_worley_fbm3p(px, py, pz, p, seed, &main));
						float got = (float)at(&v, x, y, z, c);
						if (memcmp(&want, &got, sizeof got) != 0) {
							CHECK(memcmp(&want, &got, sizeof got) == 0);
							goto next;
						}
						n++;
					}
		next:;
		}
		cs_volume_free(&v);
	}
	printf("  %ld voxel channels as defined\n", n);
}


/* No visible seam: the step across the wrap (voxel n-1 to voxel 0) is like
 * a step inside the volume, on every axis and channel. */
static void baked_volume_has_no_seam(void)
{
	struct cs_volume v;
	enum { N = 32, D = 32 };
	CHECK(bake_small(&v, N, D, 0) == CS_OK);
	for (int c = 0; c < 4; c++)
		for (int axis = 0; axis < 3; axis++) {
			double inside = 0.0, wrap = 0.0;
			int ni = 0, nw = 0;
			for (int a = 0; a < N; a++)
				for (int b = 0; b < N; b++)
					for (int i = 0; i < N; i++) {
						int j = (i + 1) % N;
						double d;
						if (axis == 0)
							d = at(&v, j, a, b, c) - at(&v, i, a, b, c);
						else if (axis == 1)
							d = at(&v, a, j, b, c) - at(&v, a, i, b, c);
						else
							d = at(&v, a, b, j, c) - at(&v, a, b, i, c);
						if (j == 0)
							wrap += fabs(d), nw++;
						else
							inside += fabs(d), ni++;
					}
			double ratio = (wrap / nw) / (inside / ni);
			if (!(ratio > 0.75 && ratio < 1.33))
				printf("  channel %d axis %d: wrap/inside step ratio %.3f\n",
				       c, axis, ratio);
			CHECK(ratio > 0.75 && ratio < 1.33);
		}
	cs_volume_free(&v);
}

/* A deliberately non-periodic field shows the seam the test above looks for,
 * so that test can fail. */
static void seam_metric_detects_a_seam(void)
{
	struct cs_volume v;
	enum { N = 32 };
	CHECK(cs_volume_new(&v, N, 1) == CS_OK);
	for (int y = 0; y < N; y++)
		for (int x = 0; x < N; x++)
			v.data[((size_t)y * N + x) * 4] = (float)x / N;
	double inside = 0.0, wrap = 0.0;
	for (int y = 0; y < N; y++)
		for (int x = 0; x < N; x++) {
			double d = fabs(at(&v, (x + 1) % N, y, 0, 0) - at(&v, x, y, 0, 0));
			if (x == N - 1)
				wrap += d / N;
			else
				inside += d / (N * (N - 1.0));
		}
	CHECK(wrap / inside > 10.0);
	cs_volume_free(&v);
}

static void sample_is_periodic_and_interpolates_voxels(void)
{
	struct cs_volume v;
	CHECK(bake_small(&v, 8, 4, 1) == CS_OK);
	/* at a voxel centre the sample is the voxel */
	CHECK_NEAR(cs_volume_sample(&v, 2, (3 + 0.5) / 8, (5 + 0.5) / 8, (1 + 0.5) / 4),
		   at(&v, 3, 5, 1, 2), 1e-6);
	unsigned st = 12;
	for (int i = 0; i < 1000; i++) {
		double u = t_uniform(&st, -3, 3), w = t_uniform(&st, -3, 3),
		       t = t_uniform(&st, -3, 3);
		float s = cs_volume_sample(&v, 0, u, w, t);
		CHECK_NEAR(cs_volume_sample(&v, 0, u + 5, w - 2, t + 1000), s, 1e-4);
	}
	CHECK(cs_volume_sample(&v, 1, NAN, 0, 0) == 0.0f);
	CHECK(isfinite(cs_volume_sample(&v, 1, 1e300, -1e300, 3)));
	cs_volume_free(&v);
}

static void exr_round_trip_half_and_float(void)
{
	struct cs_volume v, h, f;
	CHECK(bake_small(&v, 16, 5, 2) == CS_OK);
	v.recipe.seed = 1234567;
	CHECK(cs_volume_write_exr(&v, tmp("h.exr"), 0, 1) == CS_OK);
	/* the float one's 5 chunks of 16 rows written and read on 3 threads */
	CHECK(cs_volume_write_exr(&v, tmp("f.exr"), 1, 3) == CS_OK);
	CHECK(cs_volume_read_exr(tmp("h.exr"), &h, 1) == CS_OK);
	CHECK(cs_volume_read_exr(tmp("f.exr"), &f, 3) == CS_OK);
	if (h.data == NULL || f.data == NULL)
		return;
	CHECK(h.nx == 16 && h.ny == 16 && h.nz == 5 && h.recipe.seed == 1234567);
	CHECK(memcmp(h.recipe.freq, v.recipe.freq, sizeof v.recipe.freq) == 0);
	size_t n = 16u * 16u * 5u * 4u;
	CHECK(memcmp(f.data, v.data, n * sizeof(float)) == 0);
	int bad = 0;
	for (size_t i = 0; i < n; i++)
		bad += h.data[i] != cs_half_to_float(cs_float_to_half(v.data[i]));
	CHECK(bad == 0);
	cs_volume_free(&v);
	cs_volume_free(&h);
	cs_volume_free(&f);
}

/* A voxel beyond +-1e30 is refused like a non-finite one (two near
 * FLT_MAX, which a float file holds, sampled between them to infinity:
 * the fuzzer's find); one at 1e30 is read, and its sample is finite. */
static void exr_voxels_beyond_1e30_are_refused(void)
{
	struct cs_volume v, r;
	CHECK(bake_small(&v, 16, 5, 2) == CS_OK);
	v.data[5] = 1e30f;
	v.data[9] = -1e30f;
	CHECK(cs_volume_write_exr(&v, tmp("big.exr"), 1, 1) == CS_OK);
	CHECK(cs_volume_read_exr(tmp("big.exr"), &r, 1) == CS_OK);
	cs_volume_free(&r);
	v.data[5] = 3e38f;
	v.data[9] = 3e38f;
	CHECK(cs_volume_write_exr(&v, tmp("huge.exr"), 1, 1) == CS_OK);
	CHECK(cs_volume_read_exr(tmp("huge.exr"), &r, 1) == CS_EDATA);
	cs_volume_free(&v);
}

/* Every truncation of a valid file is an error with a message, never a
 * crash and never a volume. */
static void exr_truncated_file_is_a_clear_error(void)
{
	struct cs_volume v;
	CHECK(bake_small(&v, 16, 4, 1) == CS_OK);
	CHECK(cs_volume_write_exr(&v, tmp("t.exr"), 0, 1) == CS_OK);
	cs_volume_free(&v);
	unsigned char *data;
	size_t len;
	CHECK(cs_read_all(tmp("t.exr"), 1 << 24, &data, &len) == CS_OK);
	int accepted = 0, unnamed = 0;
	for (size_t cut = 0; cut < len; cut += (cut < 600 ? 7 : 97)) {
		struct cs_volume r;
		int rc = cs_volume_read_exr_mem(data, cut, "cut.exr", &r);
		accepted += rc == CS_OK;
		unnamed += rc != CS_OK && strstr(cs_errmsg(), "cut.exr") == NULL;
		CHECK(rc != CS_OK || r.data != NULL);
		cs_volume_free(&r);
	}
	CHECK(accepted == 0);
	CHECK(unnamed == 0);
	free(data);
}

/* Flipped bytes anywhere: an error or a finite volume, never a crash. */
static void exr_corrupt_bytes_never_crash(void)
{
	struct cs_volume v;
	CHECK(bake_small(&v, 16, 4, 1) == CS_OK);
	CHECK(cs_volume_write_exr(&v, tmp("c.exr"), 0, 1) == CS_OK);
	cs_volume_free(&v);
	unsigned char *data;
	size_t len;
	CHECK(cs_read_all(tmp("c.exr"), 1 << 24, &data, &len) == CS_OK);
	unsigned st = 99;
	int rejected = 0;
	for (int trial = 0; trial < 300; trial++) {
		unsigned char *copy = malloc(len);
		memcpy(copy, data, len);
		for (int k = 0; k < 4; k++)
			copy[(size_t)t_uniform(&st, 0, (double)len)] ^=
				(unsigned char)(1u + (unsigned)t_uniform(&st, 0, 255));
		struct cs_volume r;
		if (cs_volume_read_exr_mem(copy, len, "corrupt.exr", &r) == CS_OK) {
			size_t n = (size_t)r.nx * r.ny * r.nz * 4;
			for (size_t i = 0; i < n; i++)
				CHECK(isfinite(r.data[i]));
			cs_volume_free(&r);
		} else {
			rejected++;
		}
		free(copy);
	}
	CHECK(rejected > 0);
	free(data);
}

/* Writes an EXR through the core API with the given channels and optional
 * cloudscape attributes, to test the reader's validation. */
static void write_custom(const char *path, const char *const *chans, int nch,
			 int w, int h, int attrs, int size_z)
{
	exr_context_t f;
	exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
	int part;
	if (exr_start_write(&f, path, EXR_WRITE_FILE_DIRECTLY, &init) != EXR_ERR_SUCCESS)
		return;
	exr_add_part(f, "x", EXR_STORAGE_SCANLINE, &part);
	exr_initialize_required_attr_simple(f, part, w, h, EXR_COMPRESSION_NONE);
	for (int c = 0; c < nch; c++)
		exr_add_channel(f, part, chans[c], EXR_PIXEL_FLOAT,
				EXR_PERCEPTUALLY_LINEAR, 1, 1);
	if (attrs) {
		exr_attr_v3i_t sz = {.x = w, .y = w, .z = size_z};
		struct cs_noise_recipe r;
		char buf[512];
		cs_noise_recipe_default(&r);
		cs_noise_recipe_format(&r, buf, sizeof buf);
		exr_attr_set_int(f, part, "cloudscapeFormat", 1);
		exr_attr_set_v3i(f, part, "cloudscapeVolumeSize", &sz);
		exr_attr_set_int(f, part, "cloudscapeSeed", 0);
		exr_attr_set_string(f, part, "cloudscapeRecipe", buf);
		exr_attr_set_string(f, part, "cloudscapePeriod", "R=4x4x4;G=4x4x4;B=8x8x8;A=16x16x16");
	}
	exr_write_header(f);
	float *px = calloc((size_t)w * h * nch, sizeof(float));
	int32_t spc;
	exr_get_scanlines_per_chunk(f, part, &spc);
	exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
	for (int y = 0; y < h; y += spc) {
		exr_chunk_info_t ci;
		exr_write_scanline_chunk_info(f, part, y, &ci);
		if (y == 0)
			exr_encoding_initialize(f, part, &ci, &enc);
		else
			exr_encoding_update(f, part, &ci, &enc);
		for (int k = 0; k < enc.channel_count; k++) {
			enc.channels[k].encode_from_ptr = (const uint8_t *)(px + (size_t)y * w * nch + k);
			enc.channels[k].user_bytes_per_element = 4;
			enc.channels[k].user_data_type = EXR_PIXEL_FLOAT;
			enc.channels[k].user_pixel_stride = 4 * nch;
			enc.channels[k].user_line_stride = 4 * nch * w;
		}
		if (y == 0)
			exr_encoding_choose_default_routines(f, part, &enc);
		exr_encoding_run(f, part, &enc);
	}
	exr_encoding_destroy(f, &enc);
	exr_finish(&f);
	free(px);
}

static void exr_reader_rejects_wrong_files_with_clear_messages(void)
{
	static const char *const rgb[] = {"R", "G", "B"};
	static const char *const rgba[] = {"R", "G", "B", "A"};
	static const char *const rgbz[] = {"R", "G", "B", "Z"};
	struct cs_volume v;

	write_custom(tmp("rgb.exr"), rgb, 3, 16, 64, 1, 4);
	CHECK(cs_volume_read_exr(tmp("rgb.exr"), &v, 1) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "expected channels A,B,G,R, found B,G,R");

	write_custom(tmp("rgbz.exr"), rgbz, 4, 16, 64, 1, 4);
	CHECK(cs_volume_read_exr(tmp("rgbz.exr"), &v, 1) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "expected channels A,B,G,R");

	write_custom(tmp("noattr.exr"), rgba, 4, 16, 64, 0, 4);
	CHECK(cs_volume_read_exr(tmp("noattr.exr"), &v, 1) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "missing attribute cloudscapeFormat");

	write_custom(tmp("size.exr"), rgba, 4, 16, 64, 1, 5);
	CHECK(cs_volume_read_exr(tmp("size.exr"), &v, 1) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "cloudscapeVolumeSize 16x16x5 needs 16x80");

	/* the same writer with everything right is accepted */
	write_custom(tmp("ok.exr"), rgba, 4, 16, 256, 1, 16);
	CHECK(cs_volume_read_exr(tmp("ok.exr"), &v, 1) == CS_OK);
	cs_volume_free(&v);

	FILE *fp = fopen(tmp("text.exr"), "w");
	fputs("this is not an image\n", fp);
	fclose(fp);
	CHECK(cs_volume_read_exr(tmp("text.exr"), &v, 1) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "text.exr: not a readable OpenEXR file");

	CHECK(cs_volume_read_exr(tmp("absent.exr"), &v, 1) == CS_EIO);
	CHECK_STR_CONTAINS(cs_errmsg(), "absent.exr");
	CHECK_STR_CONTAINS(cs_errmsg(), "No such file");
	CHECK(v.data == NULL);
}

/* A failed write leaves neither a partial file nor the temporary, and does
 * not touch an existing file; a good write replaces it whole. */
static void outputs_are_atomic(void)
{
	char dir[512];
	snprintf(dir, sizeof dir, "%s/atomic", tmpdir);
	mkdir(dir, 0755);
	char dst[600];
	snprintf(dst, sizeof dst, "%s/out.exr", dir);
	FILE *fp = fopen(dst, "w");
	fputs("old", fp);
	fclose(fp);

	struct cs_outfile of;
	CHECK(cs_outfile_open(&of, dst) == CS_OK);
	CHECK(write(of.fd, "partial", 7) == 7);
	CHECK(count_files(dir) == 2);
	cs_outfile_abort(&of);
	CHECK(count_files(dir) == 1);
	unsigned char *d;
	size_t n;
	CHECK(cs_read_all(dst, 100, &d, &n) == CS_OK);
	CHECK(n == 3 && memcmp(d, "old", 3) == 0);
	free(d);

	struct cs_volume v;
	CHECK(bake_small(&v, 8, 2, 1) == CS_OK);
	CHECK(cs_volume_write_exr(&v, dst, 0, 1) == CS_OK);
	CHECK(count_files(dir) == 1);
	struct cs_volume r;
	CHECK(cs_volume_read_exr(dst, &r, 1) == CS_OK);
	cs_volume_free(&r);

	CHECK(cs_volume_write_exr(&v, "/nonexistent-dir/x.exr", 0, 1) == CS_EIO);
	CHECK_STR_CONTAINS(cs_errmsg(), "/nonexistent-dir/x.exr");
	cs_volume_free(&v);
}

static void contact_sheet_layout_and_values(void)
{
	struct cs_volume v;
	CHECK(bake_small(&v, 8, 6, 1) == CS_OK);
	int slices[3] = {0, 2, 5};
	uint8_t *pix = NULL;
	int w = 0, h = 0;
	CHECK(cs_volume_contact_sheet(&v, slices, 3, "GA", &pix, &w, &h) == CS_OK);
	CHECK(w == 3 * 8 + 2 * 2 && h == 2 * 8 + 2);
	if (pix) {
		/* row 1 (A), column 2 (slice 5), voxel (3, 4) */
		uint8_t want = (uint8_t)lrintf(at(&v, 3, 4, 5, 3) * 255.0f);
		CHECK(pix[(size_t)(1 * 10 + 4) * w + (2 * 10 + 3)] == want);
		CHECK(pix[(size_t)8 * w + 0] == 255); /* the gap */
	}
	free(pix);
	CHECK(cs_volume_contact_sheet(&v, slices, 3, "X", &pix, &w, &h) == CS_EINVAL);
	slices[0] = 6;
	CHECK(cs_volume_contact_sheet(&v, slices, 3, "R", &pix, &w, &h) == CS_EINVAL);
	CHECK_STR_CONTAINS(cs_errmsg(), "slice 6 is outside 0..5");
	cs_volume_free(&v);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(recipe_formats_and_parses_back),
	CASE(bake_is_identical_for_any_thread_count),
	CASE(bake_equals_the_definition),
	CASE(baked_volume_has_no_seam),
	CASE(seam_metric_detects_a_seam),
	CASE(sample_is_periodic_and_interpolates_voxels),
	CASE(exr_round_trip_half_and_float),
	CASE(exr_voxels_beyond_1e30_are_refused),
	CASE(exr_truncated_file_is_a_clear_error),
	CASE(exr_corrupt_bytes_never_crash),
	CASE(exr_reader_rejects_wrong_files_with_clear_messages),
	CASE(outputs_are_atomic),
	CASE(contact_sheet_layout_and_values),
};

int main(void)
{
	snprintf(tmpdir, sizeof tmpdir, "%s/cs-test-volume.XXXXXX",
		 getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	if (mkdtemp(tmpdir) == NULL) {
		perror("mkdtemp");
		return 1;
	}
	T_RUN_TABLE(t_cases);
	char cmd[600];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
	if (system(cmd) != 0)
		return 1;
	TEST_EXIT();
}
