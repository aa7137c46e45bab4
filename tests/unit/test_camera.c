/* test_camera.c - where the camera looks, against geometry only: the world
 * frame is east-north-up at the scene origin (render.h), so at the origin
 * the centre ray of a camera looking at azimuth 0 is +y (north), at 90 +x
 * (east); the edge rays of a perspective image sit at +-FOV/2 horizontally;
 * an all-sky fisheye has the zenith in the middle, north up, east left and
 * the horizon on its circle; an equirect map spans 360 degrees of azimuth,
 * the look azimuth in the middle and east to its right. */
#include "core/err.h"
#include "core/sphere.h"
#include "render/camera.h"
#include "render/render.h"
#include "test.h"

#define DEG (CS_PI / 180.0)

static struct cs_scene sc;

static double angle_deg(cs_v3 a, cs_v3 b)
{
	double c = v3_dot(v3_norm(a), v3_norm(b));
	return acos(c > 1.0 ? 1.0 : c < -1.0 ? -1.0 : c) / DEG;
}

/* the direction at azimuth az (clockwise from north) and elevation el at
 * the origin, written from the definition */
static cs_v3 enu(double az_deg, double el_deg)
{
	return v3(sin(az_deg * DEG) * cos(el_deg * DEG), cos(az_deg * DEG) * cos(el_deg * DEG),
		  sin(el_deg * DEG));
}

static void centre_ray_points_where_the_camera_looks(void)
{
	sc.earth_radius_m = CS_EARTH_RADIUS_M;
	static const double looks[][2] = {{0, 0}, {90, 0}, {180, 0}, {270, 0},
					  {0, 30}, {135, -20}, {300, 60}};
	for (size_t k = 0; k < sizeof looks / sizeof looks[0]; k++) {
		struct cs_camera c;
		/* odd sizes: the middle pixel's centre is the image centre */
		CHECK(cs_camera_init(&c, &sc, v3(0, 0, 600), 46.95, looks[k][0], looks[k][1], 60,
				     101, 51) == CS_OK);
		cs_v3 d;
		CHECK(cs_camera_ray(&c, 50, 25, &d) == 1);
		double a = angle_deg(d, enu(looks[k][0], looks[k][1]));
		if (!(a < 1e-6)) {
			printf("  look %g/%g: the centre ray is %.4f deg off\n", looks[k][0],
			       looks[k][1], a);
			t_case_failed = 1;
		}
	}
	/* the named cases, spelled out: north is +y, east is +x */
	struct cs_camera c;
	cs_v3 d;
	CHECK(cs_camera_init(&c, &sc, v3(0, 0, 600), 46.95, 0, 0, 60, 101, 51) == CS_OK);
	cs_camera_ray(&c, 50, 25, &d);
	CHECK_NEAR(d.y, 1.0, 1e-9);
	CHECK(cs_camera_init(&c, &sc, v3(0, 0, 600), 46.95, 90, 0, 60, 101, 51) == CS_OK);
	cs_camera_ray(&c, 50, 25, &d);
	CHECK_NEAR(d.x, 1.0, 1e-9);
	/* the top row looks up, the left column to the left (west of north) */
	CHECK(cs_camera_init(&c, &sc, v3(0, 0, 600), 46.95, 0, 0, 60, 101, 51) == CS_OK);
	cs_camera_ray(&c, 50, 0, &d);
	CHECK(d.z > 0.1);
	cs_camera_ray(&c, 0, 25, &d);
	CHECK(d.x < -0.1);
}

/* The first and last pixel columns of a wide image lie half a pixel inside
 * the image's edges, so with 4001 columns they are within 0.01 deg of
 * +-FOV/2 from the centre ray, in the horizontal plane (level camera). */
static void perspective_edges_are_at_half_the_field_of_view(void)
{
	sc.earth_radius_m = CS_EARTH_RADIUS_M;
	static const double fovs[] = {10, 45, 60, 90, 120, 150};
	for (size_t k = 0; k < sizeof fovs / sizeof fovs[0]; k++) {
		struct cs_camera c;
		CHECK(cs_camera_init(&c, &sc, v3(0, 0, 600), 46.95, 90, 0, fovs[k], 4001, 3) ==
		      CS_OK);
		cs_v3 l, r;
		cs_camera_ray(&c, 0, 1, &l);
		cs_camera_ray(&c, 4000, 1, &r);
		CHECK_NEAR(angle_deg(l, enu(90, 0)), fovs[k] / 2, 0.01);
		CHECK_NEAR(angle_deg(r, enu(90, 0)), fovs[k] / 2, 0.01);
		/* looking east: left is north, right is south, both level */
		CHECK_NEAR(atan2(l.x, l.y) / DEG, 90 - fovs[k] / 2, 0.01);
		CHECK_NEAR(atan2(r.x, r.y) / DEG, 90 + fovs[k] / 2, 0.01);
		CHECK_NEAR(l.z, 0.0, 1e-9);
		/* square pixels: the vertical field follows the aspect ratio */
		CHECK(cs_camera_init(&c, &sc, v3(0, 0, 600), 46.95, 90, 0, fovs[k], 4001, 2001) ==
		      CS_OK);
		cs_v3 top;
		cs_camera_ray(&c, 2000, 0, &top);
		double half_v = atan(tan(fovs[k] / 2 * DEG) * 2001.0 / 4001.0) / DEG;
		CHECK_NEAR(asin(top.z) / DEG, half_v, 0.03); /* half a row inside */
	}
}

static void fisheye_is_the_sky_seen_from_below(void)
{
	sc.earth_radius_m = CS_EARTH_RADIUS_M;
	struct cs_camera c;
	CHECK(cs_camera_init(&c, &sc, v3(0, 0, 600), 46.95, 0, 90, 90, 2001, 2001) == CS_OK);
	c.projection = CS_PROJ_FISHEYE;
	cs_v3 d;
	CHECK(cs_camera_ray(&c, 1000, 1000, &d) == 1);
	CHECK_NEAR(d.z, 1.0, 1e-9); /* the zenith in the middle */
	CHECK(cs_camera_ray(&c, 1000, 0, &d) == 1);
	CHECK_NEAR(angle_deg(d, enu(0, 0)), 0.0, 0.1); /* north horizon at the top */
	CHECK(cs_camera_ray(&c, 0, 1000, &d) == 1);
	CHECK_NEAR(angle_deg(d, enu(90, 0)), 0.0, 0.1); /* east on the left */
	CHECK(cs_camera_ray(&c, 2000, 1000, &d) == 1);
	CHECK_NEAR(angle_deg(d, enu(270, 0)), 0.0, 0.1); /* west on the right */
	CHECK(cs_camera_ray(&c, 1000, 2000, &d) == 1);
	CHECK_NEAR(angle_deg(d, enu(180, 0)), 0.0, 0.1);
	/* equidistant: half way out is 45 deg up */
	CHECK(cs_camera_ray(&c, 1000, 500, &d) == 1);
	CHECK_NEAR(angle_deg(d, enu(0, 45)), 0.0, 0.1);
	CHECK(cs_camera_ray(&c, 0, 0, &d) == 0); /* a corner: outside */
}

static void equirect_spans_all_azimuths(void)
{
	sc.earth_radius_m = CS_EARTH_RADIUS_M;
	struct cs_camera c;
	CHECK(cs_camera_init(&c, &sc, v3(0, 0, 600), 46.95, 30, 0, 60, 3601, 1801) == CS_OK);
	c.projection = CS_PROJ_EQUIRECT;
	cs_v3 d;
	cs_camera_ray(&c, 1800, 900, &d);
	CHECK_NEAR(angle_deg(d, enu(30, 0)), 0.0, 1e-6); /* the look in the middle */
	cs_camera_ray(&c, 2700, 900, &d);
	CHECK_NEAR(angle_deg(d, enu(120, 0)), 0.0, 0.1); /* a quarter right: 90 deg east */
	cs_camera_ray(&c, 0, 900, &d);
	CHECK_NEAR(angle_deg(d, enu(210, 0)), 0.0, 0.1); /* the edges: behind */
	cs_camera_ray(&c, 3600, 900, &d);
	CHECK_NEAR(angle_deg(d, enu(210, 0)), 0.0, 0.1);
	cs_camera_ray(&c, 1800, 0, &d);
	CHECK_NEAR(d.z, 1.0, 1e-4); /* the top row: the zenith */
	cs_camera_ray(&c, 1800, 450, &d);
	CHECK_NEAR(angle_deg(d, enu(30, 45)), 0.0, 0.1);
}

static const struct t_case t_cases[] = {
	CASE(centre_ray_points_where_the_camera_looks),
	CASE(perspective_edges_are_at_half_the_field_of_view),
	CASE(fisheye_is_the_sky_seen_from_below),
	CASE(equirect_spans_all_azimuths),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
