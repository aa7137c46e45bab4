#include "weather/places.h"

#include <string.h>
#include <strings.h>

/* WGS84; heights above sea level of the named point (summits for hills).
 * Gurten: 858 m is Gurten Kulm's summit (swisstopo; the tower's foot); its
 * viewing tower's platform stands 25 m above it, hence the 883 m camera. */
static const struct cs_place places[] = {
	{"Bern", 46.94798, 7.44743, 540.0, "old town (Zytglogge)"},
	{"Solothurn", 47.20791, 7.53714, 432.0, "old town, 30 km north of Bern"},
	{"Fribourg", 46.80683, 7.16197, 610.0, "old town, 27 km south-west of Bern"},
	{"Gurten", 46.91722, 7.44361, 858.0, "Bern's hill, summit"},
	{"Bantiger", 46.97917, 7.52916, 947.0, "hill north-east of Bern, summit"},
	{"Chasseral", 47.13317, 7.05936, 1607.0, "Jura summit, 40 km north-west of Bern"},
	{"Niesen", 46.64533, 7.65128, 2362.0, "Alpine foothill summit, 35 km south of Bern"},
};

enum { GURTEN = 3, BANTIGER = 4 };

static const struct cs_view views[] = {
	{"gurten", &places[GURTEN], 25.0, 12.0, -1.0, 60.0,
	 "Gurten summit (858 m), from its tower at 25 m, looking north over Bern toward Solothurn"},
	{"bantiger", &places[BANTIGER], 25.0, 235.5, -1.0, 60.0,
	 "Bantiger (947 m), from the tower's platform at 25 m, looking south-west over Bern toward Fribourg"},
};

#define COUNT(a) (int)(sizeof(a) / sizeof(a)[0])

const struct cs_place *cs_places(int *count)
{
	*count = COUNT(places);
	return places;
}

const struct cs_place *cs_place_find(const char *name)
{
	for (int i = 0; i < COUNT(places); i++)
		if (strcasecmp(places[i].name, name) == 0)
			return &places[i];
	return NULL;
}

const struct cs_view *cs_views(int *count)
{
	*count = COUNT(views);
	return views;
}

const struct cs_view *cs_view_find(const char *name)
{
	for (int i = 0; i < COUNT(views); i++)
		if (strcasecmp(views[i].name, name) == 0)
			return &views[i];
	return NULL;
}

double cs_view_alt_m(const struct cs_view *v)
{
	return v->place->alt_m + v->eye_m;
}
