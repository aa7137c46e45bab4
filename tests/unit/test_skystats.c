/* The statistics skycompare reports (io/skystats.c, io/picture.c,
 * apps/skycompare_run.c) against closed forms: the earth mover's distance
 * of a translated histogram is the translation, chi-squared is 0 for equal
 * and 1 for disjoint histograms, cloud fractions of pictures with known
 * cloud pixels are exact, an exposure change scales the mean luminance by
 * 2^EV and leaves the red/blue ratio alone, area resampling undoes an
 * integer enlargement exactly.  The sRGB decoding is written again here
 * from IEC 61966-2-1. */
#include "test.h"

#include "apps/skycompare_run.h"
#include "core/err.h"
#include "io/picture.h"
#include "io/skystats.h"

#include <stdint.h>
#include <stdlib.h>

static double ref_eotf(int level)
{
	double v = level / 255.0;
	return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
}

/* A w x h picture of one display colour; lin decoded as skycompare does
 * for PNG and JPEG. */
static void solid(struct cs_picture *p, int w, int h, int r, int g, int b)
{
	CHECK(cs_picture_alloc(p, w, h, 0) == CS_OK);
	for (int i = 0; i < w * h; i++) {
		int c[3] = {r, g, b};
		for (int k = 0; k < 3; k++) {
			p->srgb[i * 3 + k] = (uint8_t)c[k];
			p->lin[i * 3 + k] = (float)ref_eotf(c[k]);
		}
	}
}

static void set_px(struct cs_picture *p, int i, int r, int g, int b)
{
	int c[3] = {r, g, b};
	for (int k = 0; k < 3; k++) {
		p->srgb[i * 3 + k] = (uint8_t)c[k];
		p->lin[i * 3 + k] = (float)ref_eotf(c[k]);
	}
}

static void emd_of_a_translated_histogram_is_the_translation(void)
{
	long a[CS_SKY_BINS] = {0}, b[CS_SKY_BINS] = {0};
	unsigned s = 7;
	for (int k = 20; k < 200; k++)
		a[k] = (long)t_uniform(&s, 0, 1000);
	for (int shift = 0; shift <= 40; shift += 7) {
		memset(b, 0, sizeof b);
		for (int k = 0; k + shift < CS_SKY_BINS; k++)
			b[k + shift] = 3 * a[k]; /* normalisation: a count scale is no change */
		CHECK_NEAR(cs_hist_emd(a, b, CS_SKY_BINS), shift, 1e-9);
		CHECK_NEAR(cs_hist_emd(b, a, CS_SKY_BINS), shift, 1e-9);
	}
	CHECK_NEAR(cs_hist_chi2(a, a, CS_SKY_BINS), 0.0, 1e-15);
	/* two single bins i and j: |i - j| */
	long d1[CS_SKY_BINS] = {0}, d2[CS_SKY_BINS] = {0}, e[CS_SKY_BINS] = {0};
	d1[10] = 5, d2[250] = 1;
	CHECK_NEAR(cs_hist_emd(d1, d2, CS_SKY_BINS), 240.0, 1e-9);
	CHECK(isnan(cs_hist_emd(d1, e, CS_SKY_BINS)));
	CHECK(isnan(cs_hist_chi2(e, d1, CS_SKY_BINS)));
}

static void chi2_is_zero_equal_one_disjoint_and_a_third_between(void)
{
	long p[4] = {1, 1, 0, 0}, q[4] = {0, 0, 3, 5}, r[4] = {2, 0, 0, 0};
	CHECK_NEAR(cs_hist_chi2(p, p, 4), 0.0, 1e-15);
	CHECK_NEAR(cs_hist_chi2(p, q, 4), 1.0, 1e-12);
	/* (1/2, 1/2) against (1, 0): 0.5 ((1/2)^2/(3/2) + (1/2)^2/(1/2)) = 1/3 */
	CHECK_NEAR(cs_hist_chi2(p, r, 4), 1.0 / 3.0, 1e-12);
}

static void cloud_fraction_of_known_pixels_is_exact(void)
{
	/* 40 x 25: 137 grey cloud pixels (R/B = 1), 9 black (never
	 * classified), 50 not sky (a cloud colour the mask hides), the rest
	 * blue sky (linear R/B 0.14) */
	struct cs_picture p;
	solid(&p, 40, 25, 90, 140, 220);
	CHECK(cs_sky_mask_all(&p) == CS_OK);
	for (int i = 0; i < 137; i++)
		set_px(&p, 3 * i + 1, 200, 200, 200);
	for (int i = 0; i < 9; i++)
		set_px(&p, 900 + 2 * i, 0, 0, 0);
	for (int i = 950; i < 1000; i++) {
		set_px(&p, i, 210, 210, 210);
		p.sky[i] = 0;
	}
	struct cs_sky_stats s;
	unsigned char cls[1000];
	CHECK(cs_sky_stats(&p, CS_SKY_RB_THRESHOLD, cls, &s) == CS_OK);
	CHECK(s.sky_pixels == 950);
	CHECK(s.cls.sky_pixels == 941);
	CHECK(s.cls.cloud_pixels == 137);
	CHECK_NEAR(s.cls.cloud_fraction, 137.0 / 941.0, 1e-15);
	CHECK(cls[1] == CS_SKY_CLOUD && cls[0] == CS_SKY_CLEAR && cls[900] == CS_SKY_NONE &&
	      cls[960] == CS_SKY_NONE);
	/* the threshold splits at linear R/B: levels whose decoded ratio
	 * lies just under and just over 0.75 */
	int r_lo = 0, r_hi = 0;
	for (int r = 0; r < 256; r++) {
		double q = ref_eotf(r) / ref_eotf(200);
		if (q < 0.75)
			r_lo = r;
		else if (!r_hi)
			r_hi = r;
	}
	set_px(&p, 0, r_lo, 150, 200);
	set_px(&p, 3, r_hi, 150, 200);
	CHECK(cs_sky_stats(&p, CS_SKY_RB_THRESHOLD, cls, &s) == CS_OK);
	CHECK(cls[0] == CS_SKY_CLEAR && cls[3] == CS_SKY_CLOUD);
	CHECK(s.cls.cloud_pixels == 138);
	/* a higher threshold: the grey cloud (R/B = 1) stays, r_hi goes */
	CHECK(cs_sky_stats(&p, 0.9, cls, &s) == CS_OK);
	CHECK(s.cls.cloud_pixels == 137 && cls[3] == CS_SKY_CLEAR);
	cs_picture_free(&p);
}

static void luminance_and_colour_of_known_levels(void)
{
	/* 3 pixels: grey 0, 128, 255, and one (255, 0, 0) */
	struct cs_picture p;
	solid(&p, 4, 1, 0, 0, 0);
	set_px(&p, 1, 128, 128, 128);
	set_px(&p, 2, 255, 255, 255);
	set_px(&p, 3, 255, 0, 0);
	struct cs_sky_stats s;
	CHECK(cs_sky_stats(&p, CS_SKY_RB_THRESHOLD, NULL, &s) == CS_OK);
	double y128 = ref_eotf(128); /* 0.2158605 */
	CHECK_NEAR(y128, 0.2158605, 1e-7);
	CHECK_NEAR(s.mean_lum, (0.0 + y128 + 1.0 + 0.2126) / 4.0, 1e-12);
	/* median of 0, 0.2126, 0.2159, 1: the mean of the middle two */
	CHECK_NEAR(s.median_lum, (0.2126 + y128) / 2.0, 1e-12);
	CHECK_NEAR(s.mean_rgb[0], (0 + 128 + 255 + 255) / 4.0, 1e-12);
	CHECK_NEAR(s.mean_rgb[1], (0 + 128 + 255 + 0) / 4.0, 1e-12);
	CHECK_NEAR(s.median_rgb[0], 128, 0); /* lower median of 0 128 255 255 */
	CHECK_NEAR(s.median_rgb[2], 0, 0);   /* of 0 0 128 255 */
	CHECK(s.mean_lum_kcd_m2 < 0.0);      /* not an EXR */
	cs_picture_free(&p);
}

static void exposure_change_scales_luminance_and_keeps_cloud_fraction(void)
{
	/* an HDR "render": linear radiance, and the same 1 stop brighter */
	struct cs_picture a, b;
	CHECK(cs_picture_alloc(&a, 32, 16, 0) == CS_OK);
	CHECK(cs_picture_alloc(&b, 32, 16, 0) == CS_OK);
	unsigned st = 3;
	for (int i = 0; i < 32 * 16; i++)
		for (int k = 0; k < 3; k++) {
			a.lin[i * 3 + k] = (float)t_uniform(&st, 0.5, 12.0);
			b.lin[i * 3 + k] = 2.0f * a.lin[i * 3 + k];
		}
	a.hdr = b.hdr = 1;
	struct cs_sky_stats sa, sb;
	CHECK(cs_sky_stats(&a, CS_SKY_RB_THRESHOLD, NULL, &sa) == CS_OK);
	CHECK(cs_sky_stats(&b, CS_SKY_RB_THRESHOLD, NULL, &sb) == CS_OK);
	CHECK_NEAR(sb.mean_lum_kcd_m2 / sa.mean_lum_kcd_m2, 2.0, 1e-6);
	CHECK(sa.cls.cloud_pixels == sb.cls.cloud_pixels);
	CHECK(sa.cls.cloud_pixels > 0 && sa.cls.cloud_pixels < 32 * 16);
	cs_picture_free(&a);
	cs_picture_free(&b);
}

static void identical_pictures_differ_by_nothing(void)
{
	struct cs_picture a, b;
	solid(&a, 16, 8, 90, 140, 220);
	solid(&b, 16, 8, 90, 140, 220);
	for (int i = 0; i < 40; i++) {
		set_px(&a, i * 3, 200 + i, 201, 205);
		set_px(&b, i * 3, 200 + i, 201, 205);
	}
	struct cs_sky_stats sa, sb;
	struct cs_sky_diff d;
	unsigned char ca[128], cb[128];
	CHECK(cs_sky_stats(&a, CS_SKY_RB_THRESHOLD, ca, &sa) == CS_OK);
	CHECK(cs_sky_stats(&b, CS_SKY_RB_THRESHOLD, cb, &sb) == CS_OK);
	CHECK(cs_sky_diff(&a, &b, &sa, &sb, ca, cb, &d) == CS_OK);
	CHECK(d.emd_mean == 0.0 && d.chi2_mean == 0.0 && d.mean_abs_d_level == 0.0);
	CHECK(d.d_cloud_fraction == 0.0 && d.cloud_disagree == 0.0 && d.lum_ratio == 1.0);
	char text[256];
	CHECK(cs_skycompare_verdict(&sa, &sb, &d, text, sizeof text) == CS_MATCH);
	CHECK_STR_CONTAINS(text, "match: the same cloud cover");
	/* every level 10 up: EMD 10 per channel, mean difference -10 */
	for (int i = 0; i < 128 * 3; i++)
		b.srgb[i] = (uint8_t)(a.srgb[i] + 10);
	CHECK(cs_sky_stats(&b, CS_SKY_RB_THRESHOLD, cb, &sb) == CS_OK);
	CHECK(cs_sky_diff(&a, &b, &sa, &sb, ca, cb, &d) == CS_OK);
	for (int k = 0; k < 3; k++) {
		CHECK_NEAR(d.emd[k], 10.0, 1e-9);
		CHECK_NEAR(d.mean_d_level[k], -10.0, 1e-12);
	}
	CHECK_NEAR(d.mean_abs_d_level, 10.0, 1e-12);
	CHECK(d.lum_ratio < 1.0);
	cs_picture_free(&a);
	cs_picture_free(&b);
}

static void verdict_limits(void)
{
	struct cs_sky_stats a = {0}, b = {0};
	struct cs_sky_diff d = {0};
	char t[256];
	a.sky_pixels = b.sky_pixels = 10;
	a.mean_lum = b.mean_lum = 0.5;
	d.lum_ratio = 1.0;
	d.d_cloud_fraction = 0.09, d.emd_mean = 7.5;
	CHECK(cs_skycompare_verdict(&a, &b, &d, t, sizeof t) == CS_MATCH);
	d.d_cloud_fraction = -0.11; /* 10 % over the limit */
	CHECK(cs_skycompare_verdict(&a, &b, &d, t, sizeof t) == CS_FAIR);
	CHECK_STR_CONTAINS(t, "clearer");
	d.d_cloud_fraction = 0.09, d.emd_mean = 8.5;
	CHECK(cs_skycompare_verdict(&a, &b, &d, t, sizeof t) == CS_FAIR);
	d.d_cloud_fraction = 0.24, d.emd_mean = 23;
	CHECK(cs_skycompare_verdict(&a, &b, &d, t, sizeof t) == CS_FAIR);
	CHECK_STR_CONTAINS(t, "cloudier");
	d.d_cloud_fraction = 0.26;
	CHECK(cs_skycompare_verdict(&a, &b, &d, t, sizeof t) == CS_POOR);
	d.d_cloud_fraction = 0.0, d.emd_mean = 25;
	CHECK(cs_skycompare_verdict(&a, &b, &d, t, sizeof t) == CS_POOR);
	d.emd_mean = 1, d.lum_ratio = 1.14;
	CHECK(cs_skycompare_verdict(&a, &b, &d, t, sizeof t) == CS_MATCH);
	CHECK_STR_CONTAINS(t, "as bright");
	d.lum_ratio = 1.17;
	cs_skycompare_verdict(&a, &b, &d, t, sizeof t);
	CHECK_STR_CONTAINS(t, "17 % brighter");
	b.sky_pixels = 0;
	CHECK(cs_skycompare_verdict(&a, &b, &d, t, sizeof t) == CS_POOR);
	CHECK_STR_CONTAINS(t, "the photo has no sky");
}

static void area_resampling_undoes_an_enlargement(void)
{
	struct cs_picture a, big;
	CHECK(cs_picture_alloc(&a, 5, 3, 0) == CS_OK);
	CHECK(cs_picture_alloc(&big, 15, 6, 0) == CS_OK); /* x3 across, x2 down */
	unsigned st = 11;
	for (int i = 0; i < 15 * 3; i++)
		a.srgb[i] = (uint8_t)t_uniform(&st, 0, 256);
	for (int y = 0; y < 6; y++)
		for (int x = 0; x < 15; x++)
			memcpy(big.srgb + (y * 15 + x) * 3, a.srgb + ((y / 2) * 5 + x / 3) * 3, 3);
	CHECK(cs_picture_resample(&big, 5, 3) == CS_OK);
	CHECK(big.width == 5 && big.height == 3);
	CHECK(memcmp(big.srgb, a.srgb, 45) == 0);
	/* a 2 x 2 block to one pixel: the mean */
	struct cs_picture q;
	solid(&q, 2, 2, 0, 0, 0);
	set_px(&q, 1, 100, 10, 0);
	set_px(&q, 2, 200, 20, 0);
	set_px(&q, 3, 100, 30, 4);
	CHECK(cs_picture_resample(&q, 1, 1) == CS_OK);
	CHECK(q.srgb[0] == 100 && q.srgb[1] == 15 && q.srgb[2] == 1);
	/* a mask: sky where at least half the covered area is */
	uint8_t m[4] = {1, 1, 0, 1}, m2[4] = {1, 0, 0, 0}, *o;
	CHECK(cs_mask_resample(m, 2, 2, 1, 1, &o) == CS_OK && o[0] == 1);
	free(o);
	CHECK(cs_mask_resample(m2, 2, 2, 1, 1, &o) == CS_OK && o[0] == 0);
	free(o);
	cs_picture_free(&a);
	cs_picture_free(&big);
	cs_picture_free(&q);
}

static void masks_from_depth_horizon_and_an_estimate(void)
{
	/* 128 x 64: blue sky above row 30, dark green ground below, a black
	 * pole in column 50 and a bright cloud in the sky */
	struct cs_picture p;
	solid(&p, 128, 64, 120, 160, 225);
	for (int y = 30; y < 64; y++)
		for (int x = 0; x < 128; x++)
			set_px(&p, y * 128 + x, 60, 90, 40);
	for (int y = 0; y < 64; y++)
		set_px(&p, y * 128 + 50, 10, 10, 10);
	for (int y = 5; y < 12; y++)
		for (int x = 70; x < 90; x++)
			set_px(&p, y * 128 + x, 235, 235, 238);
	CHECK(cs_sky_mask_auto(&p) == CS_OK);
	long sky = 0;
	int wrong = 0;
	for (int i = 0; i < 128 * 64; i++) {
		sky += p.sky[i];
		wrong += p.sky[i] != (i / 128 < 30);
	}
	CHECK(wrong == 0);
	CHECK(sky == 30 * 128);
	/* a green foreground as bright as the sky is still ground */
	for (int y = 40; y < 64; y++)
		for (int x = 0; x < 128; x++)
			set_px(&p, y * 128 + x, 190, 230, 150);
	CHECK(cs_sky_mask_auto(&p) == CS_OK);
	sky = 0;
	for (int i = 0; i < 128 * 64; i++)
		sky += p.sky[i];
	CHECK(sky == 30 * 128);
	CHECK(cs_sky_mask_horizon(&p, 10) == CS_OK);
	sky = 0;
	for (int i = 0; i < 128 * 64; i++)
		sky += p.sky[i];
	CHECK(sky == 10 * 128);
	CHECK(cs_sky_mask_depth(&p, 1e10) == CS_EINVAL); /* no A, Z */
	cs_picture_free(&p);
	/* depth: clear ground (A 0, Z 500 m) is not sky; cloud over ground
	 * (A 0.3) and empty sky (Z 1e10) are */
	CHECK(cs_picture_alloc(&p, 3, 1, 1) == CS_OK);
	p.alpha[0] = 0.0f, p.depth[0] = 500.0f;
	p.alpha[1] = 0.3f, p.depth[1] = 500.0f;
	p.alpha[2] = 0.0f, p.depth[2] = 1e10f;
	CHECK(cs_sky_mask_depth(&p, 1e10) == CS_OK);
	CHECK(p.sky[0] == 0 && p.sky[1] == 1 && p.sky[2] == 1);
	cs_picture_free(&p);
}

static void aces_inverse_undoes_narkowicz_2015(void)
{
	/* hand values of the fit (test_image.c): x -> y */
	static const double hand[][2] = {
		{0.05, 0.044283069913142535}, {0.18, 0.2668989203894968},
		{0.5, 0.6163069544364508},    {1.0, 0.8037974683544302},
		{2.0, 0.914855072463768},     {0.0, 0.0},
	};
	for (size_t i = 0; i < sizeof hand / sizeof hand[0]; i++)
		CHECK_NEAR(cs_aces_inverse(hand[i][1]), hand[i][0], 1e-9);
	/* a PNG level back to radiance: x = L 2^ev / 16, at ev = 1 */
	struct cs_picture p;
	solid(&p, 1, 1, 0, 0, 0);
	p.srgb[0] = 200;
	cs_picture_undo_display(&p, 1.0);
	double y = ref_eotf(200);
	double x = cs_aces_inverse(y);
	CHECK_NEAR(p.lin[0], 16.0 / 2.0 * x, 1e-5 * x);
	CHECK(p.hdr == 1);
	cs_picture_free(&p);
}

static void series_patterns(void)
{
	char b[64];
	CHECK(cs_series_name("r/%05d.png", 42, b, sizeof b) == CS_OK);
	CHECK(strcmp(b, "r/00042.png") == 0);
	CHECK(cs_series_name("%d%%-%3d", 7, b, sizeof b) != CS_OK); /* two conversions */
	CHECK(cs_series_name("100%%/f%d.jpg", 7, b, sizeof b) == CS_OK);
	CHECK(strcmp(b, "100%/f7.jpg") == 0);
	CHECK(cs_series_name("x%3d", 5, b, sizeof b) == CS_OK && strcmp(b, "x  5") == 0);
	CHECK(cs_series_pattern_check("--series", "a.png") == CS_EINVAL);
	CHECK_STR_CONTAINS(cs_errmsg(), "--series: 'a.png' needs exactly one index conversion");
	CHECK(cs_series_pattern_check("--series", "a%s.png") == CS_EINVAL);
	CHECK(cs_series_pattern_check("--series", "a%ld.png") == CS_EINVAL);
	CHECK(cs_series_name("%05d", 1, b, 4) == CS_EINVAL); /* too long */
}

static const struct t_case t_cases[] = {
	CASE(emd_of_a_translated_histogram_is_the_translation),
	CASE(chi2_is_zero_equal_one_disjoint_and_a_third_between),
	CASE(cloud_fraction_of_known_pixels_is_exact),
	CASE(luminance_and_colour_of_known_levels),
	CASE(exposure_change_scales_luminance_and_keeps_cloud_fraction),
	CASE(identical_pictures_differ_by_nothing),
	CASE(verdict_limits),
	CASE(area_resampling_undoes_an_enlargement),
	CASE(masks_from_depth_horizon_and_an_estimate),
	CASE(aces_inverse_undoes_narkowicz_2015),
	CASE(series_patterns),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
