/* test.h - a minimal test harness.  Each test binary runs its cases and
 * prints one line per case: "ok NAME", "FAIL NAME: why" or "skip NAME: why".
 * The binary exits 1 if any case failed.
 *
 * The plan: the cases are listed in ONE place, a table before main(), and
 * their number follows from it:
 *
 *     static const struct t_case t_cases[] = {
 *             CASE(first_case),
 *             CASE(second_case),
 *     };
 *     int main(void)
 *     {
 *             (setup)
 *             T_RUN_TABLE(t_cases);   prints "plan N", then runs each case
 *             (teardown)
 *             TEST_EXIT();
 *     }
 *
 * tests/run fails a binary that prints no "plan N" line, prints a number of
 * case lines other than N (it ended early, or ran something the table does
 * not list), or exits nonzero without a FAIL line.
 *
 * A case that failed a CHECK and then calls SKIP is counted as failed.  SKIP
 * is only for cases that cannot run here because the shared data folder is
 * absent, and, under ThreadSanitizer (t_under_tsan: make check SAN=thread),
 * for a case that compares numbers for minutes there and whose threads
 * other cases of that run exercise (the plain and ASan runs keep it).
 * t_data_path() finds the folder ($DATA, which tests/run sets to an absolute
 * path, else ../shared/data from the working directory), so running a binary
 * from another directory works.  t_top_path() finds files of the source
 * tree ($TOP, which tests/run sets, else the working directory). */
#ifndef CS_TEST_H
#define CS_TEST_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
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

#define TEST_EXIT() return t_failed_cases ? 1 : 0

/* clang's __has_feature, 0 where the compiler has none (GCC before 14) */
#ifdef __has_feature
#define T_HAS_FEATURE(f) __has_feature(f)
#else
#define T_HAS_FEATURE(f) 0
#endif

/* Whether this binary was built with ThreadSanitizer (GCC defines
 * __SANITIZE_THREAD__, clang has the feature). */
static inline int t_under_tsan(void)
{
#if defined(__SANITIZE_THREAD__) || T_HAS_FEATURE(thread_sanitizer)
	return 1;
#else
	return 0;
#endif
}

/* Whether this binary was built with AddressSanitizer or ThreadSanitizer
 * (make check SAN=1 or SAN=thread). */
static inline int t_under_sanitizer(void)
{
#if defined(__SANITIZE_ADDRESS__) || T_HAS_FEATURE(address_sanitizer)
	return 1;
#else
	return t_under_tsan();
#endif
}

/* One case of a binary's table (see the top of this file). */
struct t_case {
	const char *name;
	void (*fn)(void);
};
#define CASE(fn) { #fn, fn }

static inline void t_run_case(const struct t_case *c)
{
	t_case_failed = t_case_skipped = 0;
	t_skip_why[0] = '\0';
	fflush(stdout);
	c->fn();
	if (t_case_failed) {
		printf("FAIL %s%s%s\n", c->name,
		       t_case_skipped ? ": failed, then skipped: " : "",
		       t_case_skipped ? t_skip_why : "");
		t_failed_cases++;
	} else if (t_case_skipped)
		printf("skip %s: %s\n", c->name, t_skip_why);
	else
		printf("ok %s\n", c->name);
	fflush(stdout);
}

static inline void t_run_table(const struct t_case *cases, size_t n)
{
	printf("plan %zu\n", n);
	for (size_t i = 0; i < n; i++)
		t_run_case(&cases[i]);
}
/* RUN(fn): one case outside a table (the old way).  It prints no plan, and
 * tests/run fails a binary without one: list the case in the table instead. */
#define RUN(fn)                                                               \
	do {                                                                  \
		static const struct t_case c_ = CASE(fn);                     \
		t_run_case(&c_);                                              \
	} while (0)
#define T_RUN_TABLE(cases) t_run_table(cases, sizeof(cases) / sizeof((cases)[0]))

/* PATH inside the shared real-data folder: $DATA when set (tests/run sets
 * it, absolute), else ../shared/data from the working directory. */
static inline const char *t_data_path(char *buf, size_t size, const char *path)
{
	const char *d = getenv("DATA");
	snprintf(buf, size, "%s/%s", d && d[0] ? d : "../shared/data", path);
	return buf;
}
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

/* PATH inside the source tree: $TOP when set (tests/run sets it), else the
 * working directory. */
static inline const char *t_top_path(char *buf, size_t size, const char *path)
{
	const char *d = getenv("TOP");
	snprintf(buf, size, "%s/%s", d && d[0] ? d : ".", path);
	return buf;
}

#endif
