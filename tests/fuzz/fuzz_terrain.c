/* fuzz_terrain - the heightfield reader (terrain.h): the EXR of heights and
 * its JSON sidecar.  The input is the sidecar's length (2 bytes, little
 * endian), the sidecar, then the EXR (tests/fuzz/seeds.sh makes seeds of
 * this shape from terrainprep's output).  An accepted heightfield is
 * sampled, corners and outside included. */
#include "terrain/terrain.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 2)
		return 0;
	size_t jlen = data[0] | (size_t)data[1] << 8;
	if (jlen > size - 2)
		jlen = size - 2;
	const char *json = (const char *)data + 2;
	const uint8_t *exr = data + 2 + jlen;
	struct cs_terrain t;
	if (cs_terrain_read_mem(exr, size - 2 - jlen, "fuzz.exr", json, jlen,
				"fuzz.json", &t) == 0) {
		const double at[][2] = {{0, 0}, {-5, 3.5}, {1e9, -1e9},
					{t.width - 1.0, t.height - 1.0}, {0.5, 0.25}};
		for (int i = 0; i < 5; i++) {
			double h = cs_terrain_height(&t, at[i][0], at[i][1]);
			if (!(h >= t.min_m - 1e-3 * (1 + fabs(t.min_m)) &&
			      h <= t.max_m + 1e-3 * (1 + fabs(t.max_m))))
				abort(); /* bilinear stays inside the range */
		}
	}
	cs_terrain_free(&t);
	return 0;
}
