/* camera.h - the pinhole camera: a frame at a world position, looking at an
 * azimuth and elevation in the local east-north-up frame there. */
#ifndef CS_CAMERA_H
#define CS_CAMERA_H

#include "core/hd.h"
#include "core/vec.h"

struct cs_scene;

struct cs_camera {
	int width, height;      /* pixels */
	cs_v3 pos;              /* world position */
	cs_v3 fwd, right, up;   /* orthonormal: view direction, image right, image up */
	double tan_half_fov;    /* horizontal */
};

/* A camera at world position pos looking at azimuth (deg from north,
 * clockwise) and elevation (deg) in the local frame at pos, with a
 * horizontal field of view in degrees.  origin_lat_deg fixes the direction
 * of north.  0 or CS_EINVAL. */
int cs_camera_init(struct cs_camera *c, const struct cs_scene *sc, cs_v3 pos,
		   double origin_lat_deg, double azimuth_deg, double elevation_deg,
		   double fov_deg, int width, int height);

/* The world ray through the centre of pixel (i, j), j = 0 at the top. */
CS_HD cs_v3 cs_camera_ray(const struct cs_camera *c, int i, int j);

#endif
