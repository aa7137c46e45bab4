#include "core/half.h"

#include <math.h>
#include <string.h>

static uint32_t bits_of(float f)
{
	uint32_t u;
	memcpy(&u, &f, sizeof u);
	return u;
}

static float float_of(uint32_t u)
{
	float f;
	memcpy(&f, &u, sizeof f);
	return f;
}

uint16_t cs_float_to_half(float f)
{
	uint32_t u = bits_of(f);
	uint16_t sign = (uint16_t)((u >> 16) & 0x8000u);
	uint32_t absu = u & 0x7fffffffu;

	if (absu >= 0x7f800000u) /* inf or NaN: keep a quiet NaN bit */
		return (uint16_t)(sign | 0x7c00u | (absu > 0x7f800000u ? 0x200u : 0u));
	if (absu >= 0x477ff000u) /* rounds to >= 65520: overflow */
		return (uint16_t)(sign | 0x7c00u);
	if (absu < 0x38800000u) { /* below 2^-14: subnormal half or zero */
		if (absu < 0x33000000u) /* below half the smallest subnormal */
			return sign;
		uint32_t mant = (absu & 0x007fffffu) | 0x00800000u;
		int shift = 126 - (int)(absu >> 23); /* 14..24 */
		uint32_t q = mant >> shift;
		uint32_t rem = mant & ((1u << shift) - 1u);
		uint32_t halfway = 1u << (shift - 1);
		if (rem > halfway || (rem == halfway && (q & 1u)))
			q++;
		return (uint16_t)(sign | q);
	}
	/* normal: rebias the exponent, round the 13 dropped bits to even */
	uint32_t h = ((absu - 0x38000000u) >> 13);
	uint32_t rem = absu & 0x1fffu;
	if (rem > 0x1000u || (rem == 0x1000u && (h & 1u)))
		h++;
	return (uint16_t)(sign | h);
}

uint16_t cs_float_to_half_sat(float f)
{
	uint16_t h = cs_float_to_half(f);
	if ((h & 0x7fffu) == 0x7c00u && isfinite(f))
		return (uint16_t)((h & 0x8000u) | 0x7bffu);
	return h;
}

float cs_half_to_float(uint16_t h)
{
	uint32_t sign = (uint32_t)(h & 0x8000u) << 16;
	uint32_t exp = (h >> 10) & 0x1fu;
	uint32_t mant = h & 0x3ffu;

	if (exp == 0x1f)
		return float_of(sign | 0x7f800000u | (mant << 13));
	if (exp == 0) {
		if (mant == 0)
			return float_of(sign);
		/* subnormal: mant * 2^-24 is exact in float */
		float v = (float)mant * (1.0f / 16777216.0f);
		return sign ? -v : v;
	}
	return float_of(sign | ((exp + 112u) << 23) | (mant << 13));
}
