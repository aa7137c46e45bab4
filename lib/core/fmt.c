#include "core/fmt.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* Precision starts at 15, not 1: %g switches to an exponent when the
 * exponent reaches the precision, and 3e+04 for 30000 is shorter but not
 * what a reader expects; every double with 15 significant digits or fewer
 * comes out the same from %.15g as from the least precision that reads
 * back (its rounding to 15 digits is that decimal, trailing zeros cut). */
void cs_fmt_double(char *buf, size_t size, double v)
{
	if (size == 0)
		return;
	if (!isfinite(v)) {
		snprintf(buf, size, "%g", v);
		return;
	}
	for (int digits = 15; digits <= 17; digits++) {
		snprintf(buf, size, "%.*g", digits, v);
		if (strtod(buf, NULL) == v)
			return;
	}
}

struct cs_num cs_num(double v)
{
	struct cs_num n;
	cs_fmt_double(n.s, sizeof n.s, v);
	return n;
}

struct cs_num cs_num_round(double v, int decimals)
{
	if (!isfinite(v) || fabs(v) >= 1e15) /* no fraction left to round */
		return cs_num(v);
	if (decimals < 0)
		decimals = 0;
	if (decimals > 9)
		decimals = 9;
	/* through the decimal text, not v * 10^d: 1.005 is 1.00499999999999989
	 * and must round as the value it is, and the scaled product can
	 * round up across the half */
	char buf[64];
	snprintf(buf, sizeof buf, "%.*f", decimals, v);
	double r = strtod(buf, NULL);
	if (r == 0.0)
		r = 0.0; /* no "-0" */
	return cs_num(r);
}
