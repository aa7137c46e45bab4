#include "render/camera.h"

#include "core/err.h"
#include "render/render.h"

#include <math.h>

int cs_camera_init(struct cs_camera *c, const struct cs_scene *sc, cs_v3 pos,
		   double origin_lat_deg, double azimuth_deg, double elevation_deg,
		   double fov_deg, int width, int height)
{
	if (width < 1 || height < 1 || width > 32768 || height > 32768)
		return cs_error(CS_EINVAL, "image size %dx%d out of range 1..32768",
				width, height);
	if (!(fov_deg > 0.0 && fov_deg < 180.0))
		return cs_error(CS_EINVAL, "field of view must be between 0 and 180 degrees");
	if (!(elevation_deg >= -90.0 && elevation_deg <= 90.0) || !isfinite(azimuth_deg))
		return cs_error(CS_EINVAL, "look elevation must be -90..90 degrees");
	double lat0 = origin_lat_deg * CS_PI / 180.0;
	cs_v3 up = v3_norm(v3(pos.x, pos.y, pos.z + sc->earth_radius_m));
	cs_v3 axis = v3(0.0, cos(lat0), sin(lat0)); /* the Earth's axis */
	cs_v3 east = v3_cross(axis, up);
	if (v3_len(east) < 1e-9) /* at a pole: any east will do */
		east = v3(1.0, 0.0, 0.0);
	east = v3_norm(east);
	cs_v3 north = v3_cross(up, east);
	double az = azimuth_deg * CS_PI / 180.0, el = elevation_deg * CS_PI / 180.0;
	cs_v3 horiz = v3_add(v3_scale(east, sin(az)), v3_scale(north, cos(az)));
	c->fwd = v3_norm(v3_add(v3_scale(horiz, cos(el)), v3_scale(up, sin(el))));
	cs_v3 right = v3_cross(c->fwd, up);
	c->right = v3_len(right) > 1e-9 ? v3_norm(right)
					 : v3_norm(v3_cross(c->fwd, north)); /* straight up or down */
	c->up = v3_cross(c->right, c->fwd);
	c->pos = pos;
	c->width = width;
	c->height = height;
	c->tan_half_fov = tan(fov_deg * CS_PI / 360.0);
	return CS_OK;
}

CS_HD cs_v3 cs_camera_ray(const struct cs_camera *c, int i, int j)
{
	double sx = (2.0 * (i + 0.5) / c->width - 1.0) * c->tan_half_fov;
	double sy = (1.0 - 2.0 * (j + 0.5) / c->height) * c->tan_half_fov *
		    c->height / c->width;
	return v3_norm(v3_add(c->fwd, v3_add(v3_scale(c->right, sx),
					     v3_scale(c->up, sy))));
}
