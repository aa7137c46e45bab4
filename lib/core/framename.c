#include "core/framename.h"

#include "core/err.h"

#include <stdio.h>
#include <string.h>

/* The conversion at p[0] == '%': its total length in *len and its padding
 * width in *width (-1 for "%%"); CS_EINVAL for any other. */
static int conversion(const char *pattern, const char *p, size_t *len, int *width)
{
	const char *q = p + 1;
	if (*q == '%') {
		*len = 2, *width = -1;
		return CS_OK;
	}
	int w = 0;
	while (*q >= '0' && *q <= '9') {
		w = w * 10 + (*q++ - '0');
		if (w > CS_FRAMENAME_MAX_WIDTH)
			return cs_error(CS_EINVAL, "'%s': the width of the frame number at byte "
					"%zu is more than %d digits", pattern,
					(size_t)(p - pattern), CS_FRAMENAME_MAX_WIDTH);
	}
	if (*q != 'd')
		return cs_error(CS_EINVAL, "'%s': '%.*s' at byte %zu is not a frame number: use "
				"%%d or %%05d for the number, %%%% for a literal percent",
				pattern, *q ? (int)(q - p + 1) : (int)(q - p), p,
				(size_t)(p - pattern));
	*len = (size_t)(q - p + 1), *width = w;
	return CS_OK;
}

int cs_framename_check(const char *pattern)
{
	if (pattern == NULL)
		return cs_error(CS_EINVAL, "no output name");
	int numbers = 0;
	for (const char *p = pattern; *p; ) {
		if (*p != '%') {
			p++;
			continue;
		}
		size_t len;
		int width;
		CS_TRY(conversion(pattern, p, &len, &width));
		if (width >= 0 && ++numbers > 1)
			return cs_error(CS_EINVAL, "'%s': more than one frame number (at byte "
					"%zu)", pattern, (size_t)(p - pattern));
		p += len;
	}
	return numbers;
}

int cs_framename_format(const char *pattern, long long n, char *buf, size_t size)
{
	int rc = cs_framename_check(pattern);
	if (rc < 0)
		return rc;
	if (n < 0)
		return cs_error(CS_EINVAL, "frame number %lld is negative", n);
	size_t k = 0;
	for (const char *p = pattern; *p; ) {
		char piece[48];
		size_t len = 1, plen;
		int width = -2;
		if (*p == '%')
			conversion(pattern, p, &len, &width); /* checked above */
		if (width == -2)
			piece[0] = *p, plen = 1;
		else if (width == -1)
			piece[0] = '%', plen = 1;
		else
			plen = (size_t)snprintf(piece, sizeof piece, "%0*lld", width, n);
		if (k + plen >= size)
			return cs_error(CS_EINVAL, "'%s': the name of frame %lld is longer than "
					"%zu bytes", pattern, n, size ? size - 1 : 0);
		memcpy(buf + k, piece, plen);
		k += plen;
		p += len;
	}
	if (size == 0)
		return cs_error(CS_EINVAL, "'%s': no room for the name", pattern);
	buf[k] = '\0';
	return CS_OK;
}
