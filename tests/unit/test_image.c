/* The display transform (image.c) against values computed outside our
 * code: the ACES fit of Narkowicz 2015 ("ACES Filmic Tone Mapping Curve",
 * a = 2.51, b = 0.03, c = 2.43, d = 0.59, e = 0.14) and the sRGB OETF of
 * IEC 61966-2-1 (12.92 v up to 0.0031308, else 1.055 v^(1/2.4) - 0.055),
 * written again here from the sources, and anchor values computed by hand
 * (Python, double precision).  Then PNG write/read round trips. */
#include "test.h"

#include "core/err.h"
#include "io/image.h"

#include <stdint.h>
#include <stdlib.h>
#include <unistd.h>

static double ref_aces(double x)
{
	double y = x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14);
	return y < 0.0 ? 0.0 : y > 1.0 ? 1.0 : y;
}

static double ref_srgb(double v)
{
	return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

static void aces_matches_narkowicz_2015(void)
{
	/* by hand: x -> (x (2.51 x + 0.03)) / (x (2.43 x + 0.59) + 0.14) */
	static const double hand[][2] = {
		{0.01, 0.003770279794447903}, {0.05, 0.044283069913142535},
		{0.18, 0.2668989203894968},   {0.5, 0.6163069544364508},
		{1.0, 0.8037974683544302},    {2.0, 0.914855072463768},
		{10.0, 1.0},                  {0.0, 0.0},
	};
	for (size_t i = 0; i < sizeof hand / sizeof hand[0]; i++)
		CHECK_NEAR(cs_tonemap_aces(hand[i][0]), hand[i][1], 1e-12);
	/* every constant matters somewhere in 0..16: compare densely */
	double worst = 0.0;
	for (int i = 0; i <= 4000; i++) {
		double x = i * 0.004;
		worst = fmax(worst, fabs(cs_tonemap_aces(x) - ref_aces(x)));
	}
	CHECK_NEAR(worst, 0.0, 1e-12);
}

static void srgb_oetf_matches_iec_61966_2_1(void)
{
	static const double hand[][2] = {
		{0.0, 0.0},
		{0.001, 0.012920000000000001},   /* linear segment */
		{0.0028, 0.036176},              /* just below the knee */
		{0.0035, 0.04498790711983986},   /* just above it */
		{0.01, 0.09985282273412832},
		{0.18, 0.46135612950044164},
		{0.5, 0.7353569830524495},
		{1.0, 1.0},
	};
	for (size_t i = 0; i < sizeof hand / sizeof hand[0]; i++)
		CHECK_NEAR(cs_srgb_oetf(hand[i][0]), hand[i][1], 1e-12);
	double worst = 0.0;
	for (int i = 0; i <= 10000; i++) {
		double v = i * 1e-4;
		worst = fmax(worst, fabs(cs_srgb_oetf(v) - ref_srgb(v)));
	}
	CHECK_NEAR(worst, 0.0, 1e-12);
}

static void tonemap_srgb8_scales_by_exposure_over_16(void)
{
	/* grey radiances L (kcd/m^2) at EV 0: x = L / 16; by hand */
	static const double hand[][2] = {
		{0.8, 59}, {2.88, 141}, {8.0, 206}, {16.0, 232}, {32.0, 245},
	};
	for (size_t i = 0; i < sizeof hand / sizeof hand[0]; i++) {
		float px[3] = {(float)hand[i][0], (float)hand[i][0], (float)hand[i][0]};
		uint8_t rgb[3];
		cs_tonemap_srgb8(px, 3, 1, 0.0, rgb);
		CHECK(rgb[0] == hand[i][1] && rgb[1] == hand[i][1] && rgb[2] == hand[i][1]);
		/* one stop more exposure is the same as twice the radiance */
		float half[3] = {px[0] / 2, px[1] / 2, px[2] / 2};
		uint8_t up[3];
		cs_tonemap_srgb8(half, 3, 1, 1.0, up);
		CHECK(up[0] == rgb[0]);
	}
	/* many radiances and exposures, every channel, against the reference
	 * (strided input: the fourth float is skipped) */
	unsigned st = 7;
	int worst = 0;
	for (int i = 0; i < 20000; i++) {
		float px[4];
		for (int c = 0; c < 4; c++)
			px[c] = (float)t_uniform(&st, 0.0, 64.0);
		double ev = t_uniform(&st, -4.0, 4.0);
		uint8_t rgb[3];
		cs_tonemap_srgb8(px, 4, 1, ev, rgb);
		for (int c = 0; c < 3; c++) {
			double want = 255.0 * ref_srgb(ref_aces(px[c] * pow(2.0, ev) / 16.0));
			int d = abs((int)rgb[c] - (int)lrint(want));
			worst = d > worst ? d : worst;
		}
	}
	CHECK(worst == 0);
	/* no light, negative and non-finite radiance: black */
	float bad[6] = {0.0f, -1.0f, NAN, INFINITY, -INFINITY, 0.0f};
	uint8_t out[6];
	cs_tonemap_srgb8(bad, 3, 2, 0.0, out);
	CHECK(out[0] == 0 && out[1] == 0 && out[2] == 0 && out[4] == 0 && out[5] == 0);
}

static void auto_exposure_brings_log_average_to_key_0_25(void)
{
	/* uniform grey L = 1: 1 * 2^ev / 16 = 0.25, ev = log2(4) = 2 */
	float grey[3 * 4];
	for (int i = 0; i < 12; i++)
		grey[i] = 1.0f;
	CHECK_NEAR(cs_auto_exposure_ev(grey, 3, 4), 2.0, 1e-9);
	/* pure red R = 2: Y = 0.2126 * 2 (Rec. 709 weights), ev = log2(4 / Y) */
	float red[3] = {2.0f, 0.0f, 0.0f};
	CHECK_NEAR(cs_auto_exposure_ev(red, 3, 1), 3.2337864980183446, 1e-9);
	float green[3] = {0.0f, 2.0f, 0.0f}, blue[3] = {0.0f, 0.0f, 2.0f};
	CHECK_NEAR(cs_auto_exposure_ev(green, 3, 1), log2(4.0 / (0.7152 * 2.0)), 1e-9);
	CHECK_NEAR(cs_auto_exposure_ev(blue, 3, 1), log2(4.0 / (0.0722 * 2.0)), 1e-9);
	/* the log average, not the mean: black counts as 1e-9, so one black
	 * and one L = 1 pixel average to sqrt(1e-9) */
	float mix[8] = {0, 0, 0, 9, 1, 1, 1, 9}; /* stride 4: 9 is skipped */
	CHECK_NEAR(cs_auto_exposure_ev(mix, 4, 2), 16.94867642699313, 1e-9);
	/* and the exposure chosen puts that grey at x = 0.25 */
	double ev = cs_auto_exposure_ev(grey, 3, 4);
	uint8_t rgb[3];
	cs_tonemap_srgb8(grey, 3, 1, ev, rgb);
	CHECK(rgb[0] == (uint8_t)lrint(255.0 * ref_srgb(ref_aces(0.25))));
}

static const char *tmp_png(const char *name)
{
	static char path[512];
	snprintf(path, sizeof path, "%s/cs-test-image-%d-%s",
		 getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp", (int)getpid(), name);
	return path;
}

static void png_round_trip_is_exact(void)
{
	enum { W = 37, H = 23 };
	uint8_t rgb[W * H * 3], grey[W * H];
	unsigned st = 11;
	for (int i = 0; i < W * H * 3; i++)
		rgb[i] = (uint8_t)t_uniform(&st, 0.0, 256.0);
	for (int i = 0; i < W * H; i++)
		grey[i] = (uint8_t)(i * 7);
	const char *p = tmp_png("rgb.png");
	CHECK(cs_png_write(p, W, H, 3, rgb) == CS_OK);
	uint8_t *back = NULL;
	int w = 0, h = 0;
	CHECK(cs_png_read_rgb8(p, &back, &w, &h) == CS_OK);
	CHECK(w == W && h == H && back && memcmp(back, rgb, sizeof rgb) == 0);
	free(back);
	unlink(p);
	/* grey comes back as R = G = B */
	p = tmp_png("grey.png");
	CHECK(cs_png_write(p, W, H, 1, grey) == CS_OK);
	back = NULL;
	CHECK(cs_png_read_rgb8(p, &back, &w, &h) == CS_OK);
	int same = back != NULL && w == W && h == H;
	for (int i = 0; same && i < W * H; i++)
		same = back[3 * i] == grey[i] && back[3 * i + 1] == grey[i] &&
		       back[3 * i + 2] == grey[i];
	CHECK(same);
	free(back);
	unlink(p);
	/* refusals: no such channel count, a missing file */
	CHECK(cs_png_write(tmp_png("bad.png"), W, H, 2, grey) == CS_EINVAL);
	CHECK(access(tmp_png("bad.png"), F_OK) != 0);
	CHECK(cs_png_read_rgb8(tmp_png("absent.png"), &back, &w, &h) == CS_EDATA);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(aces_matches_narkowicz_2015),
	CASE(srgb_oetf_matches_iec_61966_2_1),
	CASE(tonemap_srgb8_scales_by_exposure_over_16),
	CASE(auto_exposure_brings_log_average_to_key_0_25),
	CASE(png_round_trip_is_exact),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
