/* The --info output style (info.h). */
#include "core/info.h"

#include "core/err.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void cs_info_init(struct cs_info *in, int json)
{
	memset(in, 0, sizeof *in);
	in->json = json;
	for (int i = 0; i <= CS_INFO_MAX_DEPTH; i++)
		in->first[i] = 1;
}

void cs_info_free(struct cs_info *in)
{
	free(in->buf);
	in->buf = NULL;
	in->len = in->cap = 0;
}

static void put(struct cs_info *in, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));

static void put(struct cs_info *in, const char *fmt, ...)
{
	if (in->failed)
		return;
	va_list ap;
	va_start(ap, fmt);
	int n = vsnprintf(NULL, 0, fmt, ap);
	va_end(ap);
	if (n < 0) {
		in->failed = 1;
		return;
	}
	if (in->len + (size_t)n + 1 > in->cap) {
		size_t cap = (in->cap ? in->cap * 2 : 256) + (size_t)n;
		char *b = realloc(in->buf, cap);
		if (b == NULL) {
			in->failed = 1;
			return;
		}
		in->buf = b;
		in->cap = cap;
	}
	va_start(ap, fmt);
	vsnprintf(in->buf + in->len, in->cap - in->len, fmt, ap);
	va_end(ap);
	in->len += (size_t)n;
}

static void put_json_string(struct cs_info *in, const char *s)
{
	put(in, "\"");
	for (; *s; s++) {
		unsigned char c = (unsigned char)*s;
		if (c == '"' || c == '\\')
			put(in, "\\%c", c);
		else if (c < 0x20)
			put(in, "\\u%04x", c);
		else
			put(in, "%c", c);
	}
	put(in, "\"");
}

/* Starts a member: the JSON separator and key, or the text indent and label. */
static void member(struct cs_info *in, const char *key, const char *label)
{
	if (in->json) {
		if (in->len == 0)
			put(in, "{");
		put(in, "%s\n%*s", in->first[in->depth] ? "" : ",",
		    2 * (in->depth + 1), "");
		in->first[in->depth] = 0;
		put_json_string(in, key);
		put(in, ": ");
	} else {
		put(in, "%*s%s:", 2 * in->depth, "", label);
	}
}

void cs_info_str(struct cs_info *in, const char *key, const char *label,
		 const char *value)
{
	member(in, key, label);
	if (in->json)
		put_json_string(in, value ? value : "");
	else
		put(in, " %s\n", value ? value : "");
}

/* A number with prec decimals, without a "-0". */
static void put_num(struct cs_info *in, double v, int prec)
{
	if (!isfinite(v)) {
		put(in, in->json ? "null" : "unknown");
		return;
	}
	char s[64];
	snprintf(s, sizeof s, "%.*f", prec, v);
	if (s[0] == '-' && strspn(s + 1, "0.") == strlen(s + 1))
		memmove(s, s + 1, strlen(s)); /* -0.00 -> 0.00 */
	put(in, "%s", s);
}

void cs_info_num(struct cs_info *in, const char *key, const char *label,
		 double v, int prec, const char *unit)
{
	cs_info_nums(in, key, label, &v, 1, prec, "", unit);
}

void cs_info_nums(struct cs_info *in, const char *key, const char *label,
		  const double *v, int n, int prec, const char *sep,
		  const char *unit)
{
	member(in, key, label);
	if (in->json) {
		if (n > 1)
			put(in, "[");
		for (int i = 0; i < n; i++) {
			put(in, "%s", i ? ", " : "");
			put_num(in, v[i], prec);
		}
		if (n > 1)
			put(in, "]");
		return;
	}
	put(in, " ");
	for (int i = 0; i < n; i++) {
		put(in, "%s", i ? sep : "");
		put_num(in, v[i], prec);
	}
	put(in, "%s%s\n", unit && unit[0] ? " " : "", unit ? unit : "");
}

void cs_info_open(struct cs_info *in, const char *key, const char *label)
{
	member(in, key, label);
	if (in->depth == CS_INFO_MAX_DEPTH) {
		in->failed = 1;
		return;
	}
	put(in, in->json ? "{" : "\n");
	in->depth++;
	in->first[in->depth] = 1;
}

void cs_info_close(struct cs_info *in)
{
	if (in->depth == 0) {
		in->failed = 1;
		return;
	}
	in->depth--;
	if (in->json)
		put(in, "\n%*s}", 2 * (in->depth + 1), "");
}

int cs_info_finish(struct cs_info *in, char **text)
{
	*text = NULL;
	while (in->depth > 0)
		cs_info_close(in);
	if (in->json)
		put(in, in->len == 0 ? "{}\n" : "\n}\n");
	if (in->failed || in->buf == NULL) {
		cs_info_free(in);
		return cs_error(CS_ENOMEM, "out of memory");
	}
	*text = in->buf;
	in->buf = NULL;
	return CS_OK;
}
