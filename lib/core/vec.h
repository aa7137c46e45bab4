/* vec.h - three-component double vectors, by value. */
#ifndef CS_VEC_H
#define CS_VEC_H

#include "core/hd.h"

#include <math.h>

#define CS_PI 3.14159265358979323846

typedef struct { double x, y, z; } cs_v3;

CS_HD static inline cs_v3 v3(double x, double y, double z) { return (cs_v3){x, y, z}; }
CS_HD static inline cs_v3 v3_add(cs_v3 a, cs_v3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
CS_HD static inline cs_v3 v3_sub(cs_v3 a, cs_v3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
CS_HD static inline cs_v3 v3_scale(cs_v3 a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
CS_HD static inline cs_v3 v3_mad(cs_v3 a, cs_v3 d, double t) { return v3(a.x + d.x * t, a.y + d.y * t, a.z + d.z * t); }
CS_HD static inline double v3_dot(cs_v3 a, cs_v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
CS_HD static inline double v3_len(cs_v3 a) { return sqrt(v3_dot(a, a)); }
CS_HD static inline cs_v3 v3_cross(cs_v3 a, cs_v3 b)
{
	return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
/* a / |a|; the zero vector stays zero. */
CS_HD static inline cs_v3 v3_norm(cs_v3 a)
{
	double l = v3_len(a);
	return l > 0.0 ? v3_scale(a, 1.0 / l) : a;
}

#endif
