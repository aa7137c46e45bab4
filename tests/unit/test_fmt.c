/* Shortest round-trip numbers: the texts of well-known doubles (the
 * digits of their exact binary values, as Python's repr and Ryu print
 * them) and a read-back check over many values. */
#include "test.h"

#include "core/fmt.h"

#include <stdint.h>
#include <stdlib.h>

static void fmt_double_prints_known_doubles_as_their_shortest_text(void)
{
	static const struct {
		double v;
		const char *text;
	} known[] = {
		{0.1, "0.1"},
		{0.1 + 0.2, "0.30000000000000004"}, /* repr(0.1 + 0.2) */
		{1.0 / 3.0, "0.3333333333333333"},  /* repr(1/3): 16 digits */
		{30000, "30000"},
		{-0.0, "-0"},
		{46.94798, "46.94798"},
		{1.7976931348623157e308, "1.7976931348623157e+308"},
		{1e21, "1e+21"},
		{2.0 / 3.0, "0.6666666666666666"},
	};
	char buf[CS_FMT_DOUBLE_SIZE];
	for (size_t i = 0; i < sizeof known / sizeof known[0]; i++) {
		cs_fmt_double(buf, sizeof buf, known[i].v);
		if (strcmp(buf, known[i].text) != 0)
			printf("  %s, expected %s\n", buf, known[i].text);
		CHECK(strcmp(buf, known[i].text) == 0);
	}
	CHECK(strcmp(cs_num(NAN).s, "nan") == 0 || strcmp(cs_num(NAN).s, "-nan") == 0);
	CHECK(strcmp(cs_num(-INFINITY).s, "-inf") == 0);
}

static void fmt_double_reads_back_exactly(void)
{
	uint64_t x = 0x9E3779B97F4A7C15ull;
	char buf[CS_FMT_DOUBLE_SIZE];
	for (int i = 0; i < 100000; i++) {
		x ^= x << 13, x ^= x >> 7, x ^= x << 17; /* xorshift64 */
		double v;
		uint64_t bits = x & ~(0x7FFull << 52); /* any mantissa and sign */
		bits |= (uint64_t)(1 + x % 2045) << 52; /* a finite exponent */
		memcpy(&v, &bits, sizeof v);
		cs_fmt_double(buf, sizeof buf, v);
		if (strtod(buf, NULL) != v) {
			CHECK(strtod(buf, NULL) == v);
			break;
		}
	}
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(fmt_double_prints_known_doubles_as_their_shortest_text),
	CASE(fmt_double_reads_back_exactly),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
