#include "core/err.h"
#include "io/exr.h"
#include "core/fileio.h"
#include "test.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char path[512];

static int read_back(int w, int h, const char *channel, float **px)
{
	unsigned char *data;
	size_t len;
	int rw, rh;
	if (cs_read_all(path, 1 << 26, &data, &len) != CS_OK)
		return -1;
	int rc = cs_exr_read_float_channel(data, len, path, channel, &rw, &rh, px);
	free(data);
	return rc == CS_OK && rw == w && rh == h ? 0 : -1;
}

/* Heights that OpenEXR 3.1's ZIP encoder corrupts (its first 16-row chunk
 * comes back as garbage): cs_exr_write notices on reading back and writes
 * them again in a way that keeps them, so they round-trip exactly. */
static void float_heights_round_trip_exactly_despite_the_zip_fault(void)
{
	char fixture[512];
	t_top_path(fixture, sizeof fixture, "tests/fixtures/zip-fallback-heights.txt");
	FILE *fp = fopen(fixture, "r");
	CHECK(fp != NULL);
	if (fp == NULL)
		return;
	enum { W = 50, H = 50 };
	static float z[W * H];
	char line[1024];
	int n = 0;
	while (n < W * H && fgets(line, sizeof line, fp)) {
		if (line[0] == '#')
			continue;
		char *p = line, *end;
		for (float v = strtof(p, &end); end != p && n < W * H; v = strtof(p, &end)) {
			z[n++] = v;
			p = end;
		}
	}
	fclose(fp);
	CHECK(n == W * H);
	const struct cs_exr_channel ch = {"Y", 1, z, 1};
	/* one thread, and its four chunks on three (the check reads them
	 * back on three too) */
	for (int threads = 1; threads <= 3; threads += 2) {
		CHECK(cs_exr_write(path, W, H, &ch, 1, NULL, 0, threads) == CS_OK);
		float *back = NULL;
		CHECK(read_back(W, H, "Y", &back) == 0);
		int bad = 0;
		for (int i = 0; back && i < W * H; i++)
			bad += back[i] != z[i];
		CHECK(bad == 0);
		free(back);
	}
}

/* Several channels, half and float, odd sizes: each reads back as written
 * (half ones rounded to half). */
static void mixed_channels_round_trip(void)
{
	enum { W = 37, H = 23 };
	static float px[W * H * 3];
	unsigned st = 3;
	for (int i = 0; i < W * H * 3; i++)
		px[i] = (float)t_uniform(&st, -100, 100);
	const struct cs_exr_channel ch[3] = {
		{"R", 0, px, 3}, {"G", 1, px + 1, 3}, {"Z", 1, px + 2, 3}};
	CHECK(cs_exr_write(path, W, H, ch, 3, NULL, 0, 1) == CS_OK);
	float *g = NULL, *r = NULL;
	CHECK(read_back(W, H, "G", &g) == 0 && read_back(W, H, "R", &r) == 0);
	int bad = 0;
	for (int i = 0; g && r && i < W * H; i++) {
		bad += g[i] != px[i * 3 + 1];
		bad += fabsf(r[i] - px[i * 3]) > fabsf(px[i * 3]) * 1e-3f;
	}
	CHECK(bad == 0);
	free(g);
	free(r);
	/* several channels in one pass, interleaved in the order asked */
	unsigned char *data;
	size_t len;
	int rw, rh;
	float *zg = NULL;
	static const char *const order[2] = {"Z", "G"};
	CHECK(cs_read_all(path, 1 << 26, &data, &len) == CS_OK);
	CHECK(cs_exr_read_channels(data, len, path, order, 2, &rw, &rh, &zg) == CS_OK);
	bad = 0;
	for (int i = 0; zg && i < W * H; i++)
		bad += zg[i * 2] != px[i * 3 + 2] || zg[i * 2 + 1] != px[i * 3 + 1];
	CHECK(bad == 0 && rw == W && rh == H);
	free(zg);
	free(data);
	CHECK(read_back(W, H, "B", &g) != 0);
	CHECK_STR_CONTAINS(cs_errmsg(), "no channel B");
}

/* The chunks compressed on several threads and written in order: the
 * same bytes as on one thread, for an image of 19 chunks of 16 rows, the
 * last one short (301 rows), and the pixels read back as written. */
static void threads_write_the_same_bytes(void)
{
	enum { W = 61, H = 301 };
	static float px[W * H * 3];
	unsigned st = 11;
	for (int i = 0; i < W * H * 3; i++)
		px[i] = (float)t_uniform(&st, 0, 1) * (float)(i % 977);
	const struct cs_exr_channel ch[3] = {
		{"R", 0, px, 3}, {"G", 1, px + 1, 3}, {"Z", 1, px + 2, 3}};
	unsigned char *one = NULL, *four = NULL;
	size_t n1 = 0, n4 = 0;
	CHECK(cs_exr_write(path, W, H, ch, 3, NULL, 0, 1) == CS_OK);
	CHECK(cs_read_all(path, 1 << 26, &one, &n1) == CS_OK);
	CHECK(cs_exr_write(path, W, H, ch, 3, NULL, 0, 4) == CS_OK);
	CHECK(cs_read_all(path, 1 << 26, &four, &n4) == CS_OK);
	CHECK(one && four && n1 == n4 && n1 > 1000 && memcmp(one, four, n1) == 0);
	static const char *const order[3] = {"Z", "G", "R"};
	float *back = NULL;
	int rw = 0, rh = 0, bad = 0;
	CHECK(four && cs_exr_read_channels(four, n4, path, order, 3, &rw, &rh, &back) == CS_OK);
	for (int i = 0; back && i < W * H; i++)
		bad += back[i * 3] != px[i * 3 + 2] || back[i * 3 + 1] != px[i * 3 + 1] ||
		       fabsf(back[i * 3 + 2] - px[i * 3]) > px[i * 3] * 1e-3f;
	CHECK(back && rw == W && rh == H && bad == 0);
	free(back);
	free(one);
	free(four);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(float_heights_round_trip_exactly_despite_the_zip_fault),
	CASE(mixed_channels_round_trip),
	CASE(threads_write_the_same_bytes),
};

int main(void)
{
	snprintf(path, sizeof path, "%s/cs-test-exr-%d.exr",
		 getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp", (int)getpid());
	T_RUN_TABLE(t_cases);
	unlink(path);
	TEST_EXIT();
}
