#include "render/camera.h"

#include "core/err.h"
#include "render/render.h"

#include <math.h>
#include <string.h>
#include <strings.h>

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
	c->projection = CS_PROJ_PERSPECTIVE;
	c->east = east, c->north = north, c->zenith = up;
	c->azimuth_rad = az;
	return CS_OK;
}

int cs_projection_parse(const char *name, enum cs_projection *p)
{
	static const char *const names[] = {"perspective", "fisheye", "equirect"};
	for (int i = 0; i < 3; i++)
		if (strcasecmp(name, names[i]) == 0) {
			*p = (enum cs_projection)i;
			return CS_OK;
		}
	return cs_error(CS_EINVAL, "unknown projection '%s' (expected perspective, fisheye "
			"or equirect)", name);
}

/* The direction at zenith angle th and azimuth az (from north, clockwise). */
CS_HD static cs_v3 local_dir(const struct cs_camera *c, double th, double az)
{
	cs_v3 h = v3_add(v3_scale(c->east, sin(az)), v3_scale(c->north, cos(az)));
	return v3_norm(v3_add(v3_scale(h, sin(th)), v3_scale(c->zenith, cos(th))));
}

CS_HD CS_COLD int cs_camera_ray(const struct cs_camera *c, int i, int j, cs_v3 *d)
{
	double u = (i + 0.5) / c->width, v = (j + 0.5) / c->height;
	if (c->projection == CS_PROJ_FISHEYE) {
		/* the largest centred circle; x right, y up, in units of its radius */
		double r = (c->width < c->height ? c->width : c->height) * 0.5;
		double x = (i + 0.5 - c->width * 0.5) / r, y = (c->height * 0.5 - j - 0.5) / r;
		double rho = sqrt(x * x + y * y);
		if (rho > 1.0)
			return 0;
		*d = local_dir(c, rho * (CS_PI / 2.0), atan2(-x, y));
		return 1;
	}
	if (c->projection == CS_PROJ_EQUIRECT) {
		double el = (0.5 - v) * CS_PI;
		*d = local_dir(c, CS_PI / 2.0 - el, c->azimuth_rad + (u - 0.5) * 2.0 * CS_PI);
		return 1;
	}
	double sx = (2.0 * u - 1.0) * c->tan_half_fov;
	double sy = (1.0 - 2.0 * v) * c->tan_half_fov * c->height / c->width;
	*d = v3_norm(v3_add(c->fwd, v3_add(v3_scale(c->right, sx), v3_scale(c->up, sy))));
	return 1;
}
