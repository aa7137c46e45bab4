/* exrpixel - reads channels of an EXR back for the tool tests.
 *
 *   exrpixel FILE X Y CHANNEL...   the channels' values at pixel (X, Y)
 *                                  (Y = 0 the top row), one line
 *   exrpixel FILE mean CHANNEL     the channel's mean over the image
 *
 * Prints "WIDTHxHEIGHT" first on its own line.  Exit 1 when the file cannot
 * be read or lacks a channel (the reader's message on stderr). */
#include "core/err.h"
#include "core/fileio.h"
#include "io/exr.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char **argv)
{
	int mean = argc == 4 && strcmp(argv[2], "mean") == 0;
	if (!mean && argc < 5) {
		fprintf(stderr, "usage: exrpixel FILE X Y CHANNEL... | FILE mean CHANNEL\n");
		return 2;
	}
	unsigned char *data;
	size_t len;
	if (cs_read_all(argv[1], (size_t)1 << 30, &data, &len) != CS_OK) {
		fprintf(stderr, "exrpixel: %s\n", cs_errmsg());
		return 1;
	}
	const char *const *ch = (const char *const *)argv + (mean ? 3 : 4);
	int nch = mean ? 1 : argc - 4, w, h;
	float *px;
	if (cs_exr_read_channels(data, len, argv[1], ch, nch, &w, &h, &px) != CS_OK) {
		fprintf(stderr, "exrpixel: %s\n", cs_errmsg());
		free(data);
		return 1;
	}
	free(data);
	printf("%dx%d\n", w, h);
	if (mean) {
		double s = 0.0;
		for (long i = 0; i < (long)w * h; i++)
			s += px[i];
		printf("%.6g\n", s / ((double)w * h));
	} else {
		int x = atoi(argv[2]), y = atoi(argv[3]);
		if (x < 0 || y < 0 || x >= w || y >= h) {
			fprintf(stderr, "exrpixel: pixel %d,%d outside %dx%d\n", x, y, w, h);
			free(px);
			return 1;
		}
		for (int c = 0; c < nch; c++)
			printf("%s%.6g", c ? " " : "", px[((long)y * w + x) * nch + c]);
		printf("\n");
	}
	free(px);
	return 0;
}
