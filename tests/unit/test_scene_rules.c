/* test_scene_rules.c - what cs_scene_build makes of the weather, against the
 * physics and the documented rules it follows:
 *  - showers fall from cumulus only when most of the precipitation is
 *    convective (the forecast's convective share over one half), steady
 *    rain from the sheets whatever the share;
 *  - water absorbs next to nothing of visible light (absorption index
 *    k ~ 2e-9 at 550 nm, Hale & Querry 1973): a cloud droplet's
 *    single-scattering albedo is above 0.999, so the scene's may be no
 *    lower than 0.98; a raindrop of 2 mm loses e^(-4 pi k d / lambda) ~
 *    1e-4 of the light that enters it, so rain's albedo may be no lower
 *    than 0.85 (the renderer's 0.9 leaves room for the drops' diffraction
 *    lobe it does not model). */
#include "core/err.h"
#include "render/render.h"
#include "render/scene.h"
#include "test.h"
#include "noise/volume.h"
#include "weather/wx.h"

static struct cs_scene sc;
static struct cs_volume noise;

static void build(const char *genus_name, double precip, double conv)
{
	struct cs_wx wx;
	cs_wx_default(&wx);
	wx.nlayers = 1;
	wx.layers[0].genus = cs_genus_from_name(genus_name);
	wx.layers[0].coverage = 0.8;
	wx.layers[0].base_m = 1200;
	wx.layers[0].top_m = 2500;
	wx.precipitation_mm_h = precip;
	wx.convective_mm_h = conv;
	wx.snow_fraction = 0.0;
	CHECK(cs_scene_build(&sc, &wx, wx.time_utc, &noise) == CS_OK);
}

static void showers_from_cumulus_only_when_most_is_convective(void)
{
	build("cumulus", 2.0, 1.2); /* 60 % convective */
	CHECK(sc.effects & CS_FX_RAIN);
	build("cumulus", 2.0, 1.9);
	CHECK(sc.effects & CS_FX_RAIN);
	build("cumulus", 2.0, 0.8); /* 40 %: steady rain, not from cumulus */
	CHECK(!(sc.effects & CS_FX_RAIN));
	build("cumulus", 2.0, 0.0);
	CHECK(!(sc.effects & CS_FX_RAIN));
	build("nimbostratus", 2.0, 0.0);
	CHECK(sc.effects & CS_FX_RAIN);
	build("nimbostratus", 2.0, 1.2);
	CHECK(sc.effects & CS_FX_RAIN);
}

static void droplets_and_drops_scatter_almost_all_the_light(void)
{
	build("nimbostratus", 2.0, 0.0);
	CHECK(sc.albedo >= 0.98 && sc.albedo <= 1.0);
	CHECK(sc.precip_albedo >= 0.85 && sc.precip_albedo <= 1.0);
}

static const struct t_case t_cases[] = {
	CASE(showers_from_cumulus_only_when_most_is_convective),
	CASE(droplets_and_drops_scatter_almost_all_the_light),
};

int main(void)
{
	if (cs_volume_new(&noise, 16, 16) != CS_OK || cs_volume_bake(&noise, 0, NULL, NULL) != CS_OK)
		return 1;
	T_RUN_TABLE(t_cases);
	cs_volume_free(&noise);
	TEST_EXIT();
}
