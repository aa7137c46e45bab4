/* Views from a user's file (cloudrender --views) and cs_look_at, the
 * direction from an eye to a point on the sphere.  Expected directions come
 * from closed forms: along the equator or a meridian the great circle's
 * bearing is 90 or 0/180 degrees, and between two points at one height
 * separated by a central angle c the chord dips c/2 below the horizon. */
#include "test.h"

#include "core/err.h"
#include "core/geo.h"
#include "weather/viewfile.h"

#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

static const double R = 6371000.0;

static void look_at_follows_great_circles_and_the_curve(void)
{
	double az = -1, el = -1;
	/* a quarter of the equator east, both on the ground: bearing 90,
	 * the chord 45 degrees below the horizon */
	CHECK(cs_look_at(R, 0, 0, 0, 0, 90, 0, &az, &el) == 0);
	CHECK_NEAR(az, 90.0, 1e-9);
	CHECK_NEAR(el, -45.0, 1e-9);
	/* 1 degree north along a meridian: bearing 0, dip 0.5 */
	CHECK(cs_look_at(R, 46, 7, 0, 47, 7, 0, &az, &el) == 0);
	CHECK_NEAR(az, 0.0, 1e-9);
	CHECK_NEAR(el, -0.5, 1e-9);
	/* and back south */
	CHECK(cs_look_at(R, 47, 7, 0, 46, 7, 0, &az, &el) == 0);
	CHECK_NEAR(az, 180.0, 1e-9);
	/* straight up and straight down */
	CHECK(cs_look_at(R, 46, 7, 500, 46, 7, 1500, &az, &el) == 0);
	CHECK_NEAR(el, 90.0, 1e-9);
	CHECK(cs_look_at(R, 46, 7, 1500, 46, 7, 500, &az, &el) == 0);
	CHECK_NEAR(el, -90.0, 1e-9);
	/* west is 270, not -90 */
	CHECK(cs_look_at(R, 0, 10, 0, 0, 9, 0, &az, &el) == 0);
	CHECK_NEAR(az, 270.0, 1e-9);
	/* the same point: no direction, nothing written */
	az = el = 123.0;
	CHECK(cs_look_at(R, 46, 7, 600, 46, 7, 600, &az, &el) == -1);
	CHECK(az == 123.0 && el == 123.0);
}

/* Writes text to a temporary file; its name in path. */
static void write_tmp(char *path, const char *text)
{
	int fd = mkstemp(path);
	FILE *f = fd >= 0 ? fdopen(fd, "w") : NULL;
	if (f) {
		fputs(text, f);
		fclose(f);
	}
}

static void views_file_is_read_with_comments_and_descriptions(void)
{
	char path[] = "/tmp/cs-test-views-XXXXXX";
	write_tmp(path, "# my views\n\n"
			"rosengarten 46.9513 7.4606 570 250 3 50  over the old town  # west\n"
			"\tGurten\t46.9 7.4 1000 180 -2 40\n");
	static struct cs_viewset set;
	CHECK(cs_viewset_read(path, &set) == CS_OK);
	unlink(path);
	CHECK(set.n == 2);
	const struct cs_view *v = cs_viewset_find(&set, "ROSENGARTEN");
	CHECK(v == &set.views[0]);
	if (v) {
		CHECK(v->place->lat_deg == 46.9513 && v->place->lon_deg == 7.4606);
		CHECK(cs_view_alt_m(v) == 570.0);
		CHECK(v->azimuth_deg == 250.0 && v->elevation_deg == 3.0 && v->fov_deg == 50.0);
		CHECK(strcmp(v->description, "over the old town") == 0);
	}
	/* the file's Gurten, not the built-in one; Bantiger still built in */
	v = cs_viewset_find(&set, "gurten");
	CHECK(v == &set.views[1] && v != NULL && cs_view_alt_m(v) == 1000.0 &&
	      v->description[0] == '\0');
	CHECK(cs_viewset_find(&set, "bantiger") == cs_view_find("bantiger"));
	CHECK(cs_viewset_find(NULL, "Bantiger") == cs_view_find("bantiger"));
	CHECK(cs_viewset_find(&set, "atlantis") == NULL);
}

static void views_file_errors_name_the_line_and_the_field(void)
{
	static const struct {
		const char *text, *msg;
	} bad[] = {
		{"a 46 7 500 10 0\n", ":1: the field of view is missing"},
		{"a 46 7 500 10 0 60\nb 46 7 x 10 0 60\n", ":2: the altitude is not a number"},
		{"a 95 7 500 10 0 60\n", ":1: the latitude must be"},
		{"a 46 7 500 10 0 180\n", ":1: the field of view must be 1..179"},
		{"a 46 7 500 10 0 60\nA 46 7 500 10 0 60\n", ":2: a second view named 'A'"},
		{"a.b 46 7 500 10 0 60\n", ":1: a name is letters"},
		{"abcdefghijabcdefghijabcdefghijab 46 7 500 10 0 60\n", "longer than 31"},
	};
	static struct cs_viewset set;
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		char path[] = "/tmp/cs-test-views-XXXXXX";
		write_tmp(path, bad[i].text);
		CHECK(cs_viewset_read(path, &set) == CS_EDATA);
		CHECK_STR_CONTAINS(cs_errmsg(), bad[i].msg);
		CHECK(set.n == 0);
		unlink(path);
	}
	CHECK(cs_viewset_read("/nonexistent/views", &set) == CS_EIO);
}

static const struct t_case t_cases[] = {
	CASE(look_at_follows_great_circles_and_the_curve),
	CASE(views_file_is_read_with_comments_and_descriptions),
	CASE(views_file_errors_name_the_line_and_the_field),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
