/* devices/backend_util.h - internal helpers the backends share: a FIFO of queued buffers and
 * a pacer that schedules frame k at start + k / rate (never by accumulated sleeps). */
#ifndef POLARCAM_DEVICES_BACKEND_UTIL_H
#define POLARCAM_DEVICES_BACKEND_UTIL_H

#include <stdbool.h>
#include <stdint.h>

#include "polarcam/source.h"

/* FIFO of buffers queued to a backend (at most 64, the pool's limit). */
typedef struct pc_bfifo {
	pc_buffer *b[64];
	unsigned head, count;
} pc_bfifo;

void pc_bfifo_clear(pc_bfifo *q);
int pc_bfifo_push(pc_bfifo *q, pc_buffer *b);
pc_buffer *pc_bfifo_pop(pc_bfifo *q);

/* Monotonic clock in ns (CLOCK_MONOTONIC). */
uint64_t pc_clock_ns(void);
/* Sleeps until the monotonic time t_ns (absolute, restarted on EINTR). */
void pc_sleep_until_ns(uint64_t t_ns);

/* Frame k is due at t0_ns + (k - k0) * period_ns; changing the rate rebases at the current
 * frame so earlier frames keep their times. period 0 = unpaced (due at once). */
typedef struct pc_pacer {
	uint64_t t0_ns, k0;
	double period_ns;
} pc_pacer;

void pc_pacer_start(pc_pacer *p, double rate_hz, uint64_t now_ns, uint64_t k);
void pc_pacer_set_rate(pc_pacer *p, double rate_hz, uint64_t k);
uint64_t pc_pacer_due_ns(const pc_pacer *p, uint64_t k);

#endif

/* Copies the (dst->width x dst->height) region at (x0, y0) of src (an unpacked integer view)
 * into dst, converting to dst's format (any integer format with at least src's bits) at dst's
 * stride. tmp must hold dst->width * dst->height uint16 when the formats differ (else NULL ok). */
int pc_copy_roi(const pc_view *src, uint32_t x0, uint32_t y0, pc_view *dst, uint16_t *tmp);

/* Negotiation helper for sources that can crop and convert anything (sim, file): completes
 * *f against a sensor of sw x sh in native format `native`, with full-sensor mosaic m, and
 * returns the verdict. ROI offsets and sizes are free (odd ones too); pixel formats: any integer
 * format with at least native's bits (packed widths must fit the packing group); strides at
 * least the row bytes. */
int pc_negotiate_flexible(pc_source_format *f, pc_pixfmt native, uint32_t sw, uint32_t sh,
                          bool polarized, const pc_mosaic *m, pc_format_verdict *verdict);
