/* sphere.h - the spherical Earth of the renderer and the heightfield: a
 * world frame east-north-up at sea level below the scene origin, metres,
 * with the Earth's centre at (0, 0, -R).
 *
 * Both functions avoid the cancellation a float port would suffer from:
 * the altitude is not |p + (0,0,R)| - R (which loses everything below a
 * metre in float at R = 6.4e6 m) but (|p|^2 + 2 R p.z) / (|p + (0,0,R)| + R),
 * the same quantity without the subtraction of two large numbers. */
#ifndef CS_SPHERE_H
#define CS_SPHERE_H

#include "core/hd.h"
#include "core/vec.h"

#if defined(__AVX2__) && !defined(__CUDA_ARCH__)
#include <immintrin.h>
#endif

/* Altitude above the sphere of radius R of world point p. */
CS_HD static inline double cs_altitude(cs_v3 p, double R)
{
	cs_v3 q = v3(p.x, p.y, p.z + R);
	return (v3_dot(p, p) + 2.0 * R * p.z) / (v3_len(q) + R);
}

/* alt[i] = cs_altitude((x[i], y[i], z[i]), R) for n points, the same
 * bits: four at a time where the code is built for AVX2. */
CS_HD static inline void cs_altitude_n(int n, const double *x, const double *y, const double *z,
				       double R, double *alt)
{
	int i = 0;
#if defined(__AVX2__) && !defined(__CUDA_ARCH__)
	__m256d r = _mm256_set1_pd(R), r2 = _mm256_set1_pd(2.0 * R);
	for (; i + 4 <= n; i += 4) {
		__m256d px = _mm256_loadu_pd(x + i), py = _mm256_loadu_pd(y + i);
		__m256d pz = _mm256_loadu_pd(z + i), qz = _mm256_add_pd(pz, r);
		__m256d xy = _mm256_add_pd(_mm256_mul_pd(px, px), _mm256_mul_pd(py, py));
		__m256d num = _mm256_add_pd(_mm256_add_pd(xy, _mm256_mul_pd(pz, pz)), _mm256_mul_pd(r2, pz));
		__m256d len = _mm256_sqrt_pd(_mm256_add_pd(xy, _mm256_mul_pd(qz, qz)));
		_mm256_storeu_pd(alt + i, _mm256_div_pd(num, _mm256_add_pd(len, r)));
	}
#endif
	for (; i < n; i++)
		alt[i] = cs_altitude(v3(x[i], y[i], z[i]), R);
}

/* Ray from o along unit d against the sphere of radius r about the Earth's
 * centre (R below the origin): the entry and exit distances (t0 <= t1), or
 * 0 if the line misses it.  Written to avoid cancellation:
 * c = (|oc| - r)(|oc| + r), and the smaller root from the larger one (q) by
 * Vieta. */
CS_HD static inline int cs_sphere_hit(cs_v3 o, cs_v3 d, double R, double r,
				      double *t0, double *t1)
{
	cs_v3 oc = v3(o.x, o.y, o.z + R);
	double dist = v3_len(oc);
	double b = v3_dot(oc, d);
	double c = (dist - r) * (dist + r);
	double disc = b * b - c;
	if (!(disc >= 0.0))
		return 0;
	double sq = sqrt(disc);
	double q = -b - (b >= 0.0 ? sq : -sq);
	double a0 = q, a1 = q != 0.0 ? c / q : 0.0;
	*t0 = a0 < a1 ? a0 : a1;
	*t1 = a0 < a1 ? a1 : a0;
	return 1;
}

#endif
