/* The one place table: sites and viewpoints agree on every ground height
 * (swisstopo: Gurten Kulm 858 m, Bantiger 947 m; both towers' platforms
 * 25 m above the ground). */
#include "test.h"

#include "weather/places.h"

static void views_stand_on_the_places_ground_plus_their_tower(void)
{
	const struct cs_view *g = cs_view_find("gurten");
	CHECK(g != NULL && g->place == cs_place_find("Gurten"));
	if (g == NULL)
		return;
	CHECK(g->place->alt_m == 858.0 && cs_view_alt_m(g) == 883.0);
	const struct cs_view *b = cs_view_find("bantiger");
	CHECK(b != NULL && b->place == cs_place_find("bantiger"));
	if (b != NULL)
		CHECK(b->place->alt_m == 947.0 && cs_view_alt_m(b) == 972.0);
}

static void every_view_is_a_place_of_the_table(void)
{
	int nv, np;
	const struct cs_view *v = cs_views(&nv);
	const struct cs_place *p = cs_places(&np);
	CHECK(nv >= 2 && np >= 5);
	for (int i = 0; i < nv; i++)
		CHECK(v[i].place >= p && v[i].place < p + np &&
		      v[i].eye_m >= 0 && v[i].eye_m < 100);
	CHECK(cs_view_find("Atlantis") == NULL && cs_place_find("Atlantis") == NULL);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(views_stand_on_the_places_ground_plus_their_tower),
	CASE(every_view_is_a_place_of_the_table),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
