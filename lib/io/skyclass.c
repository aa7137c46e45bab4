#include "io/skyclass.h"

void cs_sky_classify_map(const float *px, size_t stride, size_t n, const unsigned char *use,
			 double rb_threshold, unsigned char *cls, struct cs_sky_class *out)
{
	out->sky_pixels = out->cloud_pixels = 0;
	for (size_t i = 0; i < n; i++) {
		const float *p = px + i * stride;
		if (cls)
			cls[i] = CS_SKY_NONE;
		if ((use && !use[i]) || !(p[2] > 0.0f))
			continue;
		int cloud = p[0] / p[2] >= rb_threshold;
		out->sky_pixels++;
		out->cloud_pixels += cloud;
		if (cls)
			cls[i] = cloud ? CS_SKY_CLOUD : CS_SKY_CLEAR;
	}
	out->cloud_fraction = out->sky_pixels ? (double)out->cloud_pixels / out->sky_pixels : 0.0;
}

void cs_sky_classify(const float *px, size_t stride, size_t n, const unsigned char *use,
		     double rb_threshold, struct cs_sky_class *out)
{
	cs_sky_classify_map(px, stride, n, use, rb_threshold, NULL, out);
}
