/* half.h - IEEE 754 binary16 ("half") conversion, as stored in OpenEXR. */
#ifndef CS_HALF_H
#define CS_HALF_H

#include <stdint.h>

/* Rounds to the nearest half (ties to even); overflow gives +-inf, NaN stays
 * NaN, tiny values become subnormals or signed zero. */
uint16_t cs_float_to_half(float f);

/* cs_float_to_half, but a finite value beyond the largest half, 65504,
 * becomes +-65504 instead of +-inf: what an image's half channels store
 * (the sun's disc is about 1.6 million kcd/m^2).  Inf and NaN stay. */
uint16_t cs_float_to_half_sat(float f);

/* Exact widening of a half to float. */
float cs_half_to_float(uint16_t h);

#endif
