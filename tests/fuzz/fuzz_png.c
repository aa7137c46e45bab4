/* fuzz_png - the PNG reader behind cloudrender --terrain-color (any PNG to
 * 8-bit RGB, image.h). */
#include "io/image.h"

#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	uint8_t *rgb = NULL;
	int w = 0, h = 0;
	if (cs_png_read_rgb8_mem(data, size, "fuzz.png", &rgb, &w, &h) == 0) {
		unsigned sum = 0;
		for (size_t i = 0; i < (size_t)w * h * 3; i++)
			sum += rgb[i]; /* the whole result is inside its buffer */
		(void)sum;
	}
	free(rgb);
	return 0;
}
