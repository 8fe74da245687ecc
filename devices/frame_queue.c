/* The bounded queue between a capture's acquisition and its writer (frame_queue.h). */
#include "frame_queue.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "polarcam/error.h"

int fq_init(frame_queue *q, size_t frame_bytes, uint64_t limit_bytes)
{
	memset(q, 0, sizeof *q);
	if (frame_bytes == 0)
		return pc_error(PC_EINVAL, "frame queue: frames of 0 bytes");
	uint64_t slots = limit_bytes / frame_bytes;
	q->st.frame_bytes = frame_bytes;
	q->st.limit = slots < 2 ? 2 : slots > SIZE_MAX / 2 ? SIZE_MAX / 2 : (size_t)slots;
	q->st.capacity = q->st.limit;
	if (pthread_mutex_init(&q->lock, NULL))
		return pc_error(PC_ENOMEM, "frame queue: mutex");
	pthread_condattr_t ca;
	pthread_condattr_init(&ca);
	pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
	int e = pthread_cond_init(&q->cond, &ca);
	pthread_condattr_destroy(&ca);
	if (e) {
		pthread_mutex_destroy(&q->lock);
		return pc_error(PC_ENOMEM, "frame queue: condition variable");
	}
	return 0;
}

static void free_list(fq_item *it)
{
	while (it) {
		fq_item *next = it->next;
		free(it->mem);
		free(it);
		it = next;
	}
}

void fq_destroy(frame_queue *q)
{
	free_list(q->head);
	free_list(q->free_list);
	q->head = q->tail = q->free_list = NULL;
	pthread_cond_destroy(&q->cond);
	pthread_mutex_destroy(&q->lock);
}

void fq_arrival(frame_queue *q, double t)
{
	pthread_mutex_lock(&q->lock);
	if (q->arrivals == 0)
		q->t_first = t;
	q->t_last = t;
	q->arrivals++;
	if (q->arrivals >= 2)
		q->st.period_s = (q->t_last - q->t_first) / (double)(q->arrivals - 1);
	pthread_mutex_unlock(&q->lock);
}

/* Bytes of a view's pixels from the first byte of row 0 to the last byte of the last row. */
static size_t view_bytes(const pc_view *v)
{
	size_t row = 0;
	(void)pc_format_row_bytes(v->format, v->width, &row);
	return v->height ? v->stride * (v->height - 1) + row : 0;
}

int fq_push(frame_queue *q, const pc_frame *f, double black_dn)
{
	size_t bytes = view_bytes(&f->view);
	if (bytes > q->st.frame_bytes) {
		pthread_mutex_lock(&q->lock);
		q->st.lost++;
		pthread_mutex_unlock(&q->lock);
		return pc_error(PC_EINVAL, "frame queue: a frame of %zu bytes in slots of %zu",
		                bytes, q->st.frame_bytes);
	}
	pthread_mutex_lock(&q->lock);
	size_t pending = q->queued + q->in_hand;
	if (pending >= q->st.capacity) {
		q->st.lost++;
		pthread_mutex_unlock(&q->lock);
		return 1;
	}
	fq_item *it = q->free_list;
	if (it) {
		q->free_list = it->next;
		q->n_free--;
	}
	pthread_mutex_unlock(&q->lock);
	if (!it) { /* a new slot, allocated outside the lock */
		it = calloc(1, sizeof *it);
		if (it && !(it->mem = malloc(q->st.frame_bytes))) {
			free(it);
			it = NULL;
		}
		if (!it) {
			pthread_mutex_lock(&q->lock);
			q->st.lost++;
			pthread_mutex_unlock(&q->lock);
			return pc_error(PC_ENOMEM, "frame queue: a slot of %zu bytes",
			                q->st.frame_bytes);
		}
	}
	it->frame = *f;
	it->black_dn = black_dn;
	it->frame.view.data = it->mem;
	memcpy(it->mem, f->view.data, bytes);
	it->next = NULL;
	pthread_mutex_lock(&q->lock);
	if (q->tail)
		q->tail->next = it;
	else
		q->head = it;
	q->tail = it;
	q->queued++;
	q->st.pushed++;
	pending = q->queued + q->in_hand;
	if (pending > q->st.peak)
		q->st.peak = pending;
	pthread_cond_broadcast(&q->cond);
	pthread_mutex_unlock(&q->lock);
	return 0;
}

void fq_plan(frame_queue *q, uint64_t remaining, double fallback_period_s)
{
	pthread_mutex_lock(&q->lock);
	const double p = q->arrivals >= 2 ? q->st.period_s : fallback_period_s;
	const size_t pending = q->queued + q->in_hand;
	size_t cap = q->st.limit;
	if (q->st.written > 0 && p > 0) {
		const double w = q->write_sum / (double)q->st.written;
		double behind = w > p ? (double)remaining * (1 - p / w) : 0;
		double margin = ceil(q->st.write_max_s / p) + 1;
		double need = (double)pending + ceil(behind) + margin;
		size_t needed = need >= (double)(SIZE_MAX / 2) ? SIZE_MAX / 2 : (size_t)need;
		if (needed > q->st.needed_max)
			q->st.needed_max = needed;
		cap = needed < q->st.limit ? needed : q->st.limit;
	}
	q->st.capacity = cap;
	/* slots beyond the capacity are not kept for reuse */
	fq_item *drop = NULL;
	while (q->free_list && pending + q->n_free > cap) {
		fq_item *it = q->free_list;
		q->free_list = it->next;
		q->n_free--;
		it->next = drop;
		drop = it;
	}
	pthread_mutex_unlock(&q->lock);
	free_list(drop);
}

void fq_close(frame_queue *q)
{
	pthread_mutex_lock(&q->lock);
	q->closed = true;
	pthread_cond_broadcast(&q->cond);
	pthread_mutex_unlock(&q->lock);
}

fq_item *fq_pop(frame_queue *q)
{
	pthread_mutex_lock(&q->lock);
	while (!q->head && !q->closed)
		pthread_cond_wait(&q->cond, &q->lock);
	fq_item *it = q->head;
	if (it) {
		q->head = it->next;
		if (!q->head)
			q->tail = NULL;
		q->queued--;
		q->in_hand++;
	}
	pthread_mutex_unlock(&q->lock);
	return it;
}

void fq_done(frame_queue *q, fq_item *it, bool written, double write_s)
{
	pthread_mutex_lock(&q->lock);
	q->in_hand--;
	if (written) {
		q->st.written++;
		q->write_sum += write_s;
		if (write_s > q->st.write_max_s)
			q->st.write_max_s = write_s;
	}
	it->next = q->free_list;
	q->free_list = it;
	q->n_free++;
	pthread_cond_broadcast(&q->cond);
	pthread_mutex_unlock(&q->lock);
}

size_t fq_pending(frame_queue *q)
{
	pthread_mutex_lock(&q->lock);
	size_t n = q->queued + q->in_hand;
	pthread_mutex_unlock(&q->lock);
	return n;
}

void fq_wait(frame_queue *q, int timeout_ms)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	ts.tv_sec += timeout_ms / 1000;
	ts.tv_nsec += (long)(timeout_ms % 1000) * 1000000L;
	if (ts.tv_nsec >= 1000000000L) {
		ts.tv_sec++;
		ts.tv_nsec -= 1000000000L;
	}
	pthread_mutex_lock(&q->lock);
	if (q->queued + q->in_hand > 0)
		pthread_cond_timedwait(&q->cond, &q->lock, &ts);
	pthread_mutex_unlock(&q->lock);
}

void fq_get_stats(frame_queue *q, fq_stats *st)
{
	pthread_mutex_lock(&q->lock);
	*st = q->st;
	st->write_mean_s = q->st.written ? q->write_sum / (double)q->st.written : 0;
	pthread_mutex_unlock(&q->lock);
}
