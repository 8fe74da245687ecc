/* polarcam/error.h - the one error convention of polarcam.
 *
 * Every fallible function returns int: 0 on success or a negative PC_E* code from the list
 * below. pc_strerror() names the code; the thread-local detail message says what exactly went
 * wrong, with context (file, line, field). Library code never prints and never exits.
 */
#ifndef POLARCAM_ERROR_H
#define POLARCAM_ERROR_H

#include "polarcam/export.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PC_ERRNO_MAP(X)                                                                            \
	X(PC_EINVAL, -1, "invalid argument")                                                       \
	X(PC_ENOMEM, -2, "out of memory")                                                          \
	X(PC_EIO, -3, "input/output error")                                                        \
	X(PC_EFORMAT, -4, "malformed or unsupported data format")                                  \
	X(PC_ERANGE, -5, "value out of range")                                                     \
	X(PC_ENOTSUP, -6, "operation not supported")                                               \
	X(PC_ESTATE, -7, "operation not allowed in the current state")                             \
	X(PC_ETIMEDOUT, -8, "timed out")                                                           \
	X(PC_EDISCONNECTED, -9, "device disconnected")                                             \
	X(PC_ENOENT, -10, "no such file, device or entry")                                         \
	X(PC_EAGAIN, -11, "resource temporarily unavailable")                                      \
	X(PC_ENUMERIC, -12, "numerically undefined result")                                        \
	X(PC_EBUSY, -13, "resource busy")                                                          \
	X(PC_EOVERFLOW, -14, "size or count overflow")                                             \
	X(PC_EPERM, -15, "permission denied")                                                      \
	X(PC_ECANCELED, -16, "operation canceled")                                                 \
	X(PC_EEND, -17, "end of stream")                                                           \
	X(PC_EEXIST, -18, "output already exists")                                                 \
	X(PC_EUNAVAIL, -19, "not available here (backend not built, or device absent)")

enum pc_errno {
	PC_OK = 0,
#define PC_ERRNO_ENUM(name, value, text) name = (value),
	PC_ERRNO_MAP(PC_ERRNO_ENUM)
#undef PC_ERRNO_ENUM
};

/* Static description of an error code ("unknown error" for codes not in the list). */
PC_API const char *pc_strerror(int code);

/* Symbolic name of an error code ("PC_EINVAL"), for JSON output. */
PC_API const char *pc_errname(int code);

/* Sets the calling thread's detail message (printf format) and returns code, so that callers
 * can write: return pc_error(PC_EINVAL, "sigma = %g: must be > 0", s); */
PC_API int pc_error(int code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Prefixes the current detail message with more context ("scene.json: " + detail). Returns code. */
PC_API int pc_error_prefix(int code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* The calling thread's detail message; "" when none was set. Valid until the next pc_error*. */
PC_API const char *pc_error_detail(void);

PC_API void pc_error_clear(void);

#ifdef __cplusplus
}
#endif
#endif
