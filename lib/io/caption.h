/* caption.h - text stamped on a frame: a built-in 5x7 bitmap font (ASCII
 * 32..126, the character ROM of an HD44780-style LCD), scaled to the
 * frame's height, on a darkened box in the lower left corner. */
#ifndef CS_CAPTION_H
#define CS_CAPTION_H

#include <stddef.h>

/* The rows of a character's 5x7 glyph, top first, bit 4 the left column;
 * a byte outside 32..126 has the glyph of '?'. */
const unsigned char *cs_caption_glyph(unsigned char c);

/* The glyphs' scale for a frame height: height / 360 rounded, at least 1
 * (1 up to 539 pixels, 2 from 540: 1280x720 has 10x14-pixel letters, 3
 * from 900, ...). */
int cs_caption_scale(int height);

/* Stamps text (lines separated by '\n'; a line too long for the width is
 * wrapped at a space) in the lower left corner of a width x height image
 * of floats, stride floats a pixel, R G B first, row 0 at the top: the
 * glyphs' pixels get white in R, G and B and 1 in alpha_channel (when
 * >= 0), the box behind them is darkened to 35 %.  Returns the lines
 * drawn. */
int cs_caption_stamp(float *px, size_t stride, int width, int height, int alpha_channel,
		     const char *text, float white);

#endif
