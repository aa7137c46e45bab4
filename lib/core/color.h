/* color.h - linear sRGB (Rec. 709 primaries, D65 white): every radiance and
 * irradiance in cloudscape is a triple in it. */
#ifndef CS_COLOR_H
#define CS_COLOR_H

#include "core/hd.h"

/* Luminance of a linear Rec. 709 colour (ITU-R BT.709 Y weights). */
CS_HD static inline double cs_luminance(double r, double g, double b)
{
	return 0.2126 * r + 0.7152 * g + 0.0722 * b;
}

#endif
