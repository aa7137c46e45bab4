/* exrpixels - every pixel of an EXR's channels, for the tool tests that
 * compare two renders' pixels whatever their attributes say.
 *
 *   exrpixels FILE CHANNEL...   "WIDTHxHEIGHT", then one line a pixel
 *                               (row 0 first): the channels' values, exact
 *                               (C99 hexadecimal floats)
 *
 * Exit 1 when the file cannot be read or lacks a channel. */
#include "core/err.h"
#include "core/fileio.h"
#include "io/exr.h"

#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv)
{
	if (argc < 3) {
		fprintf(stderr, "usage: exrpixels FILE CHANNEL...\n");
		return 2;
	}
	unsigned char *data;
	size_t len;
	if (cs_read_all(argv[1], (size_t)1 << 30, &data, &len) != CS_OK) {
		fprintf(stderr, "exrpixels: %s\n", cs_errmsg());
		return 1;
	}
	int nch = argc - 2, w, h;
	float *px;
	if (cs_exr_read_channels(data, len, argv[1], (const char *const *)argv + 2, nch, &w,
				 &h, &px) != CS_OK) {
		fprintf(stderr, "exrpixels: %s\n", cs_errmsg());
		free(data);
		return 1;
	}
	free(data);
	printf("%dx%d\n", w, h);
	for (long i = 0; i < (long)w * h; i++)
		for (int c = 0; c < nch; c++)
			printf("%a%c", (double)px[i * nch + c], c == nch - 1 ? '\n' : ' ');
	free(px);
	return 0;
}
