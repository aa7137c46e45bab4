/* Heightfield files (terrain.c), DEM operations (dem.c) and terrainprep's
 * GDAL pipeline on GDAL's own test DEMs (../shared/data/dem, skipped when
 * absent). */
#include "terrain/dem.h"
#include "core/err.h"
#include "io/exr.h"
#include "core/fileio.h"
#include "terrain/terrain.h"
#include "apps/terrainprep_run.h"
#include "test.h"
#include "core/vec.h"

#include <gdal.h>
#include <gdal_utils.h>

#include <dirent.h>
#include <stdint.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

static char tmpdir[256];
static char datadir[512];

static const char *tmp(const char *name)
{
	static char path[4][512];
	static int k;
	k = (k + 1) % 4;
	snprintf(path[k], sizeof path[k], "%s/%s", tmpdir, name);
	return path[k];
}

/* ../shared/data/dem beside the project: $DATA, or found from the binary
 * (TOP/build/tests/test_terrain). */
static const char *dem(const char *name)
{
	static char path[640];
	snprintf(path, sizeof path, "%s/dem/%s", datadir, name);
	return access(path, R_OK) == 0 ? path : NULL;
}

static void find_data(void)
{
	const char *env = getenv("DATA");
	if (env) {
		snprintf(datadir, sizeof datadir, "%s", env);
		return;
	}
	char exe[400];
	ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
	exe[n > 0 ? n : 0] = '\0';
	for (int up = 0; up < 3; up++) {
		char *slash = strrchr(exe, '/');
		if (slash)
			*slash = '\0';
	}
	snprintf(datadir, sizeof datadir, "%s/../shared/data", exe);
}

static int count_files(const char *dir)
{
	DIR *d = opendir(dir);
	int n = 0;
	struct dirent *e;
	while (d && (e = readdir(d)) != NULL)
		n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
	if (d)
		closedir(d);
	return n;
}

static void write_text(const char *path, const char *text)
{
	FILE *f = fopen(path, "w");
	if (f) {
		fputs(text, f);
		fclose(f);
	}
}

/* A small terrain with distinct heights and a made-up georeference. */
static void small_terrain(struct cs_terrain *t, float *h, int w, int hh)
{
	memset(t, 0, sizeof *t);
	t->width = w;
	t->height = hh;
	t->h = h;
	t->min_m = INFINITY;
	t->max_m = -INFINITY;
	for (int i = 0; i < w * hh; i++) {
		h[i] = (float)(500.0 + 3.25 * i - 0.01 * i * i);
		t->min_m = fmin(t->min_m, h[i]);
		t->max_m = fmax(t->max_m, h[i]);
	}
	t->origin_x = 2600000.0;
	t->origin_y = 1200000.0;
	t->pixel_x_m = 25.0;
	t->pixel_y_m = 30.0;
	t->epsg = 2056;
	t->crs_wkt = "PROJCRS[\"CH1903+ / LV95\"]";
	for (int c = 0; c < 4; c++) {
		t->corner_lat[c] = 46.9 + 0.01 * c;
		t->corner_lon[c] = 7.4 - 0.02 * c;
	}
	t->center_lat = 46.95;
	t->center_lon = 7.43;
}

static void terrain_round_trips_exr_and_sidecar(void)
{
	float h[7 * 5];
	struct cs_terrain t, r;
	small_terrain(&t, h, 7, 5);
	CHECK(cs_terrain_write(tmp("rt.exr"), &t, "a.tif", "GTiff", "fill=nearest") == CS_OK);
	CHECK(access(tmp("rt.json"), R_OK) == 0);
	int rc = cs_terrain_read(tmp("rt.exr"), &r);
	CHECK(rc == CS_OK);
	if (rc != CS_OK) {
		printf("  %s\n", cs_errmsg());
		return;
	}
	CHECK(r.width == 7 && r.height == 5);
	CHECK(memcmp(r.h, h, sizeof h) == 0);
	CHECK(r.origin_x == t.origin_x && r.origin_y == t.origin_y);
	CHECK(r.pixel_x_m == 25.0 && r.pixel_y_m == 30.0);
	CHECK(r.min_m == t.min_m && r.max_m == t.max_m);
	CHECK(r.epsg == 2056);
	CHECK(strcmp(r.crs_wkt, t.crs_wkt) == 0);
	for (int c = 0; c < 4; c++)
		CHECK(r.corner_lat[c] == t.corner_lat[c] && r.corner_lon[c] == t.corner_lon[c]);
	CHECK(r.center_lat == 46.95 && r.center_lon == 7.43);
	cs_terrain_free(&r);
	CHECK(count_files(tmpdir) == 2); /* no temporaries left */
}

static void terrain_read_reports_missing_and_corrupt_sidecars(void)
{
	float h[4 * 3];
	struct cs_terrain t, r;
	small_terrain(&t, h, 4, 3);
	CHECK(cs_terrain_write(tmp("bad.exr"), &t, NULL, NULL, NULL) == CS_OK);
	unsigned char *json = NULL;
	size_t len = 0;
	CHECK(cs_read_all(tmp("bad.json"), 1 << 20, &json, &len) == CS_OK);
	char *good = strndup((const char *)json, len);
	free(json);

	unlink(tmp("bad.json"));
	CHECK(cs_terrain_read(tmp("bad.exr"), &r) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "sidecar");
	CHECK_STR_CONTAINS(cs_errmsg(), "bad.json");

	write_text(tmp("bad.json"), "{\"cloudscape_terrain\": 1, \"width\": ");
	CHECK(cs_terrain_read(tmp("bad.exr"), &r) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "not a JSON object");

	/* one field at a time made wrong, each must be caught */
	static const char *const edits[][3] = {
		{"\"width\":\t4", "\"width\":\t5", "says 5x3"},
		{"\"row_order\":\t\"north-up\"", "\"row_order\":\t\"south-up\"", "row_order"},
		{"\"max\":\t", "\"max\":\t1", "disagrees"},
		{"\"cloudscape_terrain\":\t1", "\"cloudscape_terrain\":\t2", "version 2"},
		{"\"x\":\t25", "\"x\":\t-25", "pixel_size_m.x"},
		{"\"lat\":\t46.9,", "\"lat\":\t146.9,", "wgs84.upper_left.lat"},
		{"\"origin\":\t{", "\"origin\":\t{\"x\":\"a\",", "origin.x"},
		{"\"format\":\t\"exr\"", "\"format\":\t\"r16\"", "only exr"},
	};
	for (size_t e = 0; e < sizeof edits / sizeof edits[0]; e++) {
		char *at = strstr(good, edits[e][0]);
		CHECK(at != NULL);
		if (at == NULL)
			continue;
		char text[8192];
		snprintf(text, sizeof text, "%.*s%s%s", (int)(at - good), good, edits[e][1],
			 at + strlen(edits[e][0]));
		write_text(tmp("bad.json"), text);
		CHECK(cs_terrain_read(tmp("bad.exr"), &r) == CS_EDATA);
		CHECK_STR_CONTAINS(cs_errmsg(), edits[e][2]);
		CHECK(r.h == NULL && r.crs_wkt == NULL);
	}
	write_text(tmp("bad.json"), good);
	CHECK(cs_terrain_read(tmp("bad.exr"), &r) == CS_OK);
	cs_terrain_free(&r);
	free(good);

	write_text(tmp("bad.exr"), "not an exr");
	CHECK(cs_terrain_read(tmp("bad.exr"), &r) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "not a readable OpenEXR file");
	CHECK(cs_terrain_read("-", &r) == CS_EINVAL);
}

static void terrain_read_refuses_voids(void)
{
	float h[3 * 3];
	struct cs_terrain t, r;
	small_terrain(&t, h, 3, 3);
	h[4] = NAN;
	struct cs_terrain_meta m = {.format = CS_TERRAIN_EXR, .nodata_policy = "fill=none"};
	CHECK(cs_terrain_write_as(tmp("void.exr"), &t, &m) == CS_OK);
	CHECK(cs_terrain_read(tmp("void.exr"), &r) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "1 of 9 heights are voids");
	m.format = CS_TERRAIN_R16;
	CHECK(cs_terrain_write_as(tmp("void.r16"), &t, &m) == CS_EINVAL);
	CHECK(access(tmp("void.r16"), F_OK) != 0);
}

static void terrain_r16_maps_range_to_16_bits(void)
{
	float h[4 * 2];
	struct cs_terrain t;
	small_terrain(&t, h, 4, 2);
	for (int i = 0; i < 8; i++)
		h[i] = i < 7 ? 100.0f * (i + 1) : 755.35f;
	t.min_m = 100;
	t.max_m = 755.35f;
	for (int flip = 0; flip < 2; flip++) {
		struct cs_terrain_meta m = {.format = CS_TERRAIN_R16, .r16_south_up = flip};
		CHECK(cs_terrain_write_as(tmp("t.r16"), &t, &m) == CS_OK);
		unsigned char *d = NULL, *j = NULL;
		size_t len = 0, jlen = 0;
		CHECK(cs_read_all(tmp("t.r16"), 1 << 20, &d, &len) == CS_OK);
		CHECK(cs_read_all(tmp("t.json"), 1 << 20, &j, &jlen) == CS_OK);
		CHECK(len == 16);
		if (len != 16 || j == NULL)
			return;
		double scale = (755.35f - 100.0) / 65535.0;
		for (int i = 0; i < 8; i++) {
			int src = flip ? (i < 4 ? i + 4 : i - 4) : i;
			unsigned v = d[2 * i] | (unsigned)d[2 * i + 1] << 8;
			CHECK_NEAR(100.0 + v * scale, h[src], scale / 2 + 1e-9);
		}
		CHECK(d[0 + 8 * flip] == 0 && d[14 - 8 * flip] == 0xff && d[15 - 8 * flip] == 0xff);
		j[jlen - 1] = '\0';
		CHECK_STR_CONTAINS((char *)j, flip ? "\"south-up\"" : "\"north-up\"");
		CHECK_STR_CONTAINS((char *)j, "\"uint16le\"");
		CHECK_STR_CONTAINS((char *)j, "\"offset\":\t100");
		free(d);
		free(j);
	}
}

static void terrain_sidecar_path_replaces_the_extension(void)
{
	char p[64];
	CHECK(cs_terrain_sidecar_path("a/b.c/t.exr", p, sizeof p) == CS_OK);
	CHECK(strcmp(p, "a/b.c/t.json") == 0);
	CHECK(cs_terrain_sidecar_path("a.b/terrain", p, sizeof p) == CS_OK);
	CHECK(strcmp(p, "a.b/terrain.json") == 0);
	CHECK(cs_terrain_sidecar_path(".hidden", p, sizeof p) == CS_OK);
	CHECK(strcmp(p, ".hidden.json") == 0);
	CHECK(cs_terrain_sidecar_path("x.json", p, sizeof p) == CS_EINVAL);
	CHECK(cs_terrain_sidecar_path("dir/", p, sizeof p) == CS_EINVAL);
	CHECK(cs_terrain_sidecar_path("abcdefgh.exr", p, 12) == CS_EINVAL);
}

static void terrain_write_to_unwritable_place_leaves_nothing(void)
{
	float h[2 * 2];
	struct cs_terrain t;
	small_terrain(&t, h, 2, 2);
	char dir[600];
	snprintf(dir, sizeof dir, "%s/ro", tmpdir);
	mkdir(dir, 0755);
	snprintf(dir, sizeof dir, "%s/ro/missing/t.exr", tmpdir);
	CHECK(cs_terrain_write(dir, &t, NULL, NULL, NULL) == CS_EIO);
	snprintf(dir, sizeof dir, "%s/ro", tmpdir);
	CHECK(count_files(dir) == 0);
	/* the sidecar cannot be written: the data file must not appear */
	snprintf(dir, sizeof dir, "%s/ro/u.json", tmpdir);
	mkdir(dir, 0755);
	snprintf(dir, sizeof dir, "%s/ro/u.exr", tmpdir);
	CHECK(cs_terrain_write(dir, &t, NULL, NULL, NULL) == CS_EIO);
	CHECK_STR_CONTAINS(cs_errmsg(), "Is a directory");
	CHECK(access(dir, F_OK) != 0);
}

static void terrain_height_is_bilinear_and_clamped(void)
{
	float h[3 * 2] = {0, 10, 20, 100, 110, 120};
	struct cs_terrain t = {.width = 3, .height = 2, .h = h};
	CHECK_NEAR(cs_terrain_height(&t, 0.5, 0.5), 55.0, 1e-9);
	CHECK_NEAR(cs_terrain_height(&t, 1.25, 0.0), 12.5, 1e-9);
	CHECK_NEAR(cs_terrain_height(&t, 2.0, 1.0), 120.0, 1e-9);
	CHECK_NEAR(cs_terrain_height(&t, -5.0, 9.0), 100.0, 1e-9);
	CHECK_NEAR(cs_terrain_height(&t, 7.0, -1.0), 20.0, 1e-9);
	CHECK_NEAR(cs_terrain_height(&t, NAN, NAN), 0.0, 1e-9);
	float one = 42.0f;
	struct cs_terrain p = {.width = 1, .height = 1, .h = &one};
	CHECK_NEAR(cs_terrain_height(&p, 0.3, 0.7), 42.0, 1e-9);
}

static void exr_reads_one_channel_of_half_or_float(void)
{
	float px[3 * 2 * 2];
	for (int i = 0; i < 12; i++)
		px[i] = 0.5f * i;
	const struct cs_exr_channel ch[2] = {{"Y", 0, px, 2}, {"Z", 1, px + 1, 2}};
	CHECK(cs_exr_write(tmp("two.exr"), 3, 2, ch, 2, NULL, 0, 1) == CS_OK);
	unsigned char *d = NULL;
	size_t len = 0;
	CHECK(cs_read_all(tmp("two.exr"), 1 << 20, &d, &len) == CS_OK);
	int w = 0, h = 0;
	float *y = NULL;
	CHECK(cs_exr_read_float_channel(d, len, "two.exr", "Y", &w, &h, &y) == CS_OK);
	CHECK(w == 3 && h == 2);
	for (int i = 0; y && i < 6; i++)
		CHECK(y[i] == px[2 * i]);
	free(y);
	CHECK(cs_exr_read_float_channel(d, len, "two.exr", "Z", &w, &h, &y) == CS_OK);
	for (int i = 0; y && i < 6; i++)
		CHECK(y[i] == px[2 * i + 1]);
	free(y);
	CHECK(cs_exr_read_float_channel(d, len, "two.exr", "Q", &w, &h, &y) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "two.exr: no channel Q");
	CHECK(cs_exr_read_float_channel(d, len / 2, "half.exr", "Y", &w, &h, &y) == CS_EDATA);
	CHECK(y == NULL);
	free(d);
}

static void fill_nearest_takes_the_closest_valid_sample(void)
{
	enum { W = 37, H = 23 };
	float h[W * H];
	unsigned seed = 5;
	for (int i = 0; i < W * H; i++) /* unique values name their sample */
		h[i] = t_uniform(&seed, 0, 1) < 0.08 ? (float)i : NAN;
	float orig[W * H];
	memcpy(orig, h, sizeof h);
	CHECK(cs_dem_fill_nearest(h, W, H) == CS_OK);
	int worst = 0;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			int i = y * W + x, best = 1 << 30;
			for (int j = 0; j < W * H; j++)
				if (!isnan(orig[j])) {
					int dx = j % W - x, dy = j / W - y;
					best = dx * dx + dy * dy < best ? dx * dx + dy * dy : best;
				}
			int s = (int)h[i], dx = s % W - x, dy = s / W - y;
			CHECK(!isnan(h[i]) && !isnan(orig[s]));
			worst += dx * dx + dy * dy != best;
		}
	CHECK(worst == 0);
	float none[4] = {NAN, NAN, NAN, NAN};
	CHECK(cs_dem_fill_nearest(none, 2, 2) == CS_EDATA);
}

static void hillshade_of_planes_is_lambertian(void)
{
	enum { W = 6, H = 5 };
	float h[W * H];
	unsigned char out[W * H];
	struct cs_hillshade s = {315, 45, 1, 1};
	for (int i = 0; i < W * H; i++)
		h[i] = 100.0f;
	cs_dem_hillshade(h, W, H, 10, 10, &s, out);
	for (int i = 0; i < W * H; i++)
		CHECK(out[i] == (int)lrint(1 + 254 * sin(45 * CS_PI / 180)));
	/* rising 1 m per 1 m to the east: normal (-1, 0, 1)/sqrt 2; sun from
	 * the west at 30 degrees: cos = (cos30 + sin30)/sqrt 2 */
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++)
			h[y * W + x] = (float)(10.0 * x);
	s = (struct cs_hillshade){270, 30, 1, 1};
	cs_dem_hillshade(h, W, H, 10, 10, &s, out);
	double want = 1 + 254 * (cos(CS_PI / 6) + 0.5) / sqrt(2.0);
	CHECK(abs(out[2 * W + 2] - (int)lrint(want)) == 0);
	/* the sun on the other side: in shadow, 1 */
	s.azimuth_deg = 90;
	s.altitude_deg = 20;
	cs_dem_hillshade(h, W, H, 10, 10, &s, out);
	CHECK(out[2 * W + 2] == 1);
	h[2 * W + 2] = NAN;
	cs_dem_hillshade(h, W, H, 10, 10, &s, out);
	CHECK(out[1 * W + 1] == 0 && out[3 * W + 3] == 0 && out[2 * W + 4] != 0);
}

/* ---- terrainprep on GDAL's test DEMs ---------------------------------- */

/* What the last prep() produced. */
static struct cs_terrainprep_result prep_res;

/* Runs terrainprep on one input into res; says why when it fails
 * unexpectedly. */
static int prep(struct cs_terrainprep_opts *o, const char *in, int want)
{
	static const char *inputs[1];
	inputs[0] = in;
	o->inputs = inputs;
	o->ninputs = 1;
	int rc = cs_terrainprep_run(o, &prep_res);
	if (rc != want)
		printf("  terrainprep gave %d, expected %d: %s\n", rc, want, cs_errmsg());
	return rc;
}

static void terrainprep_n43_to_utm17_at_1000m(void)
{
	const char *n43 = dem("n43.dt0");
	if (n43 == NULL)
		SKIP("%.200s/dem/n43.dt0 is absent", datadir);
	struct cs_terrainprep_opts o;
	cs_terrainprep_defaults(&o);
	o.res_m = 1000;
	o.output = tmp("n43.exr");
	CHECK(prep(&o, n43, CS_OK) == CS_OK);
	const struct cs_terrain *t = &prep_res.terrain;
	CHECK(t->width == 83 && t->height == 113);
	CHECK(t->epsg == 32617);
	CHECK_NEAR(t->min_m, 75.0, 1e-6);
	CHECK_NEAR(t->max_m, 456.18, 0.01);    /* gdalwarp -r bilinear: 456.18 */
	CHECK_NEAR(t->origin_x, 579834.611, 0.001);
	CHECK_NEAR(t->origin_y, 4874288.239, 0.001);
	CHECK(strcmp(prep_res.resampling_used, "bilinear") == 0);
	CHECK(prep_res.voids > 0 && prep_res.voids < 83 * 113 / 20); /* the warped tile's margins */
	CHECK_NEAR(t->center_lat, 43.5, 0.01);
	CHECK_NEAR(t->center_lon, -79.5, 0.01);
	struct cs_terrain r;
	CHECK(cs_terrain_read(tmp("n43.exr"), &r) == CS_OK);
	CHECK(r.width == 83 && r.height == 113 && r.max_m == t->max_m);
	CHECK(r.h && memcmp(r.h, t->h, sizeof(float) * 83 * 113) == 0);
	cs_terrain_free(&r);
	cs_terrainprep_result_free(&prep_res);
}

/* Our hillshade of the n43 heightfield against GDALDEMProcessing's on the
 * same grid (the Float32 GeoTIFF we wrote): interior pixels only, as
 * gdaldem leaves the border 0 without -compute_edges. */
static int hillshade_vs_gdaldem(const char *n43, double az, double alt, double z,
				double res)
{
	struct cs_terrainprep_opts o;
	cs_terrainprep_defaults(&o);
	o.res_m = res;
	o.output = tmp("hs.tif");
	o.format = CS_TERRAIN_TIF;
	o.hillshade = tmp("hs.png");
	o.azimuth_deg = az;
	o.altitude_deg = alt;
	o.z_factor = z;
	if (prep(&o, n43, CS_OK) != CS_OK)
		return 999;
	cs_terrainprep_result_free(&prep_res);
	char azs[32], alts[32], zs[32];
	snprintf(azs, sizeof azs, "%g", az);
	snprintf(alts, sizeof alts, "%g", alt);
	snprintf(zs, sizeof zs, "%g", z);
	char *argv[] = {"-of", "MEM", "-az", azs, "-alt", alts, "-z", zs, "-s", "1", NULL};
	GDALDEMProcessingOptions *opts = GDALDEMProcessingOptionsNew(argv, NULL);
	GDALDatasetH src = GDALOpen(tmp("hs.tif"), GA_ReadOnly);
	GDALDatasetH ours = GDALOpen(tmp("hs.png"), GA_ReadOnly);
	GDALDatasetH ref = src && opts ? GDALDEMProcessing("", src, "hillshade", NULL, opts, NULL)
				       : NULL;
	int worst = 999;
	if (ref && ours) {
		int w = GDALGetRasterXSize(ref), h = GDALGetRasterYSize(ref);
		unsigned char *a = malloc((size_t)w * h), *b = malloc((size_t)w * h);
		if (GDALGetRasterXSize(ours) == w && GDALGetRasterYSize(ours) == h &&
		    GDALRasterIO(GDALGetRasterBand(ref, 1), GF_Read, 0, 0, w, h, a, w, h,
				 GDT_Byte, 0, 0) == CE_None &&
		    GDALRasterIO(GDALGetRasterBand(ours, 1), GF_Read, 0, 0, w, h, b, w, h,
				 GDT_Byte, 0, 0) == CE_None) {
			worst = 0;
			for (int y = 1; y < h - 1; y++)
				for (int x = 1; x < w - 1; x++) {
					int d = abs(a[y * w + x] - b[y * w + x]);
					worst = d > worst ? d : worst;
				}
		}
		free(a);
		free(b);
	}
	GDALDEMProcessingOptionsFree(opts);
	GDALClose(ref);
	GDALClose(ours);
	GDALClose(src);
	return worst;
}

static void hillshade_agrees_with_gdaldem_on_n43(void)
{
	const char *n43 = dem("n43.dt0");
	if (n43 == NULL)
		SKIP("%.200s/dem/n43.dt0 is absent", datadir);
	int d1 = hillshade_vs_gdaldem(n43, 315, 45, 1, 1000);
	int d2 = hillshade_vs_gdaldem(n43, 100, 30, 10, 0);
	int d3 = hillshade_vs_gdaldem(n43, 200, 60, 30, 500);
	printf("  max grey-level difference to gdaldem: %d, %d, %d\n", d1, d2, d3);
	CHECK(d1 <= 1 && d2 <= 1 && d3 <= 1);
}

static void terrainprep_needs_s_srs_without_crs(void)
{
	const char *asc = dem("nodata_float.asc");
	if (asc == NULL)
		SKIP("%.200s/dem/nodata_float.asc is absent", datadir);
	struct cs_terrainprep_opts o;
	cs_terrainprep_defaults(&o);
	o.output = tmp("nf.exr");
	CHECK(prep(&o, asc, CS_EDATA) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "has no coordinate reference system");
	CHECK_STR_CONTAINS(cs_errmsg(), "--s-srs");
	CHECK(access(tmp("nf.exr"), F_OK) != 0 && access(tmp("nf.json"), F_OK) != 0);
	o.s_srs = "EPSG:32611";
	CHECK(prep(&o, asc, CS_OK) == CS_OK);
	CHECK(prep_res.terrain.width == 5 && prep_res.terrain.height == 5 && prep_res.terrain.epsg == 32611);
	CHECK(prep_res.terrain.min_m == 107 && prep_res.terrain.max_m == 156 && prep_res.voids == 0);
	CHECK(prep_res.terrain.pixel_x_m == 60 && prep_res.terrain.origin_y == 3750120 + 300);
	cs_terrainprep_result_free(&prep_res);
	o.s_srs = "EPSG:999999999";
	CHECK(prep(&o, asc, CS_EINVAL) == CS_EINVAL);
}

static void terrainprep_fill_modes_on_withnodata(void)
{
	const char *asc = dem("withnodata.asc");
	if (asc == NULL)
		SKIP("%.200s/dem/withnodata.asc is absent", datadir);
	struct cs_terrainprep_opts o;
	cs_terrainprep_defaults(&o);
	o.s_srs = "EPSG:32611";
	o.output = tmp("wn.tif");
	o.format = CS_TERRAIN_TIF;
	/* nearest: the void (upper left, -999) takes its neighbours' 0 */
	CHECK(prep(&o, asc, CS_OK) == CS_OK && prep_res.voids == 1);
	CHECK(prep_res.terrain.h && prep_res.terrain.h[0] == 0.0f && prep_res.terrain.max_m == 0.0);
	cs_terrainprep_result_free(&prep_res);
	o.fill = CS_FILL_VALUE;
	o.fill_value = 123.5;
	CHECK(prep(&o, asc, CS_OK) == CS_OK);
	CHECK(prep_res.terrain.h && prep_res.terrain.h[0] == 123.5f && prep_res.terrain.h[3] == 0.0f);
	CHECK(prep_res.terrain.max_m == 123.5);
	cs_terrainprep_result_free(&prep_res);
	o.fill = CS_FILL_NONE;
	CHECK(prep(&o, asc, CS_OK) == CS_OK);
	CHECK(prep_res.terrain.h && isnan(prep_res.terrain.h[0]) && prep_res.terrain.h[1] == 0.0f);
	cs_terrainprep_result_free(&prep_res);
	o.max_void_fraction = 0.2; /* 1 of 4 is 25% */
	CHECK(prep(&o, asc, CS_EDATA) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "25.0% of the output samples are voids");
	/* --src-nodata none: -999 is a height like any other */
	o.max_void_fraction = 0.5;
	o.have_src_nodata = o.src_nodata_none = 1;
	CHECK(prep(&o, asc, CS_OK) == CS_OK && prep_res.voids == 0 && prep_res.terrain.min_m == -999.0);
	cs_terrainprep_result_free(&prep_res);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(terrain_round_trips_exr_and_sidecar),
	CASE(terrain_read_reports_missing_and_corrupt_sidecars),
	CASE(terrain_read_refuses_voids),
	CASE(terrain_r16_maps_range_to_16_bits),
	CASE(terrain_sidecar_path_replaces_the_extension),
	CASE(terrain_write_to_unwritable_place_leaves_nothing),
	CASE(terrain_height_is_bilinear_and_clamped),
	CASE(exr_reads_one_channel_of_half_or_float),
	CASE(fill_nearest_takes_the_closest_valid_sample),
	CASE(hillshade_of_planes_is_lambertian),
	CASE(terrainprep_n43_to_utm17_at_1000m),
	CASE(hillshade_agrees_with_gdaldem_on_n43),
	CASE(terrainprep_needs_s_srs_without_crs),
	CASE(terrainprep_fill_modes_on_withnodata),
};

int main(void)
{
	snprintf(tmpdir, sizeof tmpdir, "%s/cs-test-terrain.XXXXXX",
		 getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	if (mkdtemp(tmpdir) == NULL) {
		perror("mkdtemp");
		return 1;
	}
	find_data();
	T_RUN_TABLE(t_cases);
	char cmd[300];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
	if (system(cmd) != 0)
		return 1;
	TEST_EXIT();
}
