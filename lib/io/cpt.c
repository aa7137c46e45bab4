/* GMT colour palettes (cpt.h). */
#include "io/cpt.h"

#include "core/err.h"
#include "core/fileio.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* One colour in one token: "r/g/b" or a grey "v"; 0 or -1. */
static int colour1(const char *tok, float c[3])
{
	char buf[64], *end;
	snprintf(buf, sizeof buf, "%s", tok);
	const char *str = buf;
	int parts = strchr(buf, '/') ? 3 : 1;
	for (int k = 0; k < parts; k++) {
		double v = strtod(str, &end);
		if (end == str || !(v >= 0 && v <= 255) ||
		    *end != (k < parts - 1 ? '/' : '\0'))
			return -1;
		c[k] = (float)v;
		str = end + 1;
	}
	if (parts == 1)
		c[1] = c[2] = c[0];
	return 0;
}

/* One colour in three tokens "r g b"; 0 or -1. */
static int colour3(char *const *tok, float c[3])
{
	for (int k = 0; k < 3; k++) {
		char *end;
		double v = strtod(tok[k], &end);
		if (end == tok[k] || *end != '\0' || !(v >= 0 && v <= 255))
			return -1;
		c[k] = (float)v;
	}
	return 0;
}

static int number(const char *s, double *v)
{
	char *end;
	*v = strtod(s, &end);
	return end != s && *end == '\0' && isfinite(*v) ? 0 : -1;
}

int cs_cpt_parse(const char *text, struct cs_cpt *p)
{
	memset(p, 0, sizeof *p);
	int line = 0;
	const char *s = text;
	while (*s) {
		char buf[1024], *tok[16];
		size_t len = strcspn(s, "\n");
		line++;
		if (len >= sizeof buf)
			return cs_error(CS_EDATA, "line %d: too long", line);
		memcpy(buf, s, len);
		buf[len] = '\0';
		s += len + (s[len] == '\n');
		char *hash = strchr(buf, '#');
		if (hash) {
			char *m = strstr(hash, "COLOR_MODEL");
			if (m && !strstr(m, "RGB") && !strstr(m, "rgb"))
				return cs_error(CS_EDATA, "line %d: only the RGB colour model "
						"is read", line);
			*hash = '\0';
		}
		int n = 0;
		for (char *save = NULL, *t = strtok_r(buf, " \t\r;", &save);
		     t && n < 16; t = strtok_r(NULL, " \t\r;", &save))
			tok[n++] = t;
		if (n == 0)
			continue;
		if (strcmp(tok[0], "B") == 0 || strcmp(tok[0], "F") == 0 ||
		    strcmp(tok[0], "N") == 0) {
			float *c = tok[0][0] == 'B' ? p->b : tok[0][0] == 'F' ? p->f : p->nan;
			if (!(n == 2 && colour1(tok[1], c) == 0) &&
			    !(n == 4 && colour3(tok + 1, c) == 0))
				return cs_error(CS_EDATA, "line %d: '%s' needs one colour "
						"(r g b, r/g/b or grey)", line, tok[0]);
			*(tok[0][0] == 'B' ? &p->has_b : tok[0][0] == 'F' ? &p->has_f
									: &p->has_n) = 1;
			continue;
		}
		if (p->n == CS_CPT_MAX_SLICES)
			return cs_error(CS_EDATA, "line %d: more than %d slices", line,
					CS_CPT_MAX_SLICES);
		/* an annotation flag (L, U, B) may end the line */
		if ((n == 5 || n == 9) && strlen(tok[n - 1]) == 1 && strchr("LUB", tok[n - 1][0]))
			n--;
		int k = p->n, ok = 0;
		if (n == 8)
			ok = number(tok[0], &p->z0[k]) == 0 && colour3(tok + 1, p->c0[k]) == 0 &&
			     number(tok[4], &p->z1[k]) == 0 && colour3(tok + 5, p->c1[k]) == 0;
		else if (n == 4)
			ok = number(tok[0], &p->z0[k]) == 0 && colour1(tok[1], p->c0[k]) == 0 &&
			     number(tok[2], &p->z1[k]) == 0 && colour1(tok[3], p->c1[k]) == 0;
		if (!ok)
			return cs_error(CS_EDATA, "line %d: not 'z0 colour z1 colour' "
					"(colour: r g b, r/g/b or grey 0..255)", line);
		if (!(p->z1[k] > p->z0[k]))
			return cs_error(CS_EDATA, "line %d: z1 %g is not above z0 %g", line,
					p->z1[k], p->z0[k]);
		if (k > 0 && p->z0[k] < p->z1[k - 1])
			return cs_error(CS_EDATA, "line %d: slices must ascend "
					"(z0 %g is below the previous z1 %g)", line, p->z0[k],
					p->z1[k - 1]);
		p->n++;
	}
	if (p->n == 0)
		return cs_error(CS_EDATA, "no colour slices");
	return CS_OK;
}

int cs_cpt_read(const char *path, struct cs_cpt *p)
{
	unsigned char *data;
	size_t len;
	CS_TRY(cs_read_all(path, 1 << 22, &data, &len));
	char *text = (char *)malloc(len + 1);
	if (text == NULL) {
		free(data);
		return cs_error(CS_ENOMEM, "out of memory");
	}
	memcpy(text, data, len);
	text[len] = '\0';
	free(data);
	int rc = strlen(text) != len ? cs_error(CS_EDATA, "a NUL byte in the text")
				     : cs_cpt_parse(text, p);
	free(text);
	if (rc != CS_OK)
		return cs_error(rc, "%s: %s", strcmp(path, "-") == 0 ? "standard input" : path,
				cs_errmsg());
	return CS_OK;
}

CS_HD void cs_cpt_color(const struct cs_cpt *p, double z, double rgb[3])
{
	const float *c = NULL;
	if (isnan(z)) {
		for (int k = 0; k < 3; k++)
			rgb[k] = p->has_n ? p->nan[k] : 0.0;
		return;
	}
	if (z < p->z0[0])
		c = p->has_b ? p->b : p->c0[0];
	else if (z > p->z1[p->n - 1])
		c = p->has_f ? p->f : p->c1[p->n - 1];
	if (c) {
		for (int k = 0; k < 3; k++)
			rgb[k] = c[k];
		return;
	}
	/* the last slice whose z0 <= z (binary search) */
	int lo = 0, hi = p->n - 1;
	while (lo < hi) {
		int mid = (lo + hi + 1) / 2;
		if (p->z0[mid] <= z)
			lo = mid;
		else
			hi = mid - 1;
	}
	double t = (z - p->z0[lo]) / (p->z1[lo] - p->z0[lo]);
	t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t; /* a gap between slices: its end */
	for (int k = 0; k < 3; k++)
		rgb[k] = p->c0[lo][k] + t * (p->c1[lo][k] - p->c0[lo][k]);
}
