/* fmt.h - numbers as text that reads back to the same double. */
#ifndef CS_FMT_H
#define CS_FMT_H

#include <stddef.h>

/* v as the first of %.15g, %.16g, %.17g that strtod reads back to v
 * exactly (%.17g always does for IEEE 754 binary64): "0.1", "30000",
 * "0.30000000000000004"; "nan", "inf", "-inf" when not finite.  A size of
 * at least CS_FMT_DOUBLE_SIZE always holds the whole text. */
#define CS_FMT_DOUBLE_SIZE 32
void cs_fmt_double(char *buf, size_t size, double v);

/* The same text by value, for a printf argument: cs_num(v).s */
struct cs_num {
	char s[CS_FMT_DOUBLE_SIZE];
};
struct cs_num cs_num(double v);

/* v rounded to the given decimals (0..9), to the nearest as printf's %.*f
 * rounds the exact binary value, as the
 * shortest text that reads back to that rounded value: 1271.8967441392303
 * with 0 gives "1272", 4.4399999999999995 with 2 gives "4.44", 0.0134
 * with 3 gives "0.013"; never "-0".  Reading the text and rounding again
 * gives the same text. */
struct cs_num cs_num_round(double v, int decimals);

#endif
