/* tests/check.h - check macros for the test programs: print both values and file:line, count
 * failures, exit 1 at the end if any failed, 77 to skip. */
#ifndef POLARCAM_TESTS_CHECK_H
#define POLARCAM_TESTS_CHECK_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static int pc_test_failures;
static int pc_test_checks;

#define CHECK(cond)                                                                                \
	do {                                                                                       \
		pc_test_checks++;                                                                  \
		if (!(cond)) {                                                                     \
			pc_test_failures++;                                                        \
			fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);   \
		}                                                                                  \
	} while (0)

/* |a - b| <= tol */
#define CHECK_NEAR(a, b, tol)                                                                      \
	do {                                                                                       \
		double pc_a_ = (double)(a), pc_b_ = (double)(b), pc_t_ = (double)(tol);            \
		pc_test_checks++;                                                                  \
		if (!(fabs(pc_a_ - pc_b_) <= pc_t_)) {                                             \
			pc_test_failures++;                                                        \
			fprintf(stderr,                                                            \
			        "%s:%d: CHECK_NEAR failed: %s = %.17g, %s = %.17g, "               \
			        "|diff| = %.3g > %.3g\n",                                          \
			        __FILE__, __LINE__, #a, pc_a_, #b, pc_b_, fabs(pc_a_ - pc_b_),     \
			        pc_t_);                                                            \
		}                                                                                  \
	} while (0)

/* |a - b| <= rel * |b| */
#define CHECK_REL(a, b, rel)                                                                       \
	do {                                                                                       \
		double pc_a_ = (double)(a), pc_b_ = (double)(b), pc_r_ = (double)(rel);            \
		pc_test_checks++;                                                                  \
		if (!(fabs(pc_a_ - pc_b_) <= pc_r_ * fabs(pc_b_))) {                               \
			pc_test_failures++;                                                        \
			fprintf(stderr,                                                            \
			        "%s:%d: CHECK_REL failed: %s = %.17g, %s = %.17g, "                \
			        "rel diff = %.3g > %.3g\n",                                        \
			        __FILE__, __LINE__, #a, pc_a_, #b, pc_b_,                          \
			        fabs(pc_a_ - pc_b_) / fabs(pc_b_), pc_r_);                         \
		}                                                                                  \
	} while (0)

#define CHECK_EQ_INT(a, b)                                                                         \
	do {                                                                                       \
		long long pc_a_ = (long long)(a), pc_b_ = (long long)(b);                          \
		pc_test_checks++;                                                                  \
		if (pc_a_ != pc_b_) {                                                              \
			pc_test_failures++;                                                        \
			fprintf(stderr, "%s:%d: CHECK_EQ_INT failed: %s = %lld, %s = %lld\n",      \
			        __FILE__, __LINE__, #a, pc_a_, #b, pc_b_);                         \
		}                                                                                  \
	} while (0)

/* Exit 77: the test needs something this machine does not have; say what. */
#define SKIP(...)                                                                                  \
	do {                                                                                       \
		fprintf(stderr, "SKIP: ");                                                         \
		fprintf(stderr, __VA_ARGS__);                                                      \
		fprintf(stderr, "\n");                                                             \
		exit(77);                                                                          \
	} while (0)

/* Makes a new private directory $TMPDIR/NAME.XXXXXX (/tmp when TMPDIR is unset or empty) and
 * writes its path into buf. NULL, with the reason on stderr, when it does not fit or cannot be
 * made. */
static inline char *pc_test_tmpdir(char *buf, size_t size, const char *name)
{
	const char *t = getenv("TMPDIR");
	if (!t || !*t)
		t = "/tmp";
	int n = snprintf(buf, size, "%s/%s.XXXXXX", t, name);
	if (n < 0 || (size_t)n >= size) {
		fprintf(stderr, "temporary directory %s/%s.XXXXXX: longer than %zu bytes\n", t,
		        name, size - 1);
		return NULL;
	}
	if (!mkdtemp(buf)) {
		perror(buf);
		return NULL;
	}
	return buf;
}

static inline int pc_test_finish(const char *name)
{
	if (pc_test_failures) {
		fprintf(stderr, "%s: %d of %d checks FAILED\n", name, pc_test_failures,
		        pc_test_checks);
		return 1;
	}
	printf("%s: all %d checks passed\n", name, pc_test_checks);
	return 0;
}

#endif
