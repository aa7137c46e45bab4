#include "noise/cache.h"

#include "core/err.h"
#include "core/fileio.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define MAGIC "cloudscape noise cache 1\n"

int cs_noise_cache_dir(char *buf, size_t size)
{
	const char *off = getenv("CLOUDSCAPE_NO_CACHE");
	const char *xdg = getenv("XDG_CACHE_HOME"), *home = getenv("HOME");
	int n = 0;
	if (off != NULL && off[0] != '\0' && strcmp(off, "0") != 0)
		n = 0;
	else if (xdg != NULL && xdg[0] == '/') /* XDG: a relative path is ignored */
		n = snprintf(buf, size, "%s/cloudscape", xdg);
	else if (home != NULL && home[0] != '\0')
		n = snprintf(buf, size, "%s/.cache/cloudscape", home);
	if (n <= 0 || (size_t)n >= size)
		n = 0;
	if (size > 0 && n == 0)
		buf[0] = '\0';
	return n;
}

/* FNV-1a, 64 bits. */
static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
	const unsigned char *b = p;
	for (size_t i = 0; i < n; i++)
		h = (h ^ b[i]) * 0x100000001b3ull;
	return h;
}

/* What makes the volume, one line. */
static void describe(const struct cs_volume *v, char *buf, size_t size)
{
	char recipe[256];
	cs_noise_recipe_format(&v->recipe, recipe, sizeof recipe);
	snprintf(buf, size, "version=%s;size=%dx%dx%d;seed=%u;%s;float32le\n", CS_VERSION,
		 v->nx, v->ny, v->nz, (unsigned)v->recipe.seed, recipe);
}

static int mkdirs(char *path)
{
	for (char *s = path + 1; *s; s++)
		if (*s == '/') {
			*s = '\0';
			int rc = mkdir(path, 0777);
			*s = '/';
			if (rc != 0 && errno != EEXIST)
				return -1;
		}
	return mkdir(path, 0777) == 0 || errno == EEXIST ? 0 : -1;
}

/* 1 when path holds exactly the volume described by desc (and fills v). */
static int load(struct cs_volume *v, const char *path, const char *desc)
{
	FILE *f = fopen(path, "rb");
	if (f == NULL)
		return 0;
	size_t nd = strlen(desc), nm = strlen(MAGIC), nf = (size_t)v->nx * v->ny * v->nz * 4;
	char head[512];
	uint64_t sum = 0;
	int ok = nm + nd < sizeof head && fread(head, 1, nm + nd, f) == nm + nd &&
		 memcmp(head, MAGIC, nm) == 0 && memcmp(head + nm, desc, nd) == 0 &&
		 fread(v->data, sizeof(float), nf, f) == nf && fread(&sum, sizeof sum, 1, f) == 1 &&
		 fgetc(f) == EOF &&
		 sum == fnv(0xcbf29ce484222325ull, v->data, nf * sizeof(float));
	fclose(f);
	return ok;
}

static void store(const struct cs_volume *v, const char *dir, const char *path,
		  const char *desc)
{
	char d[4096];
	snprintf(d, sizeof d, "%s", dir);
	if (mkdirs(d) != 0)
		return;
	struct cs_outfile of;
	size_t nf = (size_t)v->nx * v->ny * v->nz * 4;
	uint64_t sum = fnv(0xcbf29ce484222325ull, v->data, nf * sizeof(float));
	if (cs_outfile_open(&of, path) != CS_OK)
		return;
	if (cs_outfile_write(&of, MAGIC, strlen(MAGIC)) != CS_OK ||
	    cs_outfile_write(&of, desc, strlen(desc)) != CS_OK ||
	    cs_outfile_write(&of, v->data, nf * sizeof(float)) != CS_OK ||
	    cs_outfile_write(&of, &sum, sizeof sum) != CS_OK || cs_outfile_commit(&of) != CS_OK)
		cs_outfile_abort(&of);
}

int cs_noise_cache_bake(struct cs_volume *v, int nthreads, int *hit)
{
	char dir[4096], path[4200], desc[400];
	*hit = 0;
	int rc = cs_noise_recipe_check(&v->recipe);
	if (rc != CS_OK || v->data == NULL || cs_noise_cache_dir(dir, sizeof dir) == 0)
		return cs_volume_bake(v, nthreads, NULL, NULL);
	describe(v, desc, sizeof desc);
	snprintf(path, sizeof path, "%s/noise-%dx%dx%d-%016llx.bin", dir, v->nx, v->ny, v->nz,
		 (unsigned long long)fnv(0xcbf29ce484222325ull, desc, strlen(desc)));
	if (load(v, path, desc)) {
		*hit = 1;
		return CS_OK;
	}
	rc = cs_volume_bake(v, nthreads, NULL, NULL);
	if (rc == CS_OK)
		store(v, dir, path, desc);
	return rc;
}
