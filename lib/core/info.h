/* info.h - the one style of the programs' --info output (noisebake --info,
 * terrainprep --info): labelled lines as gdalinfo and exrheader print them,
 * "label: value", groups indented by two spaces under "label:"; or, with
 * json set, the same facts as one JSON object whose keys carry the units
 * ("pixel_size_m").  Text is built in memory; the caller prints it. */
#ifndef CS_INFO_H
#define CS_INFO_H

#include <stddef.h>

#define CS_INFO_MAX_DEPTH 8

struct cs_info {
	int json;              /* 1: JSON object, 0: labelled lines */
	char *buf;             /* the text so far (malloc'ed, NUL-terminated) */
	size_t len, cap;
	int depth;             /* open groups */
	int first[CS_INFO_MAX_DEPTH + 1]; /* no member yet at this depth */
	int failed;            /* out of memory: cs_info_finish fails */
};

void cs_info_init(struct cs_info *in, int json);

/* label: value (a JSON string at key). */
void cs_info_str(struct cs_info *in, const char *key, const char *label,
		 const char *value);

/* label: v unit, with prec decimals; JSON: the number at key rounded to
 * prec decimals (null when not finite).  unit may be NULL or "". */
void cs_info_num(struct cs_info *in, const char *key, const char *label,
		 double v, int prec, const char *unit);

/* label: v0<sep>v1... unit; JSON: an array of the n numbers. */
void cs_info_nums(struct cs_info *in, const char *key, const char *label,
		  const double *v, int n, int prec, const char *sep,
		  const char *unit);

/* label: (then the members indented); JSON: "key": { ... }. */
void cs_info_open(struct cs_info *in, const char *key, const char *label);
void cs_info_close(struct cs_info *in);

/* The finished text (closes the JSON object, adds the last newline); the
 * caller owns *text.  CS_ENOMEM if any step ran out of memory. */
int cs_info_finish(struct cs_info *in, char **text);

/* Frees an unfinished builder. */
void cs_info_free(struct cs_info *in);

#endif
