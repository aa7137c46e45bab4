/* The default view (camera.h, cs_default_look): look where the clouds are. */
#include "render/camera.h"

#include "render/march.h"
#include "render/render.h"

#include <math.h>
#include <stdio.h>

/* Azimuth (deg from north, clockwise) of a local east-north-up vector. */
static double azimuth_of(double east, double north)
{
	double a = atan2(east, north) * 180.0 / CS_PI;
	return a < 0.0 ? a + 360.0 : a;
}

void cs_default_look(const struct cs_scene *sc, double eye_alt_m, double fov_deg,
		     int width, int height, const double *far_x, const double *far_y,
		     int nfar, double *azimuth_deg, double *elevation_deg, char *why,
		     size_t why_size)
{
	/* the lowest layer of the site, else the far site with the most cover */
	int lowest = -1, best_far = -1;
	double far_cover = 0.0;
	for (int i = 0; i < sc->nlayers; i++) {
		const struct cs_cloud_layer *l = &sc->layers[i];
		if (l->site < 0 && (lowest < 0 || l->base_m < sc->layers[lowest].base_m))
			lowest = i;
		if (l->site >= 0 && l->site < nfar && l->coverage > far_cover) {
			far_cover = l->coverage;
			best_far = l->site;
		}
	}
	double sun_az = azimuth_of(sc->sun_dir.x, sc->sun_dir.y);
	const char *az_why;
	if (lowest < 0 && best_far >= 0) {
		*azimuth_deg = azimuth_of(far_x[best_far], far_y[best_far]);
		az_why = "toward the far site with the most cloud";
		for (int i = 0; i < sc->nlayers; i++)
			if (sc->layers[i].site == best_far &&
			    (lowest < 0 || sc->layers[i].base_m < sc->layers[lowest].base_m))
				lowest = i;
	} else if (sc->sun_dir.z > 0.0) {
		*azimuth_deg = fmod(sun_az + 180.0, 360.0);
		az_why = "away from the sun";
	} else {
		*azimuth_deg = sun_az;
		az_why = "toward the sun below the horizon";
	}
	double el = CS_VIEW_DEFAULT_ELEVATION_DEG;
	const char *el_why = "";
	double vfov = 2.0 * atan(tan(fov_deg * CS_PI / 360.0) * height / width) * 180.0 / CS_PI;
	if (lowest >= 0 && sc->layers[lowest].base_m > eye_alt_m) {
		double hb = sc->layers[lowest].base_m - eye_alt_m;
		double tau = cs_haze_depth(sc, eye_alt_m, 1.0, hb) +
			     cs_fog_depth(sc, eye_alt_m, 1.0, hb);
		double s = tau / CS_VIEW_MAX_DEPTH;
		double e_min = s < 1.0 ? asin(s) * 180.0 / CS_PI : 90.0;
		double need = e_min - vfov / 4.0;
		if (need > el) {
			el = need < CS_VIEW_MAX_ELEVATION_DEG ? need : CS_VIEW_MAX_ELEVATION_DEG;
			el_why = ", raised to see the lowest base through the haze";
		}
	}
	*elevation_deg = el;
	snprintf(why, why_size, "%s%s", az_why, el_why);
}
