/* The caption's bitmap font and its placement: glyphs against the HD44780
 * A00 character ROM (Hitachi's datasheet, table 4), the scale a frame
 * height gets, the box darkened behind the text, wrapping at a space. */
#include "test.h"

#include "io/caption.h"

#include <stdlib.h>

/* Hitachi HD44780U datasheet, character ROM A00, rows top first. */
static const struct {
	char c;
	unsigned char rows[7];
} rom[] = {
	{'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}},
	{'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}},
	{'A', {0x0E, 0x11, 0x11, 0x11, 0x1F, 0x11, 0x11}},
	{'m', {0x00, 0x00, 0x1A, 0x15, 0x15, 0x11, 0x11}},
	{'%', {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03}},
	{'/', {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00}},
};

static void caption_glyphs_are_the_hd44780_rom(void)
{
	for (size_t i = 0; i < sizeof rom / sizeof rom[0]; i++)
		CHECK(memcmp(cs_caption_glyph((unsigned char)rom[i].c), rom[i].rows, 7) == 0);
	/* outside printable ASCII: '?' */
	CHECK(cs_caption_glyph(0xC3) == cs_caption_glyph('?'));
	CHECK(cs_caption_glyph('\t') == cs_caption_glyph('?'));
}

static void caption_scale_follows_the_height(void)
{
	CHECK(cs_caption_scale(90) == 1);
	CHECK(cs_caption_scale(360) == 1);
	CHECK(cs_caption_scale(539) == 1);
	CHECK(cs_caption_scale(540) == 2);
	CHECK(cs_caption_scale(720) == 2);
	CHECK(cs_caption_scale(1080) == 3);
	CHECK(cs_caption_scale(2160) == 6);
}

/* A 1280x720 grey frame with "2" stamped: at scale 2 the glyph's ROM bits
 * are 2x2 blocks at column 16 (margin 4 x 2 twice), one line of 18 rows:
 * box rows 720 - 8 - 30 = 682..711, glyph rows 690..703. */
static void caption_draws_the_glyph_on_a_darkened_box(void)
{
	int w = 1280, h = 720;
	float *px = malloc((size_t)w * h * 5 * sizeof *px);
	CHECK(px != NULL);
	if (px == NULL)
		return;
	for (size_t i = 0; i < (size_t)w * h * 5; i++)
		px[i] = 1.0f;
	CHECK(cs_caption_stamp(px, 5, w, h, 3, "2", 100.0f) == 1);
	int wrong = 0;
	for (int r = 0; r < 14; r++)
		for (int c = 0; c < 10; c++) {
			const float *p = px + ((size_t)(690 + r) * w + 16 + c) * 5;
			int on = (rom[1].rows[r / 2] >> (4 - c / 2)) & 1;
			wrong += on ? !(p[0] == 100.0f && p[3] == 1.0f)
				    : !(fabsf(p[0] - 0.35f) < 1e-6f && p[3] == 1.0f);
		}
	CHECK(wrong == 0);
	/* the box: 8..8+26 wide (one letter: 10 + 16), rows 682..711 */
	CHECK(fabsf(px[((size_t)682 * w + 8) * 5] - 0.35f) < 1e-6f);
	CHECK(fabsf(px[((size_t)711 * w + 33) * 5 + 2] - 0.35f) < 1e-6f);
	CHECK(px[((size_t)681 * w + 8) * 5] == 1.0f);  /* above it */
	CHECK(px[((size_t)712 * w + 8) * 5] == 1.0f);  /* below it */
	CHECK(px[((size_t)700 * w + 34) * 5] == 1.0f); /* right of it */
	CHECK(px[((size_t)700 * w + 7) * 5] == 1.0f);  /* left of it */
	CHECK(px[((size_t)700 * w + 20) * 5 + 4] == 1.0f); /* Z untouched */
	free(px);
}

/* 48 columns: (320 - 16) / 6 at scale 1; a longer line is cut at its last
 * space that fits. */
static void caption_wraps_a_long_line_at_a_space(void)
{
	int w = 320, h = 90;
	float *px = calloc((size_t)w * h * 5, sizeof *px);
	CHECK(px != NULL);
	if (px == NULL)
		return;
	CHECK(cs_caption_stamp(px, 5, w, h, 3, "aaaa bbbb cccc dddd eeee ffff gggg hhhh iiii jjjj kkkk", 1.0f) == 2);
	CHECK(cs_caption_stamp(px, 5, w, h, 3, "one\ntwo\nthree", 1.0f) == 3);
	CHECK(cs_caption_stamp(px, 5, 10, h, 3, "too narrow", 1.0f) == 0);
	free(px);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(caption_glyphs_are_the_hd44780_rom),
	CASE(caption_scale_follows_the_height),
	CASE(caption_draws_the_glyph_on_a_darkened_box),
	CASE(caption_wraps_a_long_line_at_a_space),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
