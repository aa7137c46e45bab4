#include "core/geo.h"

#include "core/vec.h"

#include <math.h>

double cs_great_circle_m(double lat1_deg, double lon1_deg, double lat2_deg,
			 double lon2_deg)
{
	const double k = CS_PI / 180.0;
	double a = sin((lat2_deg - lat1_deg) * k / 2);
	double b = sin((lon2_deg - lon1_deg) * k / 2);
	double h = a * a + cos(lat1_deg * k) * cos(lat2_deg * k) * b * b;
	/* rounding can push h just above 1 near the antipode */
	return 2.0 * CS_EARTH_RADIUS_M * asin(sqrt(h < 1.0 ? h : 1.0));
}

int cs_look_at(double radius_m, double eye_lat_deg, double eye_lon_deg, double eye_alt_m,
	       double lat_deg, double lon_deg, double alt_m, double *azimuth_deg,
	       double *elevation_deg)
{
	const double k = CS_PI / 180.0;
	double p1 = eye_lat_deg * k, p2 = lat_deg * k, dl = (lon_deg - eye_lon_deg) * k;
	double r1 = radius_m + eye_alt_m, r2 = radius_m + alt_m;
	/* the target in the eye's east, north and up (the eye at r1 up): the
	 * rotation written out, so that a target due north has east 0 exactly */
	double e = r2 * cos(p2) * sin(dl);
	double n = r2 * (cos(p1) * sin(p2) - sin(p1) * cos(p2) * cos(dl));
	double u = r2 * (sin(p1) * sin(p2) + cos(p1) * cos(p2) * cos(dl)) - r1;
	double h = sqrt(e * e + n * n);
	if (h < 1e-6 && fabs(u) < 1e-6) /* a micrometre: the same point */
		return -1;
	double az = atan2(e, n) / k;
	if (az < 0.0)
		az += 360.0;
	*azimuth_deg = az >= 360.0 ? az - 360.0 : az;
	*elevation_deg = atan2(u, h) / k;
	return 0;
}
