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
