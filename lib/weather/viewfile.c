#include "weather/viewfile.h"

#include "core/err.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* The numeric fields and their ranges (those of cloudrender's options). */
static const struct {
	const char *what;
	double lo, hi;
} fields[] = {
	{"latitude", -89.9, 89.9},     {"longitude", -180.0, 180.0},
	{"altitude", -500.0, 100000.0}, {"azimuth", -360.0, 360.0},
	{"elevation", -90.0, 90.0},    {"field of view", 1.0, 179.0},
};
enum { NFIELDS = 6 };

static int bad(const char *path, int line, const char *what, const char *tok)
{
	return cs_error(CS_EDATA, "%s:%d: %s%s%s%s", path, line, what, tok ? " '" : "",
			tok ? tok : "", tok ? "'" : "");
}

/* One view line (comment and newline already cut) into view i of set. */
static int parse_line(const char *path, int line, char *s, struct cs_viewset *set)
{
	char *save = NULL, *tok = strtok_r(s, " \t\r", &save);
	if (tok == NULL)
		return CS_OK; /* blank */
	size_t len = strlen(tok);
	if (len >= CS_VIEWFILE_NAME)
		return bad(path, line, "name longer than 31 characters:", tok);
	for (size_t k = 0; k < len; k++)
		if (!isalnum((unsigned char)tok[k]) && tok[k] != '-' && tok[k] != '_')
			return bad(path, line, "a name is letters, digits, '-' and '_', not", tok);
	for (int i = 0; i < set->n; i++)
		if (strcasecmp(set->names[i], tok) == 0)
			return bad(path, line, "a second view named", tok);
	if (set->n == CS_VIEWFILE_MAX)
		return cs_error(CS_EDATA, "%s:%d: more than %d views", path, line, CS_VIEWFILE_MAX);
	int i = set->n;
	snprintf(set->names[i], CS_VIEWFILE_NAME, "%s", tok);
	double v[NFIELDS];
	for (int f = 0; f < NFIELDS; f++) {
		tok = strtok_r(NULL, " \t\r", &save);
		if (tok == NULL) {
			char what[192];
			snprintf(what, sizeof what, "the %s is missing (a view is NAME LAT_DEG "
				 "LON_DEG ALT_M AZIMUTH_DEG ELEVATION_DEG FOV_DEG)", fields[f].what);
			return bad(path, line, what, NULL);
		}
		char *end;
		errno = 0;
		v[f] = strtod(tok, &end);
		if (end == tok || *end != '\0' || errno == ERANGE || !isfinite(v[f])) {
			char what[64];
			snprintf(what, sizeof what, "the %s is not a number:", fields[f].what);
			return bad(path, line, what, tok);
		}
		if (v[f] < fields[f].lo || v[f] > fields[f].hi) {
			char what[96];
			snprintf(what, sizeof what, "the %s must be %g..%g, not", fields[f].what,
				 fields[f].lo, fields[f].hi);
			return bad(path, line, what, tok);
		}
	}
	/* the rest of the line, blanks squeezed at its ends, describes it */
	const char *rest = save ? save : "";
	while (*rest == ' ' || *rest == '\t')
		rest++;
	snprintf(set->text[i], CS_VIEWFILE_TEXT, "%s", rest);
	for (size_t k = strlen(set->text[i]); k > 0 && isspace((unsigned char)set->text[i][k - 1]);)
		set->text[i][--k] = '\0';
	set->places[i] = (struct cs_place){set->names[i], v[0], v[1], v[2], set->text[i]};
	set->views[i] = (struct cs_view){set->names[i], &set->places[i], 0.0, v[3], v[4], v[5],
					 set->text[i]};
	set->n++;
	return CS_OK;
}

int cs_viewset_read(const char *path, struct cs_viewset *set)
{
	set->n = 0;
	FILE *f = fopen(path, "r");
	if (f == NULL)
		return cs_error(CS_EIO, "%s: %s", path, strerror(errno));
	char buf[1024];
	int line = 0, rc = CS_OK;
	while (rc == CS_OK && fgets(buf, sizeof buf, f) != NULL) {
		line++;
		size_t n = strlen(buf);
		if (n == sizeof buf - 1 && buf[n - 1] != '\n' && !feof(f)) {
			rc = bad(path, line, "line longer than 1022 characters", NULL);
			break;
		}
		char *hash = strchr(buf, '#');
		if (hash)
			*hash = '\0';
		buf[strcspn(buf, "\n")] = '\0';
		rc = parse_line(path, line, buf, set);
	}
	if (rc == CS_OK && ferror(f))
		rc = cs_error(CS_EIO, "%s: read error", path);
	fclose(f);
	if (rc != CS_OK)
		set->n = 0;
	return rc;
}

const struct cs_view *cs_viewset_find(const struct cs_viewset *set, const char *name)
{
	for (int i = 0; set && i < set->n; i++)
		if (strcasecmp(set->names[i], name) == 0)
			return &set->views[i];
	return cs_view_find(name);
}
