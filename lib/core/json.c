#include "core/json.h"

#include "core/err.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The index of the quote that closes the string opening at s[i], or len. */
static size_t string_close(const char *s, size_t len, size_t i)
{
	for (i++; i < len; i++) {
		if (s[i] == '\\')
			i++;
		else if (s[i] == '"')
			return i;
	}
	return len;
}

size_t cs_json_string_end(const char *s, size_t len, size_t i)
{
	size_t q = string_close(s, len, i);
	return q < len ? q + 1 : len;
}

size_t cs_json_container_end(const char *s, size_t len, size_t i, int *flat)
{
	int depth = 0;
	*flat = 1;
	while (i < len) {
		char c = s[i];
		if (c == '"') {
			i = cs_json_string_end(s, len, i);
			continue;
		}
		if (c == '{' || c == '[') {
			if (++depth > 1)
				*flat = 0;
		} else if ((c == '}' || c == ']') && --depth == 0) {
			return i + 1;
		}
		i++;
	}
	return len;
}

int cs_json_cut_short(const char *s, size_t len, size_t from)
{
	int depth = 0, in_string = 0, after = 0;
	size_t i = 0;
	while (i < len) {
		char c = s[i];
		if (c == '"') {
			size_t q = string_close(s, len, i);
			in_string = q >= len;
			i = q + 1;
			continue;
		}
		if (c == '{' || c == '[')
			depth++;
		else if (c == '}' || c == ']')
			depth--;
		if (i >= from && c != '\0' && strchr("{}[]", c) != NULL)
			after = 1;
		i++;
	}
	return (in_string || depth > 0) && !after;
}

void cs_json_near(const char *s, size_t len, size_t at, size_t *from,
		  size_t *to)
{
	if (at > len)
		at = len;
	*from = at, *to = at;
	while (*from > 0 && at - *from < 10 &&
	       (unsigned char)s[*from - 1] >= 0x20)
		(*from)--;
	while (*to < len && *to - at < 20 && (unsigned char)s[*to] >= 0x20)
		(*to)++;
}

static void indent(FILE *f, int depth)
{
	fputc('\n', f);
	for (int d = 0; d < depth; d++)
		fputs("  ", f);
}

/* Writes one character outside strings and whitespace; inner: inside a
 * container written on one line. */
static void pretty_char(FILE *f, char c, int inner, int *depth)
{
	fputc(c, f);
	if (inner && (c == ',' || c == ':'))
		fputc(' ', f);
	else if (!inner && (c == '{' || c == '['))
		indent(f, ++*depth);
	else if (!inner && c == ',')
		indent(f, *depth);
	else if (!inner && c == ':')
		fputc(' ', f);
}

int cs_json_pretty(const char *json, char **out)
{
	char *buf = NULL;
	size_t size, flat_end = 0, len = strlen(json);
	int depth = 0;
	FILE *f = open_memstream(&buf, &size);
	if (f == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	for (size_t i = 0; i < len; i++) {
		char c = json[i];
		if (c == '"') {
			size_t e = cs_json_string_end(json, len, i);
			fwrite(json + i, 1, e - i, f);
			i = e - 1;
		} else if (c != ' ' && c != '\t' && c != '\n' && c != '\r') {
			int flat = 0;
			if ((c == '{' || c == '[') && i >= flat_end) {
				size_t e = cs_json_container_end(json, len, i, &flat);
				if (flat)
					flat_end = e;
			}
			pretty_char(f, c, i < flat_end, &depth);
		}
		/* before the closing bracket of a multi-line container */
		if (i + 1 >= flat_end && depth > 0 &&
		    (json[i + 1] == '}' || json[i + 1] == ']'))
			indent(f, --depth);
	}
	fputc('\n', f);
	int bad = ferror(f);
	if (fclose(f) != 0 || bad) {
		free(buf);
		return cs_error(CS_ENOMEM, "out of memory");
	}
	*out = buf;
	return CS_OK;
}
