/* json.h - scanning JSON text without parsing it: where strings and
 * containers end, whether a text was cut short, an excerpt for a message,
 * and re-indenting.  Parsing itself is cJSON's. */
#ifndef CS_JSON_H
#define CS_JSON_H

#include <stddef.h>

/* The index just past the string whose opening quote is s[i] (escapes
 * skipped), or len when the text ends inside it. */
size_t cs_json_string_end(const char *s, size_t len, size_t i);

/* The index just past the object or array that opens at s[i], or len when
 * the text ends first; *flat = 1 when it holds no object or array. */
size_t cs_json_container_end(const char *s, size_t len, size_t i, int *flat);

/* 1 when the text stops inside a string or with objects or arrays still
 * open, and no bracket outside a string stands at or after byte from: the
 * mark of a cut transfer, whatever a parser stumbled on first (cJSON
 * reports a cut string or number where it starts, so pass its error
 * offset; len when any ending counts). */
int cs_json_cut_short(const char *s, size_t len, size_t from);

/* The excerpt of s (len bytes, NUL not needed) to quote near byte at:
 * [*from, *to), at most 10 bytes before at (cJSON sometimes reports one
 * byte past the fault) and 20 from it, stopping at a control character so
 * that a message stays on one line. */
void cs_json_near(const char *s, size_t len, size_t at, size_t *from,
		  size_t *to);

/* The JSON text json (NUL-terminated) indented: two spaces a level, an
 * object or array with no object or array inside on one line.  *out
 * malloc'ed for the caller.  CS_ENOMEM. */
int cs_json_pretty(const char *json, char **out);

#endif
