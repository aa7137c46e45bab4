/* hash.h - integer hashing: the only source of randomness in cloudscape.
 *
 * Everything random (noise feature points, gradients, per-pixel jitter) is a
 * pure function of integer coordinates and a seed, computed in 32-bit
 * unsigned arithmetic, so the same seed gives the same bits on every machine
 * and compiler.  No floating-point hashing (no fract(sin(x) * 43758.5453)). */
#ifndef CS_HASH_H
#define CS_HASH_H

#include "core/hd.h"

#include <stdint.h>

/* A full-avalanche 32-bit integer permutation (Wellons' "lowbias32":
 * xorshift-multiply, constants 0x7feb352d and 0x846ca68b). */
CS_HD static inline uint32_t cs_hash_u32(uint32_t x)
{
	x ^= x >> 16;
	x *= 0x7feb352du;
	x ^= x >> 15;
	x *= 0x846ca68bu;
	x ^= x >> 16;
	return x;
}

/* Hash of three signed lattice coordinates and a seed.  Negative coordinates
 * are taken modulo 2^32 (two's complement), which is well defined. */
CS_HD static inline uint32_t cs_hash3i(int32_t x, int32_t y, int32_t z, uint32_t seed)
{
	uint32_t h = cs_hash_u32(seed ^ 0x9e3779b9u);
	h = cs_hash_u32(h ^ (uint32_t)x);
	h = cs_hash_u32(h ^ (uint32_t)y);
	h = cs_hash_u32(h ^ (uint32_t)z);
	return h;
}

/* A hash mapped to a double in [0, 1) with 24 bits of resolution. */
CS_HD static inline double cs_hash_unit(uint32_t h)
{
	return (double)(h >> 8) * (1.0 / 16777216.0);
}

#endif
