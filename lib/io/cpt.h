/* cpt.h - colour palettes in GMT's CPT text format (as makecpt writes
 * them and gmt grdimage -C reads them), height -> colour, for
 * cloudrender --terrain-cpt.  The format (man 1 cloudrender, TERRAIN
 * PALETTE): one slice per line, "z0 r0 g0 b0 z1 r1 g1 b1" or
 * "z0 r0/g0/b0 z1 r1/g1/b1" (0..255, or one grey value), the colour
 * linear in z between; "#" starts a comment (and "# COLOR_MODEL = RGB"
 * is the only model read); "B", "F" and "N" lines give the colour below
 * the first slice, above the last and of NaN.  Slices ascend in z. */
#ifndef CS_CPT_H
#define CS_CPT_H

#include "core/hd.h"

#define CS_CPT_MAX_SLICES 1024

struct cs_cpt {
	int n;
	double z0[CS_CPT_MAX_SLICES], z1[CS_CPT_MAX_SLICES];
	float c0[CS_CPT_MAX_SLICES][3], c1[CS_CPT_MAX_SLICES][3]; /* 0..255 */
	int has_b, has_f, has_n;
	float b[3], f[3], nan[3];
};

/* Parses CPT text; errors (CS_EDATA) name the line: "line 3: ...". */
int cs_cpt_parse(const char *text, struct cs_cpt *p);

/* Reads a CPT file ("-": standard input); messages start with its name. */
int cs_cpt_read(const char *path, struct cs_cpt *p);

/* The colour at z, 0..255 per channel: interpolated within its slice (a
 * z on the boundary of two slices takes the upper one's start); below
 * the first slice B (else the first slice's start colour), above the last
 * F (else its end colour); NaN: N (else black). */
CS_HD void cs_cpt_color(const struct cs_cpt *p, double z, double rgb[3]);

#endif
