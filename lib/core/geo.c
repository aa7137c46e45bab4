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

/* Earth-centred: x toward (0, 0), z toward the north pole. */
static void ecef(double r, double lat, double lon, double p[3])
{
	p[0] = r * cos(lat) * cos(lon);
	p[1] = r * cos(lat) * sin(lon);
	p[2] = r * sin(lat);
}

int cs_look_at(double radius_m, double eye_lat_deg, double eye_lon_deg, double eye_alt_m,
	       double lat_deg, double lon_deg, double alt_m, double *azimuth_deg,
	       double *elevation_deg)
{
	const double k = CS_PI / 180.0;
	double la = eye_lat_deg * k, lo = eye_lon_deg * k, a[3], b[3], d[3];
	ecef(radius_m + eye_alt_m, la, lo, a);
	ecef(radius_m + alt_m, lat_deg * k, lon_deg * k, b);
	for (int i = 0; i < 3; i++)
		d[i] = b[i] - a[i];
	/* the eye's east, north and up, dotted with the line of sight */
	double e = -sin(lo) * d[0] + cos(lo) * d[1];
	double n = -sin(la) * cos(lo) * d[0] - sin(la) * sin(lo) * d[1] + cos(la) * d[2];
	double u = cos(la) * cos(lo) * d[0] + cos(la) * sin(lo) * d[1] + sin(la) * d[2];
	double h = sqrt(e * e + n * n);
	if (h == 0.0 && u == 0.0)
		return -1;
	double az = atan2(e, n) / k;
	*azimuth_deg = az < 0.0 ? az + 360.0 : az;
	*elevation_deg = atan2(u, h) / k;
	return 0;
}
