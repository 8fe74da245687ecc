/* guest_common.h - PASS/FAIL/SKIP reporting for programs that run inside the QEMU test guest.
 * The host (run-guest.sh) reads these lines from the serial console. */
#ifndef POLARCAM_TESTS_GUEST_COMMON_H
#define POLARCAM_TESTS_GUEST_COMMON_H

#include <stdarg.h>
#include <stdio.h>
#include <time.h>

static int gt_npass, gt_nfail, gt_nskip;
static double gt_t_last;           /* time of the previous result line */
static const char *gt_prefix = ""; /* prepended to check names ("mplane-") */

static inline double gt_now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Each result line ends with the seconds since the previous one: what that check cost. */
#if defined(__GNUC__)
__attribute__((format(printf, 3, 0)))
#endif
static inline void
gt_vline(const char *tag, const char *name, const char *fmt, va_list ap)
{
	double now = gt_now();
	if (gt_t_last == 0.0)
		gt_t_last = now;
	printf("%s %s%s: ", tag, gt_prefix, name);
	vprintf(fmt, ap);
	printf(" [%.1f s]\n", now - gt_t_last);
	gt_t_last = now;
	fflush(stdout);
}

#if defined(__GNUC__)
#define GT_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define GT_PRINTF(a, b)
#endif

static inline void GT_PRINTF(2, 3) gt_pass(const char *name, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	gt_vline("PASS", name, fmt, ap);
	va_end(ap);
	gt_npass++;
}

static inline void GT_PRINTF(2, 3) gt_fail(const char *name, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	gt_vline("FAIL", name, fmt, ap);
	va_end(ap);
	gt_nfail++;
}

static inline void GT_PRINTF(2, 3) gt_skip(const char *name, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	gt_vline("SKIP", name, fmt, ap);
	va_end(ap);
	gt_nskip++;
}

static inline void GT_PRINTF(1, 2) gt_info(const char *fmt, ...)
{
	va_list ap;
	if (gt_t_last == 0.0)
		gt_t_last = gt_now();
	va_start(ap, fmt);
	printf("  ");
	vprintf(fmt, ap);
	printf("\n");
	fflush(stdout);
	va_end(ap);
}

/* Summary line and exit status: 1 if anything failed, 77 if nothing ran but skips, else 0. */
static inline int gt_finish(void)
{
	printf("GUEST-SUMMARY pass=%d fail=%d skip=%d\n", gt_npass, gt_nfail, gt_nskip);
	fflush(stdout);
	if (gt_nfail)
		return 1;
	if (!gt_npass && gt_nskip)
		return 77;
	return 0;
}

#endif
