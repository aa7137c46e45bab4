/* The default view (cs_default_look, man 1 cloudrender DEFAULT VIEW): it
 * looks away from the sun, and on a hazy day it still shows the nearest
 * clouds. */
#include "test.h"

#include "apps/cloudrender_run.h"
#include "astro/sun.h"
#include "core/err.h"
#include "core/fileio.h"
#include "core/time.h"
#include "io/exr.h"
#include "render/camera.h"
#include "render/device.h"
#include "render/render.h"

#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

static char tmpdir[256];

static const char *tmp(const char *name)
{
	static char path[4][512];
	static int k;
	k = (k + 1) % 4;
	snprintf(path[k], sizeof path[k], "%s/%s", tmpdir, name);
	return path[k];
}

/* Montevideo on 2024-10-07 at 15:00 UTC (the sun high in the north), 
 * broken cumulus 960 m over the ground (cover 0.35, or none), visibility
 * vis_m. */
static void hazy_state(struct cs_wx *wx, double vis_m, int clouds)
{
	cs_wx_default(wx);
	snprintf(wx->site.name, sizeof wx->site.name, "Montevideo");
	wx->site.lat_deg = -34.81, wx->site.lon_deg = -56.15, wx->site.alt_m = 34;
	cs_time_parse("2024-10-07T15:00:00Z", &wx->time_utc);
	wx->nlayers = clouds ? 1 : 0;
	wx->layers[0] = (struct cs_wx_layer){CS_CUMULUS, 0.35, 994, 2194};
	wx->visibility_m = vis_m;
	wx->fog_probability = 0;
	wx->precipitation_mm_h = wx->convective_mm_h = 0;
}

/* Renders a state (written to wx.json) with the default view, or looking
 * at (az, el) when look; *Y: malloc'ed luminance of w x h pixels. */
static int render(const struct cs_wx *wx, int look, double az, double el, int w, int h,
		  float **Y, float **Z, struct cs_cloudrender_result *res)
{
	char *json = NULL;
	if (cs_wx_to_json(wx, &json) != CS_OK)
		return -1;
	int rc = cs_write_file(tmp("wx.json"), json, strlen(json));
	free(json);
	struct cs_cloudrender_opts o;
	cs_cloudrender_defaults(&o);
	o.wx_path = tmp("wx.json");
	o.noise_size = 32;
	o.width = w, o.height = h;
	o.quality = "low";
	cs_render_quality("low", &o.settings);
	o.threads = 2;
	o.have_look = look, o.look_az_deg = az, o.look_el_deg = el;
	o.outputs[0] = tmp("v.exr");
	o.noutputs = 1;
	if (rc == CS_OK)
		rc = cs_cloudrender_run(&o, res);
	cs_cloudrender_result_free(res);
	if (rc != CS_OK) {
		printf("  render: %s\n", cs_errmsg());
		return rc;
	}
	unsigned char *data;
	size_t len;
	float *px;
	int pw, ph;
	const char *ch[4] = {"R", "G", "B", "Z"};
	if (cs_read_all(tmp("v.exr"), 1 << 28, &data, &len) != CS_OK)
		return -1;
	rc = cs_exr_read_channels(data, len, "v.exr", ch, 4, &pw, &ph, &px);
	free(data);
	if (rc != CS_OK)
		return rc;
	*Y = malloc((size_t)pw * ph * sizeof **Y);
	*Z = malloc((size_t)pw * ph * sizeof **Z);
	for (int i = 0; i < pw * ph; i++) { /* Rec. 709 luminance */
		(*Y)[i] = 0.2126f * px[4 * i] + 0.7152f * px[4 * i + 1] + 0.0722f * px[4 * i + 2];
		(*Z)[i] = px[4 * i + 3];
	}
	free(px);
	return CS_OK;
}

/* Visible cloud: the fraction of the frame's pixels that are sky in the
 * cloudless render (z0: no ground hit) and stand out from their 5 x 5
 * neighbourhood's mean luminance by more than 1 % - the edges and
 * texture of clouds.  The haze alone is smooth; a shadow falling on it
 * darkens it evenly. */
static double cloud_pixels(const float *y, const float *z0, int w, int h)
{
	int k = 0;
	for (int j = 2; j < h - 2; j++)
		for (int i = 2; i < w - 2; i++) {
			double m = 0.0;
			int sky = 1;
			for (int dj = -2; dj <= 2; dj++)
				for (int di = -2; di <= 2; di++) {
					m += y[(j + dj) * w + i + di];
					sky &= z0[(j + dj) * w + i + di] > 0.5f * (float)CS_SKY_DEPTH_M;
				}
			m /= 25.0;
			k += sky && fabs(y[j * w + i] - m) > 0.01 * m;
		}
	return (double)k / (w * h);
}

static void default_view_looks_away_from_the_sun(void)
{
	struct cs_wx wx;
	struct cs_cloudrender_result r;
	float *Y = NULL, *Z = NULL;
	hazy_state(&wx, 30000, 1);
	CHECK(render(&wx, 0, 0, 0, 32, 18, &Y, &Z, &r) == CS_OK);
	free(Y), free(Z);
	/* the sun's azimuth from NOAA's algorithm, independently of the scene */
	struct cs_sun sun;
	CHECK(cs_sun_position(wx.time_utc, wx.site.lat_deg, wx.site.lon_deg, &sun) == CS_OK);
	double want = fmod(sun.azimuth_deg + 180.0, 360.0);
	double d = fabs(fmod(r.look_az_deg - want + 540.0, 360.0) - 180.0);
	CHECK_NEAR(d, 0.0, 0.5);
	/* not Bern's fixed south-south-east: in the southern spring afternoon
	 * the sun is in the north-west, the view to the south-east */
	CHECK(sun.azimuth_deg > 270.0 || sun.azimuth_deg < 45.0);
	CHECK_NEAR(r.look_el_deg, CS_VIEW_DEFAULT_ELEVATION_DEG, 1e-9);
}

/* Cumulus at 0.35 behind haze of 2 km visibility: the default view (raised
 * until the lowest base shows) sees textured cloud on more than 3 % of the
 * pixels, and more than twice what the fixed 8-degree pitch of before saw
 * (measured: 14 % when the rule was made, 9.4 % since the deck's
 * transmittance follows the sun's elevation and the clouds' insides are
 * darker, 4.9 % since medium looks the depths toward the sun and up the
 * column up in the light cache, whose light has none of the march's
 * grain, which a pixel 1 % off its neighbours' mean also counts; 0.1 %
 * at 8 degrees). */
static void hazy_default_view_still_shows_the_nearest_clouds(void)
{
	struct cs_wx wx;
	struct cs_cloudrender_result r;
	float *y1 = NULL, *y0 = NULL, *z1 = NULL, *z0 = NULL;
	float *f1 = NULL, *f0 = NULL, *g1 = NULL, *g0 = NULL;
	const int w = 96, h = 54;
	/* 2 km: the haze's vertical optical depth up to the base is 1.3 */
	hazy_state(&wx, 2000, 1);
	CHECK(render(&wx, 0, 0, 0, w, h, &y1, &z1, &r) == CS_OK);
	double az = r.look_az_deg, el = r.look_el_deg;
	hazy_state(&wx, 2000, 0);
	CHECK(render(&wx, 1, az, el, w, h, &y0, &z0, &r) == CS_OK);
	hazy_state(&wx, 2000, 1);
	CHECK(render(&wx, 1, az, 8.0, w, h, &f1, &g1, &r) == CS_OK);
	hazy_state(&wx, 2000, 0);
	CHECK(render(&wx, 1, az, 8.0, w, h, &f0, &g0, &r) == CS_OK);
	if (y1 && y0 && f1 && f0) {
		double f = cloud_pixels(y1, z0, w, h), c = cloud_pixels(y0, z0, w, h);
		double f8 = cloud_pixels(f1, g0, w, h), c8 = cloud_pixels(f0, g0, w, h);
		printf("  visibility 2 km: default elevation %.1f deg, cloud pixels %.3f "
		       "(cloudless %.3f); at 8 deg %.3f (%.3f)\n", el, f, c, f8, c8);

		CHECK(c < 0.01 && c8 < 0.01);
		CHECK(el > CS_VIEW_DEFAULT_ELEVATION_DEG);
		CHECK(f > 0.03);
		/* the fixed 8-degree pitch of before sees (almost) only haze */
		CHECK(f8 < f / 2);
	}
	free(y1), free(y0), free(z1), free(z0), free(f1), free(f0), free(g1), free(g0);
}

/* The presets' light on a GPU (cloudrender --source-every): low, medium
 * and high, whose light is cached, find a cloudy sample's light at every
 * sample there (faster on a GPU, no less accurate), at every other on the
 * CPU; a preset told to march its light and any explicit --source-every
 * keep theirs; the reference is at every sample everywhere. */
static void a_gpus_presets_find_the_light_at_every_sample(void)
{
	static const struct {
		const char *q;
		int device, light_march, given, want;
	} c[] = {
		{"low", CS_DEVICE_CPU, -1, 0, 2},
		{"low", CS_DEVICE_CUDA, -1, 0, 1},
		{"medium", CS_DEVICE_CPU, -1, 0, 2},
		{"medium", CS_DEVICE_CUDA, -1, 0, 1},
		{"high", CS_DEVICE_CUDA, -1, 0, 1},
		{"high", CS_DEVICE_CPU, -1, 0, 2},
		{"reference", CS_DEVICE_CUDA, -1, 0, 1},
		{"low", CS_DEVICE_CUDA, -1, 2, 2},
		{"medium", CS_DEVICE_CUDA, CS_LIGHT_GEOMETRIC, 0, 2},
		{"high", CS_DEVICE_CUDA, CS_LIGHT_GEOMETRIC, 0, 2},
		{"high", CS_DEVICE_CUDA, CS_LIGHT_CACHE, 0, 1},
	};
	for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
		struct cs_cloudrender_opts o;
		cs_cloudrender_defaults(&o);
		o.quality = c[i].q;
		CHECK(cs_render_quality(c[i].q, &o.settings) == CS_OK);
		o.device = c[i].device;
		o.light_march = c[i].light_march;
		o.source_every = c[i].given;
		struct cs_render_settings s;
		cs_cloudrender_settings(&o, &s);
		if (s.source_every != c[i].want) {
			printf("  %s on %s: source every %d, expected %d\n", c[i].q,
			       c[i].device == CS_DEVICE_CUDA ? "cuda" : "cpu", s.source_every,
			       c[i].want);
			t_case_failed = 1;
		}
	}
}

static const struct t_case t_cases[] = {
	CASE(default_view_looks_away_from_the_sun),
	CASE(hazy_default_view_still_shows_the_nearest_clouds),
	CASE(a_gpus_presets_find_the_light_at_every_sample),
};

int main(void)
{
	snprintf(tmpdir, sizeof tmpdir, "%s/cs-view-XXXXXX",
		 getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	if (mkdtemp(tmpdir) == NULL)
		return 1;
	T_RUN_TABLE(t_cases);
	unlink(tmp("wx.json"));
	unlink(tmp("v.exr"));
	rmdir(tmpdir);
	TEST_EXIT();
}
