/* exrpatch - rewrites integer attributes in an OpenEXR header, to make the
 * hostile files the robustness tests need from a valid one (a data window
 * or a volume size the file cannot hold).  Works on the bytes: the
 * header is a list of NAME\0TYPE\0SIZE(int32 LE)VALUE up to an empty name.
 *
 *   exrpatch IN OUT NAME=INT[,INT...] ...
 *
 * Every INT replaces one little-endian int32 of NAME's value, in order
 * (box2i: xmin,ymin,xmax,ymax; v3i: x,y,z; int; compression: one byte).
 * Exit 1 when IN cannot be read or lacks NAME. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static unsigned char *slurp(const char *path, size_t *len)
{
	FILE *f = fopen(path, "rb");
	if (f == NULL)
		return NULL;
	size_t cap = 1 << 16, n = 0;
	unsigned char *b = malloc(cap);
	size_t got;
	while (b && (got = fread(b + n, 1, cap - n, f)) > 0) {
		n += got;
		if (n == cap) {
			unsigned char *nb = realloc(b, cap *= 2);
			if (nb == NULL)
				free(b);
			b = nb;
		}
	}
	fclose(f);
	*len = n;
	return b;
}

/* The offset of NAME's value in the header, or 0; *size its byte count. */
static size_t find_attr(const unsigned char *b, size_t len, const char *name,
			const char **type, int32_t *size)
{
	size_t at = 8; /* magic and version */
	while (at < len && b[at] != 0) {
		const char *n = (const char *)b + at;
		size_t nl = strnlen(n, len - at);
		const char *t = n + nl + 1;
		size_t tl = strnlen(t, len - (size_t)((const unsigned char *)t - b));
		size_t vat = (size_t)((const unsigned char *)t - b) + tl + 1;
		if (vat + 4 > len)
			return 0;
		memcpy(size, b + vat, 4);
		if (strcmp(n, name) == 0) {
			*type = t;
			return vat + 4;
		}
		at = vat + 4 + (size_t)*size;
	}
	return 0;
}

int main(int argc, char **argv)
{
	if (argc < 4) {
		fprintf(stderr, "usage: exrpatch IN OUT NAME=INT[,INT...] ...\n");
		return 2;
	}
	size_t len = 0;
	unsigned char *b = slurp(argv[1], &len);
	if (b == NULL) {
		fprintf(stderr, "exrpatch: cannot read %s\n", argv[1]);
		return 1;
	}
	for (int a = 3; a < argc; a++) {
		char name[256];
		const char *eq = strchr(argv[a], '=');
		if (eq == NULL || (size_t)(eq - argv[a]) >= sizeof name)
			return 2;
		memcpy(name, argv[a], (size_t)(eq - argv[a]));
		name[eq - argv[a]] = '\0';
		const char *type = NULL;
		int32_t size = 0;
		size_t v = find_attr(b, len, name, &type, &size);
		if (v == 0) {
			fprintf(stderr, "exrpatch: %s has no attribute %s\n", argv[1], name);
			return 1;
		}
		int one_byte = strcmp(type, "compression") == 0;
		const char *p = eq + 1;
		for (int k = 0; *p; k++) {
			long x = strtol(p, (char **)&p, 10);
			if (one_byte) {
				b[v] = (unsigned char)x;
			} else if ((k + 1) * 4 <= size) {
				uint32_t u = (uint32_t)(int32_t)x;
				unsigned char le[4] = {u & 255, (u >> 8) & 255,
						       (u >> 16) & 255, u >> 24};
				memcpy(b + v + k * 4, le, 4);
			}
			if (*p == ',')
				p++;
		}
	}
	FILE *f = fopen(argv[2], "wb");
	if (f == NULL || fwrite(b, 1, len, f) != len || fclose(f) != 0) {
		fprintf(stderr, "exrpatch: cannot write %s\n", argv[2]);
		return 1;
	}
	free(b);
	return 0;
}
