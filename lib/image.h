/* image.h - image output: 8-bit PNG (libpng's simplified API). */
#ifndef CS_IMAGE_H
#define CS_IMAGE_H

#include <stdint.h>

/* Writes width x height pixels of 1 (grey), 3 (RGB, sRGB) or 4 (RGBA)
 * interleaved 8-bit channels, rows top to bottom, to path ("-" = stdout).
 * Atomic: no partial file on failure. */
int cs_png_write(const char *path, int width, int height, int channels,
		 const uint8_t *pixels);

#endif
