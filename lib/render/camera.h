/* camera.h - the pinhole camera: a frame at a world position, looking at an
 * azimuth and elevation in the local east-north-up frame there. */
#ifndef CS_CAMERA_H
#define CS_CAMERA_H

#include "core/hd.h"
#include "core/vec.h"

#include <stddef.h>

struct cs_scene;

/* How pixels map to directions. */
enum cs_projection {
	CS_PROJ_PERSPECTIVE, /* pinhole, horizontal field of view */
	CS_PROJ_FISHEYE,     /* all-sky camera looking up: equidistant, the
				horizon on the largest circle, north up and
				east left (the sky seen from below) */
	CS_PROJ_EQUIRECT     /* 360 x 180 environment map: azimuth across (the
				look azimuth in the middle, east to its
				right), elevation from +90 at the top to -90 */
};

struct cs_camera {
	int width, height;      /* pixels */
	cs_v3 pos;              /* world position */
	cs_v3 fwd, right, up;   /* orthonormal: view direction, image right, image up */
	double tan_half_fov;    /* horizontal */
	enum cs_projection projection;
	cs_v3 east, north, zenith; /* the local frame at pos */
	double azimuth_rad;     /* the look azimuth (equirect's middle) */
};

/* The projection's name ("perspective", "fisheye", "equirect") to its
 * value: 0 or CS_EINVAL. */
int cs_projection_parse(const char *name, enum cs_projection *p);

/* A camera at world position pos looking at azimuth (deg from north,
 * clockwise) and elevation (deg) in the local frame at pos, with a
 * horizontal field of view in degrees.  origin_lat_deg fixes the direction
 * of north.  0 or CS_EINVAL. */
int cs_camera_init(struct cs_camera *c, const struct cs_scene *sc, cs_v3 pos,
		   double origin_lat_deg, double azimuth_deg, double elevation_deg,
		   double fov_deg, int width, int height);

/* The default view (man 1 cloudrender, DEFAULT VIEW): where to look from
 * an eye at eye_alt_m (m above sea level) at the scene's site with a
 * perspective camera of horizontal field fov_deg and a width x height
 * image.  Azimuth: with the sun up, away from it (the clouds lit from the
 * front, as photographers shoot them); with the sun down, toward it (the
 * twilight); when only far sites have clouds, toward the one with the most
 * cover (far_x, far_y: their world positions, nfar of them).  Elevation:
 * 8 deg, or higher when the haze and fog would hide the lowest layer's
 * base: the lowest elevation at which the base is seen through an optical
 * depth of at most CS_VIEW_MAX_DEPTH (flat Earth) is kept a quarter of the
 * frame below its top edge, at most CS_VIEW_MAX_ELEVATION_DEG.  why gets a short reason. */
#define CS_VIEW_DEFAULT_ELEVATION_DEG 8.0
#define CS_VIEW_MAX_DEPTH 1.5 /* transmittance e^-1.5 = 22 % */
#define CS_VIEW_MAX_ELEVATION_DEG 60.0 /* the horizon's side stays in view */
void cs_default_look(const struct cs_scene *sc, double eye_alt_m, double fov_deg,
		     int width, int height, const double *far_x, const double *far_y,
		     int nfar, double *azimuth_deg, double *elevation_deg, char *why,
		     size_t why_size);

/* The world direction through the centre of pixel (i, j), j = 0 at the
 * top, into *d: 1, or 0 for a pixel outside a fisheye's circle. */
CS_HD int cs_camera_ray(const struct cs_camera *c, int i, int j, cs_v3 *d);

#endif
