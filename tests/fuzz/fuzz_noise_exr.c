/* fuzz_noise_exr - the noise-volume reader (man 5 cloudscape-noise):
 * OpenEXR header, cloudscape attributes, pixels; a volume it accepts is
 * sampled at a few points, far ones included. */
#include "noise/volume.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct cs_volume v;
	if (cs_volume_read_exr_mem(data, size, "fuzz.exr", &v) == 0) {
		const double at[] = {0.0, 0.37, -2.5, 1e9, -1e300, 1e308};
		for (int i = 0; i < 6; i++) {
			float out[4];
			cs_volume_sample4(&v, at[i], at[(i + 1) % 6], at[(i + 2) % 6], out);
			for (int c = 0; c < 4; c++)
				if (!isfinite(out[c])) /* the reader refuses non-finite voxels */
					abort();
		}
	}
	cs_volume_free(&v);
	return 0;
}
