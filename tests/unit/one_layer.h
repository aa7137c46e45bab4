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

#endif
