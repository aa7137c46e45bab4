/* test.h - a minimal test harness.  Each test binary runs its cases and
 * prints one line per case: "ok NAME", "FAIL NAME: why" or "skip NAME: why".
 * tests/run counts the lines.  The binary exits 1 if any case failed. */
#ifndef CS_TEST_H
#define CS_TEST_H

#include <math.h>
#include <stdio.h>
#include <string.h>

static int t_failed_cases, t_case_failed, t_case_skipped;
static char t_skip_why[256];

#define CHECK(cond)                                                           \
	do {                                                                  \
		if (!(cond)) {                                                \
			printf("  %s:%d: CHECK(%s) failed\n", __FILE__,        \
			       __LINE__, #cond);                               \
			t_case_failed = 1;                                    \
		}                                                             \
	} while (0)

#define CHECK_NEAR(a, b, tol)                                                 \
	do {                                                                  \
		double a_ = (a), b_ = (b);                                    \
		if (!(fabs(a_ - b_) <= (tol))) {                              \
			printf("  %s:%d: %s = %.12g, expected %.12g +- %g\n",  \
			       __FILE__, __LINE__, #a, a_, b_, (double)(tol)); \
			t_case_failed = 1;                                    \
		}                                                             \
	} while (0)

#define CHECK_STR_CONTAINS(s, sub)                                            \
	do {                                                                  \
		const char *s_ = (s);                                         \
		if (strstr(s_, (sub)) == NULL) {                              \
			printf("  %s:%d: \"%s\" does not contain \"%s\"\n",     \
			       __FILE__, __LINE__, s_, (sub));                 \
			t_case_failed = 1;                                    \
		}                                                             \
	} while (0)

#define SKIP(...)                                                             \
	do {                                                                  \
		snprintf(t_skip_why, sizeof t_skip_why, __VA_ARGS__);         \
		t_case_skipped = 1;                                           \
		return;                                                       \
	} while (0)

#define RUN(fn)                                                               \
	do {                                                                  \
		t_case_failed = t_case_skipped = 0;                           \
		fflush(stdout);                                               \
		fn();                                                         \
		if (t_case_skipped)                                           \
			printf("skip %s: %s\n", #fn, t_skip_why);             \
		else if (t_case_failed) {                                     \
			printf("FAIL %s\n", #fn);                             \
			t_failed_cases++;                                     \
		} else                                                        \
			printf("ok %s\n", #fn);                               \
		fflush(stdout);                                               \
	} while (0)

#define TEST_EXIT() return t_failed_cases ? 1 : 0

/* A deterministic uniform double in [lo, hi) for test inputs. */
static inline double t_uniform(unsigned *state, double lo, double hi)
{
	*state = *state * 1664525u + 1013904223u;
	unsigned x = *state;
	x ^= x >> 16;
	x *= 0x7feb352du;
	x ^= x >> 15;
	return lo + (hi - lo) * ((x >> 8) / 16777216.0);
}

#endif
