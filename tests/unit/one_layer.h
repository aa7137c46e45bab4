/* one_layer.h - the weather of one cloud layer for the unit tests that
 * render it (test_reference, test_tower_light). */
#ifndef CS_TEST_ONE_LAYER_H
#define CS_TEST_ONE_LAYER_H

#include "core/time.h"
#include "test.h"
#include "weather/wx.h"

/* One cloud layer of genus g, cover, base and top (m) over the default
 * site at time_utc (ISO 8601), no rain, visibility_m. */
static inline void one_layer_wx(struct cs_wx *wx, const char *time_utc, enum cs_genus g,
				double cover, double base_m, double top_m, double visibility_m)
{
	cs_wx_default(wx);
	CHECK(cs_time_parse(time_utc, &wx->time_utc) == CS_OK);
	wx->nlayers = 1;
	wx->layers[0].genus = g;
	wx->layers[0].coverage = cover;
	wx->layers[0].base_m = base_m, wx->layers[0].top_m = top_m;
	wx->visibility_m = visibility_m;
	wx->precipitation_mm_h = 0.0;
}

/* Two layers: one_layer_wx's of genus g, then a second of genus g2,
 * cover2, base2_m and top2_m. */
static inline void two_layer_wx(struct cs_wx *wx, const char *time_utc, enum cs_genus g,
				double cover, double base_m, double top_m, enum cs_genus g2,
				double cover2, double base2_m, double top2_m)
{
	one_layer_wx(wx, time_utc, g, cover, base_m, top_m, 20000.0);
	wx->nlayers = 2;
	wx->layers[1] = wx->layers[0];
	wx->layers[1].genus = g2;
	wx->layers[1].coverage = cover2;
	wx->layers[1].base_m = base2_m, wx->layers[1].top_m = top2_m;
}

#endif
