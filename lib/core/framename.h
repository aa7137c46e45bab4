/* framename.h - output names numbered printf-style, as ffmpeg's image2
 * muxer numbers them: "frames/%05d.png" with frame 42 is "frames/00042.png".
 *
 * A pattern holds at most one number conversion: "%d" (no padding), or
 * "%Nd" and "%0Nd" (both zero-padded to N digits, N = 1..CS_FRAMENAME_MAX_WIDTH,
 * as ffmpeg pads "%5d" with zeros too); "%%" is a literal percent.  Any other
 * conversion ("%s", "%x", "%-5d", "%i", a lone "%") is refused, so that a
 * name is never taken literally by mistake. */
#ifndef CS_FRAMENAME_H
#define CS_FRAMENAME_H

#include <stddef.h>

#define CS_FRAMENAME_MAX_WIDTH 20

/* 1 when pattern holds a frame number, 0 when it is a literal name (no
 * conversion, "%%" allowed), CS_EINVAL when a conversion is refused (the
 * message names it and its byte offset). */
int cs_framename_check(const char *pattern);

/* The name of frame number n (>= 0) into buf of size bytes: the number
 * conversion replaced by n, "%%" by "%".  A literal pattern gives itself
 * (with "%%" as "%").  CS_EINVAL for a refused pattern, a negative n, or a
 * name that does not fit in size bytes. */
int cs_framename_format(const char *pattern, long long n, char *buf, size_t size);

#endif
