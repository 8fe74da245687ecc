/* polarcam/compliance.h - one compliance test for every frame source (in the spirit of
 * v4l2-compliance): run it against sim:, file:, aravis:, v4l2:, libcamera: alike.
 *
 * What it checks, through the public API only:
 *   - states: calls in the wrong state fail with PC_ESTATE, bad arguments with PC_EINVAL
 *   - format negotiation: the current format is valid as is; an empty request is completed
 *     without being called adjusted; impossible sizes, offsets outside the sensor and too small
 *     strides are never "valid"; an adjusted answer is valid when asked again (idempotent);
 *     set_format refuses adjustable requests and changes nothing; an ROI at an odd offset gets
 *     the mosaic shifted by that offset; every integer pixel format is answered consistently
 *   - controls: values in range read back, out-of-range values are refused (never clamped)
 *   - streaming: every frame has the negotiated format, size and stride (a padded stride when
 *     the source accepts one), data inside its buffer, strictly increasing sequence numbers and
 *     non-decreasing timestamps; statistics count what was delivered
 *   - buffers: with every buffer held, nothing more arrives; stop returns every queued buffer:
 *     after a restart all buffers are filled again; buffers_free only when all are back
 *   - faults (when the source is asked to inject one): it surfaces as the documented error or
 *     statistic, and a lost device leaves the source FAILED, still stoppable and closable.
 *
 * The library never prints: each check is reported through the log callback.
 */
#ifndef POLARCAM_COMPLIANCE_H
#define POLARCAM_COMPLIANCE_H

#include <stdbool.h>

#include "polarcam/export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pc_fault_kind {
	PC_FAULT_NONE = 0,
	PC_FAULT_DROP,       /* sequence gaps: stats.dropped > 0 */
	PC_FAULT_TIMEOUT,    /* some dequeue answers PC_ETIMEDOUT although buffers are queued */
	PC_FAULT_DISCONNECT, /* dequeue answers PC_EDISCONNECTED, the source becomes FAILED */
	PC_FAULT_CORRUPT     /* frames flagged INCOMPLETE/CORRUPT: stats.failed > 0 */
} pc_fault_kind;

/* "none", "drop", ...; parse returns PC_FAULT_NONE for NULL and -1 for unknown names. */
PC_API const char *pc_fault_name(pc_fault_kind k);
PC_API int pc_fault_parse(const char *name);

typedef enum pc_check_result { PC_CHECK_PASS = 0, PC_CHECK_FAIL, PC_CHECK_SKIP } pc_check_result;

typedef void (*pc_compliance_log_fn)(void *ctx, pc_check_result r, const char *check,
                                     const char *detail);

typedef struct pc_compliance_options {
	unsigned frames;  /* frames to stream in the main phase (0 = 8) */
	unsigned buffers; /* pool size (0 = 4) */
	int timeout_ms;   /* per dequeue (0 = 3000) */
	int starve_ms;    /* how long "nothing arrives" is waited for with all buffers held
	                     (0 = 300) */
	pc_fault_kind expect_fault;
	bool finite; /* the source may end (PC_EEND) before `frames` */
	pc_compliance_log_fn log;
	void *log_ctx;
} pc_compliance_options;

typedef struct pc_compliance_result {
	unsigned passed, failed, skipped;
	char first_failure[256];
} pc_compliance_result;

/* Runs every check against the source at uri. Returns 0 when the run completed (look at
 * result->failed), a negative error when the source could not even be opened. */
PC_API int pc_source_compliance(const char *uri, const pc_compliance_options *opt,
                                pc_compliance_result *result);

#ifdef __cplusplus
}
#endif
#endif
