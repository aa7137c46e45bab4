/* Robustness (issue 12): hostile headers refused before they allocate,
 * values at the edge of what the types hold, the camera at exactly
 * ground height, and the reproducers the fuzz targets (tests/fuzz/)
 * found, kept here so that the normal suite catches a regression. */
#include "core/err.h"
#include "core/fileio.h"
#include "core/sphere.h"
#include "core/time.h"
#include "io/exr.h"
#include "io/image.h"
#include "noise/volume.h"
#include "render/render.h"
#include "render/scene.h"
#include "terrain/heightfield.h"
#include "terrain/terrain.h"
#include "weather/provider.h"
#include "weather/wx.h"
#include "test.h"

#include <float.h>
#include <stdint.h>
#include <stdlib.h>
#include <unistd.h>

static const char *tmp_path(const char *name)
{
	static char buf[4][256];
	static int k;
	k = (k + 1) % 4;
	snprintf(buf[k], sizeof buf[k], "%s/cs-robust-%ld-%s",
		 getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp", (long)getpid(), name);
	return buf[k];
}

static unsigned char *slurp(const char *path, size_t *len)
{
	unsigned char *d = NULL;
	if (cs_read_all(path, (size_t)1 << 26, &d, len) != CS_OK)
		return NULL;
	return d;
}

/* Overwrites the int32 values of attribute name in an EXR header in
 * memory (little endian), as a hostile file would have them. */
static int patch_attr(unsigned char *b, size_t len, const char *name,
		      const int32_t *v, int n)
{
	size_t at = 8;
	while (at < len && b[at] != 0) {
		const char *an = (const char *)b + at;
		size_t nl = strnlen(an, len - at);
		const char *ty = an + nl + 1;
		size_t vat = (size_t)((const unsigned char *)ty - b) + strlen(ty) + 1;
		int32_t size;
		memcpy(&size, b + vat, 4);
		if (strcmp(an, name) == 0) {
			for (int i = 0; i < n && (i + 1) * 4 <= size; i++)
				for (int k = 0; k < 4; k++)
					b[vat + 4 + i * 4 + k] = (unsigned char)((uint32_t)v[i] >> (8 * k));
			return 1;
		}
		at = vat + 4 + (size_t)size;
	}
	return 0;
}

/* The heightfield: a data window of 268435455 x 1 in a file of a
 * few hundred bytes made the reader ask for 33 GiB of decoding blocks. */
static void heightfield_header_claiming_more_than_the_file_holds_is_refused(void)
{
	float z[16];
	for (int i = 0; i < 16; i++)
		z[i] = (float)i;
	struct cs_exr_channel ch = {"Y", 1, z, 1};
	const char *p = tmp_path("hf.exr");
	CHECK(cs_exr_write(p, 4, 4, &ch, 1, NULL, 0, 1) == CS_OK);
	size_t len = 0;
	unsigned char *b = slurp(p, &len);
	CHECK(b != NULL);
	if (b == NULL)
		return;
	int32_t dw[4] = {0, 0, 268435454, 0};
	CHECK(patch_attr(b, len, "dataWindow", dw, 4));
	int w, h;
	float *px = NULL;
	CHECK(cs_exr_read_float_channel(b, len, "hostile.exr", "Y", &w, &h, &px) == CS_EDATA);
	CHECK(px == NULL);
	CHECK_STR_CONTAINS(cs_errmsg(), "hostile.exr: the header claims 268435455x1 pixels");
	CHECK_STR_CONTAINS(cs_errmsg(), "can hold at most");
	/* the same through the heightfield reader, sidecar or not */
	struct cs_terrain t;
	CHECK(cs_terrain_read_mem(b, len, "hostile.exr", "{}", 2, "hostile.json", &t) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "hostile.exr: the header claims");
	free(b);
	unlink(p);
}

/* The bound is the compression's: deflate holds at most 1032 bytes a byte
 * (RFC 1951), an uncompressed file no more than its size. */
static void exr_bound_follows_the_compression(void)
{
	CHECK(cs_exr_max_pixel_bytes(1000, EXR_COMPRESSION_NONE) == 1000);
	CHECK(cs_exr_max_pixel_bytes(1000, EXR_COMPRESSION_ZIP) == 1032000);
	CHECK(cs_exr_max_pixel_bytes(1000, EXR_COMPRESSION_RLE) == 64000);
	CHECK(cs_exr_max_pixel_bytes(SIZE_MAX / 2, EXR_COMPRESSION_ZIP) == SIZE_MAX);
	/* a real 64x64 float image of zeros (as compressible as it gets)
	 * still reads: the bound does not refuse honest files */
	static float zero[64 * 64];
	struct cs_exr_channel ch = {"Y", 1, zero, 1};
	const char *p = tmp_path("zero.exr");
	CHECK(cs_exr_write(p, 64, 64, &ch, 1, NULL, 0, 1) == CS_OK);
	size_t len = 0;
	unsigned char *b = slurp(p, &len);
	int w = 0, h = 0;
	float *px = NULL;
	CHECK(b && cs_exr_read_float_channel(b, len, p, "Y", &w, &h, &px) == CS_OK);
	CHECK(w == 64 && h == 64 && px && px[4095] == 0.0f);
	free(px);
	free(b);
	unlink(p);
}

/* The noise volume: a 1024^3 claim got a 16 GiB calloc before its
 * other attributes were read; 512^3 is within the voxel limit but not
 * what a few kilobytes can hold. */
static void noise_header_claiming_a_huge_volume_is_refused_before_allocating(void)
{
	struct cs_volume v;
	CHECK(cs_volume_new(&v, 8, 8) == CS_OK);
	const char *p = tmp_path("n.exr");
	CHECK(cs_volume_write_exr(&v, p, 0, 1) == CS_OK);
	cs_volume_free(&v);
	size_t len = 0;
	unsigned char *b = slurp(p, &len);
	CHECK(b != NULL);
	if (b == NULL)
		return;
	unsigned char *c = malloc(len);
	memcpy(c, b, len);
	int32_t size[3] = {1024, 1024, 1024}, dw[4] = {0, 0, 1023, 1024 * 1024 - 1};
	CHECK(patch_attr(b, len, "cloudscapeVolumeSize", size, 3));
	CHECK(patch_attr(b, len, "dataWindow", dw, 4));
	CHECK(cs_volume_read_exr_mem(b, len, "huge.exr", &v) == CS_EDATA);
	CHECK(v.data == NULL);
	CHECK_STR_CONTAINS(cs_errmsg(), "huge.exr: cloudscapeVolumeSize 1024x1024x1024 is more voxels");
	int32_t size2[3] = {512, 512, 512}, dw2[4] = {0, 0, 511, 512 * 512 - 1};
	CHECK(patch_attr(c, len, "cloudscapeVolumeSize", size2, 3));
	CHECK(patch_attr(c, len, "dataWindow", dw2, 4));
	CHECK(cs_volume_read_exr_mem(c, len, "big.exr", &v) == CS_EDATA);
	CHECK(v.data == NULL);
	CHECK_STR_CONTAINS(cs_errmsg(), "big.exr: the header claims 512x262144 pixels");
	free(b);
	free(c);
	unlink(p);
}

/* A PNG header claiming 10000x10000 in a 60-byte file. */
static void png_header_claiming_more_than_the_file_holds_is_refused(void)
{
	uint8_t px[4 * 4 * 3] = {0};
	const char *p = tmp_path("s.png");
	CHECK(cs_png_write(p, 4, 4, 3, px) == CS_OK);
	size_t len = 0;
	unsigned char *b = slurp(p, &len);
	CHECK(b != NULL && len > 24);
	if (b == NULL)
		return;
	/* IHDR width and height, big endian, at bytes 16..23 (PNG spec 11.2.2);
	 * libpng checks the CRC: recompute it as the spec does */
	unsigned char dim[8] = {0, 0, 0x27, 0x10, 0, 0, 0x27, 0x10};
	memcpy(b + 16, dim, 8);
	uint32_t crc = 0xffffffffu;
	for (size_t i = 12; i < 29; i++) {
		crc ^= b[i];
		for (int k = 0; k < 8; k++)
			crc = crc & 1 ? 0xedb88320u ^ (crc >> 1) : crc >> 1;
	}
	crc ^= 0xffffffffu;
	for (int k = 0; k < 4; k++)
		b[29 + k] = (unsigned char)(crc >> (24 - 8 * k));
	uint8_t *rgb = NULL;
	int w, h;
	CHECK(cs_png_read_rgb8_mem(b, len, "wide.png", &rgb, &w, &h) == CS_EDATA);
	CHECK(rgb == NULL);
	CHECK_STR_CONTAINS(cs_errmsg(), "wide.png: the header claims 10000x10000 pixels");
	free(b);
	unlink(p);
}

/* The sidecar's EPSG code went through (int) after the range check had
 * rejected it (UBSan: 1e10 is outside int); a fraction was truncated. */
static void sidecar_epsg_is_checked_before_its_cast(void)
{
	float z[4] = {1, 2, 3, 4};
	struct cs_terrain t = {0};
	t.width = 2, t.height = 2, t.h = z;
	t.pixel_x_m = t.pixel_y_m = 10;
	t.min_m = 1, t.max_m = 4;
	t.epsg = 32632;
	t.crs_wkt = "LOCAL_CS[\"x\"]";
	const char *p = tmp_path("e.exr"), *js = tmp_path("e.json");
	CHECK(cs_terrain_write(p, &t, "test", "none", "fill=none") == CS_OK);
	size_t elen = 0, jlen = 0;
	unsigned char *exr = slurp(p, &elen), *json = slurp(js, &jlen);
	CHECK(exr && json);
	if (!exr || !json)
		return;
	char *at = strstr((char *)json, "\"epsg\"");
	at = at ? strstr(at, "32632") : NULL; /* the value, however indented */
	CHECK(at != NULL);
	static const char *const bad[] = {"1e10", "4326.7", "-1", "0"};
	static const char *const why[] = {"outside 1..999999", "4326.7 is not a whole number",
					  "outside 1..999999", "outside 1..999999"};
	for (int i = 0; i < 4 && at; i++) {
		char buf[8192];
		snprintf(buf, sizeof buf, "%.*s%s%s", (int)(at - (char *)json),
			 (char *)json, bad[i], at + 5);
		struct cs_terrain back;
		CHECK(cs_terrain_read_mem(exr, elen, p, buf, strlen(buf), "e.json", &back) == CS_EDATA);
		CHECK_STR_CONTAINS(cs_errmsg(), why[i]);
	}
	struct cs_terrain back;
	CHECK(cs_terrain_read_mem(exr, elen, p, (char *)json, jlen, "e.json", &back) == CS_OK);
	CHECK(back.epsg == 32632);
	cs_terrain_free(&back);
	free(exr);
	free(json);
	unlink(p);
	unlink(js);
}

/* The header promises any finite coordinate: 1e308 * 64 overflowed to Inf
 * and the conversion to long was undefined.  An integer coordinate is a
 * whole number of periods: the sample at 0. */
static void volume_sample_takes_any_finite_coordinate(void)
{
	struct cs_volume v;
	CHECK(cs_volume_new(&v, 16, 8) == CS_OK);
	for (size_t i = 0; i < (size_t)16 * 16 * 8 * 4; i++)
		v.data[i] = (float)((i * 2654435761u) % 1000) / 1000.0f;
	const double big[] = {1e308, -1e308, DBL_MAX, -DBL_MAX, 0x1p60, 1e20};
	for (int i = 0; i < 6; i++) {
		float a = cs_volume_sample(&v, 1, big[i], 0.3, 0.7);
		CHECK_NEAR(a, cs_volume_sample(&v, 1, 0.0, 0.3, 0.7), 0.0);
		float o[4];
		cs_volume_sample4(&v, 0.3, big[i], big[i], o);
		CHECK_NEAR(o[2], cs_volume_sample(&v, 2, 0.3, 0.0, 0.0), 0.0);
	}
	/* a fraction that a double still holds at 2^40 is kept */
	CHECK_NEAR(cs_volume_sample(&v, 0, 0x1p41 + 0.25, 0.5, 0.5),
		   cs_volume_sample(&v, 0, 0.25, 0.5, 0.5), 1e-6);
	cs_volume_free(&v);
}

/* A one-byte file "x": the message quotes what is there, nothing more
 * (it once quoted 24 bytes from before the buffer's start). */
static void malformed_provider_message_quotes_only_the_file(void)
{
	char *x = malloc(1);
	x[0] = 'x';
	struct cs_problems pr;
	CHECK(cs_provider_check(x, 1, &pr) == CS_EDATA);
	CHECK(pr.count >= 1);
	CHECK_STR_CONTAINS(pr.msg[0], "malformed JSON at byte offset 0 near \"x\"");
	struct cs_series s;
	CHECK(cs_provider_parse(x, 1, "x.json", &s) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "near \"x\"");
	cs_series_free(&s);
	free(x);
}

/* A provider's file where a weather state belongs says what it is. */
static void provider_file_as_a_state_says_what_it_is(void)
{
	static const char om[] =
		"{\"latitude\":46.94,\"longitude\":7.44,\"utc_offset_seconds\":0,"
		"\"elevation\":540,\"hourly_units\":{\"time\":\"unixtime\","
		"\"cloud_cover_low\":\"%\",\"cloud_cover_mid\":\"%\",\"cloud_cover_high\":\"%\","
		"\"precipitation\":\"mm\",\"wind_speed_10m\":\"m/s\",\"wind_direction_10m\":"
		"\"\xc2\xb0\"},\"hourly\":{\"time\":[1623628800,1623632400],"
		"\"cloud_cover_low\":[1,2],\"cloud_cover_mid\":[3,4],\"cloud_cover_high\":[5,6],"
		"\"precipitation\":[0,0],\"wind_speed_10m\":[1,2],\"wind_direction_10m\":[0,359]}}";
	struct cs_wx wx;
	CHECK(cs_wx_parse(om, strlen(om), &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "an Open-Meteo response");
	CHECK_STR_CONTAINS(cs_errmsg(), "wxinterp --at TIME FILE");
	/* any other object keeps the field's message */
	CHECK(cs_wx_parse("{\"a\":1}", 7, &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "schema: missing");
}

/* Times in messages keep their fraction: 22:00:00.5 is not 22:00:00. */
static void message_times_keep_their_fraction(void)
{
	double t;
	CHECK(cs_time_parse("2021-06-14T22:00:00.5Z", &t) == CS_OK);
	CHECK(strcmp(cs_time_text(t).s, "2021-06-14T22:00:00.5Z") == 0);
	CHECK(strcmp(cs_time_text(t - 0.5).s, "2021-06-14T22:00:00Z") == 0);
	CHECK(strcmp(cs_time_text(t + 0.2495).s, "2021-06-14T22:00:00.75Z") == 0);
	CHECK(strcmp(cs_time_text(t + 0.4999).s, "2021-06-14T22:00:01Z") == 0);
}

/* A black frame asked for 32 EV (log2(4 / 1e-9)); the documented range is
 * -20..20. */
static void auto_exposure_stays_in_the_documented_range(void)
{
	float black[4 * 5] = {0}, sun[4 * 5];
	for (int i = 0; i < 20; i++)
		sun[i] = 1e12f;
	CHECK_NEAR(cs_auto_exposure_ev(black, 5, 4), 20.0, 0.0);
	CHECK_NEAR(cs_auto_exposure_ev(sun, 5, 4), -20.0, 0.0);
	/* within the range it is log2(4 / L): L = 1 kcd/m^2 gives 2 EV */
	float one[5] = {1, 1, 1, 1, 0};
	CHECK_NEAR(cs_auto_exposure_ev(one, 5, 1), 2.0, 1e-6);
}

/* ---- the camera at exactly ground height ---------------------------- */

static void ground_scene(struct cs_scene *sc)
{
	memset(sc, 0, sizeof *sc);
	sc->earth_radius_m = CS_EARTH_RADIUS_M;
	double e = 30.0 * CS_PI / 180.0;
	sc->sun_dir = v3(0.0, cos(e), sin(e));
	cs_sky_init(&sc->sky, sc->sun_dir, 3.0);
	memcpy(sc->sun_illuminance, sc->sky.sun_illuminance, sizeof sc->sun_illuminance);
	memcpy(sc->ambient_up, sc->sky.ambient_up, sizeof sc->ambient_up);
	sc->effects = CS_FX_SUN | CS_FX_SKY | CS_FX_GROUND;
	sc->ground_alt_m = 0.0;
	sc->ground_albedo[0] = sc->ground_albedo[1] = sc->ground_albedo[2] = 0.2;
}

/* Where a ray from height h at elevation e (radians, below 0 = down)
 * meets the sphere of radius R: the nearer root of |o + t d - c| = R,
 * written without cancellation, or -1 when it misses.  Independent of the
 * renderer's own code. */
static double ground_distance(double h, double e)
{
	double R = CS_EARTH_RADIUS_M, s = -sin(e); /* > 0 looking down */
	double c = h * (2.0 * R + h), b = (R + h) * s;
	if (s <= 0.0 || b * b < c)
		return -1.0;
	return c / (b + sqrt(b * b - c));
}

/* The rule: the ground is solid.  From exactly ground height a ray below
 * the horizontal meets it at once and one above it sees the sky; from
 * 1 um and 2 m the horizon dips by sqrt(2 h / R) and a ray just below it
 * meets the ground where the sphere says, one just above it the sky. */
static void camera_at_ground_height_sees_sky_above_and_ground_below(void)
{
	static struct cs_scene sc;
	ground_scene(&sc);
	struct cs_render_settings s = {8, 8, 4, 1, 0, 0.0, 0, 0.0, 0, 0, 0, 1, 0.0, 0, CS_GROUND_SKY_COLUMNS, 0};
	const double hs[] = {0.0, 1e-6, 2.0};
	for (int i = 0; i < 3; i++) {
		double h = hs[i], dip = sqrt(2.0 * h / CS_EARTH_RADIUS_M);
		const double margins[] = {1e-4, 1e-7};
		for (int m = 0; m < 2; m++) {
			struct cs_render_stats st = {0};
			struct cs_ray_result up, down;
			double eu = -dip + margins[m], ed = -dip - margins[m];
			cs_v3 o = v3(0, 0, h);
			cs_render_ray(&sc, &s, o, v3(cos(eu), 0, sin(eu)), 0.5, &st, &up);
			cs_render_ray(&sc, &s, o, v3(cos(ed), 0, sin(ed)), 0.5, &st, &down);
			if (up.depth_m != CS_SKY_DEPTH_M)
				printf("  h %g m, %g rad above the horizon: depth %g\n", h,
				       margins[m], up.depth_m);
			CHECK(up.depth_m == CS_SKY_DEPTH_M);
			double want = ground_distance(h, ed);
			CHECK(want >= 0.0);
			/* a double resolves 9.3e-10 m at the Earth's radius: at
			 * 1 um the height itself is known to 1e-3 */
			double rel = h > 0.0 && h < 1e-3 ? 2e-3 : 1e-6;
			CHECK_NEAR(down.depth_m, want, 1e-9 + rel * want);
			/* the sky above is brighter than the grey ground below */
			CHECK(up.rgb[2] > down.rgb[2]);
		}
	}
}

/* The same rule on the terrain: an eye exactly on a flat heightfield at
 * 500 m sees the terrain below the horizontal at once and not above it. */
static void camera_on_the_terrain_sees_it_below_only(void)
{
	enum { W = 41 };
	static float z[W * W];
	for (int i = 0; i < W * W; i++)
		z[i] = 500.0f;
	double a[3] = {20, 1 / 25.0, 0}, b[3] = {20, 0, -1 / 25.0};
	struct cs_hfield f;
	CHECK(cs_hfield_init(&f, z, W, W, a, b, CS_EARTH_RADIUS_M) == CS_OK);
	const double hs[] = {0.0, 1e-6, 2.0};
	for (int i = 0; i < 3; i++) {
		cs_v3 o = v3(0, 0, 500.0 + hs[i]);
		double t = -1;
		for (int k = 0; k < 2; k++) {
			double e = k ? -0.05 : 0.05;
			int hit = cs_hfield_intersect(&f, o, v3(cos(e), 0, sin(e)), 1e6, &t, NULL);
			if (k == 0 && hit)
				printf("  h %g m, 0.05 rad up: hit at %g m\n", hs[i], t);
			CHECK(k ? hit : !hit);
			if (k)
				CHECK_NEAR(t, hs[i] / sin(0.05), 1e-3 + 1e-3 * hs[i]);
		}
	}
	cs_hfield_free(&f);
}

static const struct t_case t_cases[] = {
	CASE(heightfield_header_claiming_more_than_the_file_holds_is_refused),
	CASE(exr_bound_follows_the_compression),
	CASE(noise_header_claiming_a_huge_volume_is_refused_before_allocating),
	CASE(png_header_claiming_more_than_the_file_holds_is_refused),
	CASE(sidecar_epsg_is_checked_before_its_cast),
	CASE(volume_sample_takes_any_finite_coordinate),
	CASE(malformed_provider_message_quotes_only_the_file),
	CASE(provider_file_as_a_state_says_what_it_is),
	CASE(message_times_keep_their_fraction),
	CASE(auto_exposure_stays_in_the_documented_range),
	CASE(camera_at_ground_height_sees_sky_above_and_ground_below),
	CASE(camera_on_the_terrain_sees_it_below_only),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
