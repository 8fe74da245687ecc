/* devices/frame_queue.h - internal: the bounded queue between a capture's acquisition (the
 * calling thread: dequeue, copy, requeue at once) and its writer thread.
 *
 * Frames are copied into slots allocated when needed and kept for reuse, so that the source's
 * buffers go back to the camera as soon as a frame is in; a camera whose buffer pool runs dry
 * loses packets (the failure of issue 13: a 2448x2048 PNG written between dequeue and requeue).
 *
 * Sizing (fq_plan): with the writer's measured time per frame w (mean, max over the frames it
 * wrote) and the frame period p (measured between arrivals), R frames still to come and P
 * frames pending, the backlog peaks at the end of the acquisition at P + R (1 - p/w) when
 * w > p; with a margin for the writer's slowest frame, ceil(w_max / p) + 1:
 *
 *     needed = P + ceil(R max(0, 1 - p/w)) + ceil(w_max / p) + 1,  capacity = min(needed, limit)
 *
 * where limit is what the memory budget holds. Before the first frame is written w is unknown
 * and the capacity is the limit. A push beyond the capacity is refused (the frame is lost and
 * counted): as the capacity always covers the pending frames plus the margin, that happens only
 * at the memory limit. */
#ifndef POLARCAM_DEVICES_FRAME_QUEUE_H
#define POLARCAM_DEVICES_FRAME_QUEUE_H

#include <pthread.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "polarcam/frame.h"

typedef struct fq_item {
	pc_frame frame;  /* view.data points into mem */
	double black_dn; /* the black level known when the frame was pushed (0: none) */
	uint8_t *mem;
	struct fq_item *next;
} fq_item;

typedef struct fq_stats {
	size_t frame_bytes;
	size_t limit;      /* slots the memory budget holds */
	size_t capacity;   /* the current bound */
	size_t needed_max; /* the largest need computed (may exceed limit: frames were at risk) */
	size_t peak;       /* most frames pending at once */
	uint64_t pushed, lost, written;
	double write_mean_s, write_max_s; /* over the frames written */
	double period_s;                  /* measured between arrivals; 0 when unknown */
} fq_stats;

typedef struct frame_queue {
	pthread_mutex_t lock;
	pthread_cond_t cond; /* a push, a slot back, the close */
	fq_item *head, *tail, *free_list;
	size_t queued, in_hand, n_free;
	bool closed;
	double write_sum;
	double t_first, t_last; /* arrivals */
	uint64_t arrivals;
	fq_stats st;
} frame_queue;

/* limit_bytes: memory budget for slots (at least 2 slots are allowed). */
int fq_init(frame_queue *q, size_t frame_bytes, uint64_t limit_bytes);
void fq_destroy(frame_queue *q);

/* An arrival at time t (seconds, monotonic), counted for the period, whether pushed or not. */
void fq_arrival(frame_queue *q, double t);
/* Copies f (and the black level to process it with) into a slot: 0, or 1 when the queue is full
 * (the frame is lost and counted), or a negative error (out of memory: also counted as lost). */
int fq_push(frame_queue *q, const pc_frame *f, double black_dn);
/* Recomputes the capacity for `remaining` frames still to come; fallback_period_s is used
 * while fewer than two arrivals were seen (0: unknown). */
void fq_plan(frame_queue *q, uint64_t remaining, double fallback_period_s);
/* No more pushes. */
void fq_close(frame_queue *q);

/* Writer side: the next frame (waits), NULL once closed and empty. */
fq_item *fq_pop(frame_queue *q);
/* The frame popped last is done; written: it reached the disk in write_s seconds. */
void fq_done(frame_queue *q, fq_item *it, bool written, double write_s);

/* Frames pushed and not yet done. */
size_t fq_pending(frame_queue *q);
/* Waits up to timeout_ms for a frame to be done or the queue to change. */
void fq_wait(frame_queue *q, int timeout_ms);
void fq_get_stats(frame_queue *q, fq_stats *st);

#endif
