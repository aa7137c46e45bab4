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
