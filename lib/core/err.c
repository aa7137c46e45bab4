#include "core/err.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

static _Thread_local char last_msg[1024];

int cs_error(int code, const char *fmt, ...)
{
	/* format into a local first: an argument may be cs_errmsg() itself */
	char buf[sizeof last_msg];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(buf, sizeof buf, fmt, ap);
	va_end(ap);
	memcpy(last_msg, buf, sizeof buf);
	return code;
}

const char *cs_errmsg(void)
{
	return last_msg;
}
