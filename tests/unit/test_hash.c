#include "core/hash.h"
#include "test.h"

/* Golden values computed independently (Python integer arithmetic) from the
 * documented definition; any change of the hash changes every baked volume. */
static void hash_u32_matches_golden_values(void)
{
	CHECK(cs_hash_u32(0u) == 0x0u);
	CHECK(cs_hash_u32(1u) == 0x688990c0u);
	CHECK(cs_hash_u32(2u) == 0xd1132181u);
	CHECK(cs_hash_u32(0xdeadbeefu) == 0xe628c683u);
	CHECK(cs_hash_u32(0xffffffffu) == 0x6768824au);
}

static void hash3i_matches_golden_values_including_negative(void)
{
	CHECK(cs_hash3i(0, 0, 0, 0) == 0x41f39e5eu);
	CHECK(cs_hash3i(1, 2, 3, 4) == 0x5028aab9u);
	CHECK(cs_hash3i(-1, -2, -3, 7) == 0x3689ab78u);
	CHECK(cs_hash3i(100000, -5, 2147483647, 123) == 0x94c3abaau);
}

/* Flipping any one input bit flips close to half of the output bits. */
static void hash_u32_avalanches(void)
{
	double total = 0.0;
	int n = 0;
	for (uint32_t i = 0; i < 4096; i++) {
		uint32_t x = cs_hash_u32(i * 2654435761u);
		for (int b = 0; b < 32; b++) {
			uint32_t d = cs_hash_u32(x) ^ cs_hash_u32(x ^ (1u << b));
			total += __builtin_popcount(d);
			n++;
		}
	}
	CHECK_NEAR(total / n, 16.0, 0.1);
}

static void hash_unit_is_uniform_in_unit_interval(void)
{
	int bins[16] = {0};
	enum { N = 160000 };
	for (int i = 0; i < N; i++) {
		double u = cs_hash_unit(cs_hash3i(i, -i, i / 7, 99));
		CHECK(u >= 0.0 && u < 1.0);
		bins[(int)(u * 16)]++;
	}
	double chi2 = 0.0, e = N / 16.0;
	for (int b = 0; b < 16; b++)
		chi2 += (bins[b] - e) * (bins[b] - e) / e;
	CHECK(chi2 < 37.7); /* 15 degrees of freedom, p = 0.001 */
}

static void hash3i_seed_changes_every_output(void)
{
	int same = 0;
	for (int i = 0; i < 1000; i++)
		same += cs_hash3i(i, 0, 0, 1) == cs_hash3i(i, 0, 0, 2);
	CHECK(same == 0);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(hash_u32_matches_golden_values),
	CASE(hash3i_matches_golden_values_including_negative),
	CASE(hash_u32_avalanches),
	CASE(hash_unit_is_uniform_in_unit_interval),
	CASE(hash3i_seed_changes_every_output),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
