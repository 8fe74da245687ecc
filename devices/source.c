/* The frame-source wrappers: state machine, argument checks, buffer pool, statistics, frame
 * validation. Backends only see calls that are legal in the current state. */
#include "polarcam/source.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"

#define PC_SOURCE_MAX_BUFFERS 64u
#define PC_SOURCE_MAX_OPTIONS 32

typedef struct pc_option {
	char *key, *value;
	bool used;
} pc_option;

struct pc_source {
	const pc_source_ops *ops;
	void *priv;
	pc_source_state state;
	char scheme[16];
	char *arg;
	pc_option options[PC_SOURCE_MAX_OPTIONS];
	unsigned n_options;
	pc_source_format fmt; /* current */
	pc_buffer **bufs;
	unsigned n_bufs;
	bool backend_memory;
	pc_source_stats stats;
	bool have_last;
	uint64_t last_sequence, last_timestamp_ns;
};

const char *pc_source_state_name(pc_source_state st)
{
	switch (st) {
	case PC_SOURCE_OPEN:
		return "OPEN";
	case PC_SOURCE_READY:
		return "READY";
	case PC_SOURCE_STREAMING:
		return "STREAMING";
	case PC_SOURCE_FAILED:
		return "FAILED";
	case PC_SOURCE_CLOSED:
		return "CLOSED";
	}
	return "?";
}

const char *pc_format_verdict_name(pc_format_verdict v)
{
	switch (v) {
	case PC_FORMAT_VALID:
		return "valid";
	case PC_FORMAT_ADJUSTED:
		return "adjusted";
	case PC_FORMAT_INVALID:
		return "invalid";
	}
	return "?";
}

const char *pc_control_name(pc_control_id id)
{
	switch (id) {
	case PC_CTRL_EXPOSURE_US:
		return "exposure_us";
	case PC_CTRL_GAIN_DB:
		return "gain_db";
	case PC_CTRL_FRAME_RATE_HZ:
		return "frame_rate_hz";
	case PC_CTRL_COUNT:
		break;
	}
	return "?";
}

/* A state requirement: a bit set of states in which an operation is legal. */
#define ST(x) (1u << (x))

static int need_state(const pc_source *s, unsigned allowed, const char *op)
{
	if (allowed & ST(s->state))
		return 0;
	char want[96] = "";
	for (int st = PC_SOURCE_OPEN; st <= PC_SOURCE_FAILED; st++)
		if (allowed & ST(st)) {
			if (want[0])
				strncat(want, " or ", sizeof want - strlen(want) - 1);
			strncat(want, pc_source_state_name((pc_source_state)st),
			        sizeof want - strlen(want) - 1);
		}
	return pc_error(PC_ESTATE, "%s: the source is %s, the call needs %s", op,
	                pc_source_state_name(s->state), want);
}

/* After any backend call: a lost device makes the source FAILED. */
static int after(pc_source *s, int rc)
{
	if (rc == PC_EDISCONNECTED && s->state != PC_SOURCE_CLOSED)
		s->state = PC_SOURCE_FAILED;
	return rc;
}

static int notsup(const pc_source *s, const char *op)
{
	return pc_error(PC_ENOTSUP, "%s: the %s: source does not support this", op, s->scheme);
}

/* ---- options "k=v&k2=v2" ---- */

static int parse_options(pc_source *s, const char *q)
{
	while (*q) {
		const char *amp = strchr(q, '&');
		size_t len = amp ? (size_t)(amp - q) : strlen(q);
		if (len == 0)
			return pc_error(PC_EINVAL, "URI options: empty option (stray '&')");
		if (s->n_options == PC_SOURCE_MAX_OPTIONS)
			return pc_error(PC_EINVAL, "URI options: more than %d options",
			                PC_SOURCE_MAX_OPTIONS);
		const char *eq = memchr(q, '=', len);
		size_t klen = eq ? (size_t)(eq - q) : len;
		if (klen == 0)
			return pc_error(PC_EINVAL, "URI options: '%.*s' has no name", (int)len, q);
		pc_option *o = &s->options[s->n_options];
		o->key = strndup(q, klen);
		o->value = eq ? strndup(eq + 1, len - klen - 1) : strdup("");
		if (!o->key || !o->value) {
			free(o->key);
			free(o->value);
			o->key = o->value = NULL;
			return pc_error(PC_ENOMEM, "URI options");
		}
		for (unsigned i = 0; i < s->n_options; i++)
			if (!strcmp(s->options[i].key, o->key)) {
				int rc = pc_error(PC_EINVAL, "URI option '%s' given twice", o->key);
				free(o->key);
				free(o->value);
				o->key = o->value = NULL;
				return rc;
			}
		s->n_options++;
		q += len;
		if (*q == '&')
			q++;
	}
	return 0;
}

static int check_options_known(pc_source *s)
{
	for (unsigned i = 0; i < s->n_options; i++) {
		bool known = false;
		for (const char *const *k = s->ops->options; k && *k; k++)
			if (!strcmp(*k, s->options[i].key))
				known = true;
		if (!known) {
			char list[256] = "";
			for (const char *const *k = s->ops->options; k && *k; k++) {
				if (list[0])
					strncat(list, ", ", sizeof list - strlen(list) - 1);
				strncat(list, *k, sizeof list - strlen(list) - 1);
			}
			return pc_error(PC_EINVAL, "URI option '%s': the %s: source knows %s",
			                s->options[i].key, s->scheme,
			                list[0] ? list : "no options");
		}
	}
	return 0;
}

const char *pc_source_option(pc_source *s, const char *key)
{
	for (unsigned i = 0; i < s->n_options; i++)
		if (!strcmp(s->options[i].key, key)) {
			s->options[i].used = true;
			return s->options[i].value;
		}
	return NULL;
}

int pc_source_option_double(pc_source *s, const char *key, double min, double max, double *out)
{
	const char *v = pc_source_option(s, key);
	if (!v)
		return 0;
	char *end;
	errno = 0;
	double d = strtod(v, &end);
	if (end == v || *end || errno || !isfinite(d))
		return pc_error(PC_EINVAL, "URI option %s=%s: expected a number", key, v);
	if (d < min || d > max)
		return pc_error(PC_EINVAL, "URI option %s=%s: expected a value in [%g, %g]", key, v,
		                min, max);
	*out = d;
	return 0;
}

int pc_source_option_u64(pc_source *s, const char *key, uint64_t min, uint64_t max, uint64_t *out)
{
	const char *v = pc_source_option(s, key);
	if (!v)
		return 0;
	char *end;
	errno = 0;
	if (*v == '-' || *v == '+' || *v == ' ' || *v == '\0')
		return pc_error(PC_EINVAL, "URI option %s=%s: expected a non-negative integer", key,
		                v);
	unsigned long long u = strtoull(v, &end, 10);
	if (*end || errno)
		return pc_error(PC_EINVAL, "URI option %s=%s: expected a non-negative integer", key,
		                v);
	if (u < min || u > max)
		return pc_error(PC_EINVAL, "URI option %s=%s: expected an integer in [%llu, %llu]",
		                key, v, (unsigned long long)min, (unsigned long long)max);
	*out = u;
	return 0;
}

int pc_source_option_bool(pc_source *s, const char *key, bool *out)
{
	const char *v = pc_source_option(s, key);
	if (!v)
		return 0;
	if (!strcmp(v, "") || !strcmp(v, "1") || !strcmp(v, "true") || !strcmp(v, "yes"))
		*out = true;
	else if (!strcmp(v, "0") || !strcmp(v, "false") || !strcmp(v, "no"))
		*out = false;
	else
		return pc_error(PC_EINVAL, "URI option %s=%s: expected 1/0, true/false or yes/no",
		                key, v);
	return 0;
}

void *pc_source_priv(pc_source *s)
{
	return s->priv;
}

void pc_source_set_priv(pc_source *s, void *priv)
{
	s->priv = priv;
}

const pc_source_format *pc_source_current_format(const pc_source *s)
{
	return &s->fmt;
}

int pc_source_format_complete(pc_source_format *fmt, const pc_mosaic *sensor_mosaic)
{
	size_t row;
	int rc = pc_format_row_bytes(fmt->format, fmt->width, &row);
	if (rc)
		return rc;
	if (fmt->height == 0)
		return pc_error(PC_EINVAL, "format height 0: expected at least one row");
	if (fmt->stride == 0)
		fmt->stride = row;
	if (fmt->stride < row)
		return pc_error(PC_EINVAL, "stride %zu: a %u-pixel %s row needs %zu bytes",
		                fmt->stride, fmt->width, pc_format_info_get(fmt->format)->name,
		                row);
	if (fmt->stride > (SIZE_MAX - row) / fmt->height)
		return pc_error(PC_EOVERFLOW, "frame %ux%u stride %zu: size overflows", fmt->width,
		                fmt->height, fmt->stride);
	size_t need = fmt->stride * (fmt->height - 1) + row;
	if (fmt->frame_bytes < need)
		fmt->frame_bytes = need;
	if (sensor_mosaic)
		fmt->mosaic = pc_mosaic_shift(sensor_mosaic, fmt->offset_x, fmt->offset_y);
	if (!fmt->format_name[0])
		snprintf(fmt->format_name, sizeof fmt->format_name, "%s",
		         pc_format_info_get(fmt->format)->name);
	return 0;
}

/* ---- open / close ---- */

int pc_source_open_ops(pc_source **out, const pc_source_ops *ops, const char *scheme,
                       const char *arg_with_options)
{
	if (!out || !ops || !scheme || !arg_with_options)
		return pc_error(PC_EINVAL, "pc_source_open_ops: missing argument");
	*out = NULL;
	if (!ops->open)
		return pc_error(PC_ENOTSUP, "%s: source has no open operation", scheme);
	pc_source *s = calloc(1, sizeof *s);
	if (!s)
		return pc_error(PC_ENOMEM, "source");
	s->ops = ops;
	snprintf(s->scheme, sizeof s->scheme, "%s", scheme);
	const char *q = strchr(arg_with_options, '?');
	s->arg = q ? strndup(arg_with_options, (size_t)(q - arg_with_options))
	           : strdup(arg_with_options);
	int rc = s->arg ? 0 : pc_error(PC_ENOMEM, "source");
	if (!rc && q)
		rc = parse_options(s, q + 1);
	if (!rc)
		rc = check_options_known(s);
	s->state = PC_SOURCE_OPEN;
	if (!rc)
		rc = ops->open(s, s->arg);
	if (rc) {
		for (unsigned i = 0; i < s->n_options; i++) {
			free(s->options[i].key);
			free(s->options[i].value);
		}
		free(s->arg);
		free(s);
		return rc;
	}
	/* the default format, so get_format works at once */
	if (ops->try_format) {
		pc_source_format f;
		memset(&f, 0, sizeof f);
		pc_format_verdict v;
		rc = ops->try_format(s, &f, &v);
		if (!rc && v == PC_FORMAT_INVALID)
			rc = pc_error_prefix(
			    PC_EIO, "%s: the source has no usable default format: ", scheme);
		if (!rc)
			s->fmt = f;
		if (rc) {
			pc_source_close(s);
			return rc;
		}
	}
	*out = s;
	return 0;
}

int pc_source_open(pc_source **out, const char *uri)
{
	if (!out)
		return pc_error(PC_EINVAL, "pc_source_open: output pointer missing");
	*out = NULL;
	if (!uri || !*uri)
		return pc_error(PC_EINVAL,
		                "source URI missing: expected SCHEME:ID such as sim:default");
	const char *colon = strchr(uri, ':');
	if (!colon || colon == uri || (size_t)(colon - uri) >= 16)
		return pc_error(PC_EINVAL,
		                "source URI '%s': expected SCHEME:ID (sim:, file:, aravis:, "
		                "v4l2:, libcamera:)",
		                uri);
	char scheme[16];
	memcpy(scheme, uri, (size_t)(colon - uri));
	scheme[colon - uri] = '\0';
	const pc_source_backend *b = pc_source_backend_find(scheme);
	if (!b) {
		char list[128] = "";
		for (unsigned i = 0; pc_source_backend_get(i); i++) {
			if (list[0])
				strncat(list, ", ", sizeof list - strlen(list) - 1);
			strncat(list, pc_source_backend_get(i)->scheme,
			        sizeof list - strlen(list) - 1);
		}
		return pc_error(PC_EINVAL, "source URI '%s': unknown scheme '%s' (known: %s)", uri,
		                scheme, list);
	}
	if (!b->ops)
		return pc_error(PC_EUNAVAIL, "source URI '%s': the %s: backend is not built in: %s",
		                uri, scheme, b->missing ? b->missing : "disabled");
	int rc = pc_source_open_ops(out, b->ops, scheme, colon + 1);
	if (rc == PC_ENOENT && b->enumerate) /* a device backend: the device is absent */
		rc = PC_EUNAVAIL;
	if (rc && rc != PC_ENOMEM)
		return pc_error_prefix(rc, "%s: ", uri);
	return rc;
}

static void free_pool(pc_source *s)
{
	if (!s->bufs)
		return;
	if (s->backend_memory && s->ops->buffers_free)
		s->ops->buffers_free(s, s->bufs, s->n_bufs);
	for (unsigned i = 0; i < s->n_bufs; i++) {
		if (!s->backend_memory)
			free(s->bufs[i]->data);
		free(s->bufs[i]);
	}
	free(s->bufs);
	s->bufs = NULL;
	s->n_bufs = 0;
}

void pc_source_close(pc_source *s)
{
	if (!s)
		return;
	if (s->state == PC_SOURCE_STREAMING || s->state == PC_SOURCE_FAILED) {
		if (s->ops->stop)
			(void)s->ops->stop(s);
	}
	free_pool(s);
	s->state = PC_SOURCE_CLOSED;
	if (s->ops->close)
		s->ops->close(s);
	for (unsigned i = 0; i < s->n_options; i++) {
		free(s->options[i].key);
		free(s->options[i].value);
	}
	free(s->arg);
	free(s);
}

pc_source_state pc_source_get_state(const pc_source *s)
{
	return s ? s->state : PC_SOURCE_CLOSED;
}

int pc_source_get_info(pc_source *s, pc_source_info *info)
{
	if (!s || !info)
		return pc_error(PC_EINVAL, "pc_source_get_info: missing argument");
	memset(info, 0, sizeof *info);
	snprintf(info->scheme, sizeof info->scheme, "%s", s->scheme);
	snprintf(info->id, sizeof info->id, "%s", s->arg);
	info->sensor_width = s->fmt.sensor_width;
	info->sensor_height = s->fmt.sensor_height;
	info->polarized = s->fmt.polarized;
	if (!s->ops->get_info)
		return 0;
	return after(s, s->ops->get_info(s, info));
}

/* ---- formats ---- */

int pc_source_get_format(pc_source *s, pc_source_format *fmt)
{
	if (!s || !fmt)
		return pc_error(PC_EINVAL, "pc_source_get_format: missing argument");
	*fmt = s->fmt;
	return 0;
}

static int check_request(const pc_source_format *fmt)
{
	if (fmt->format != PC_FMT_INVALID && !pc_format_info_get(fmt->format))
		return pc_error(PC_EINVAL, "format request: pixel format %d is not a known format",
		                (int)fmt->format);
	if (!memchr(fmt->format_name, '\0', sizeof fmt->format_name))
		return pc_error(PC_EINVAL, "format request: format_name is not terminated");
	return 0;
}

int pc_source_try_format(pc_source *s, pc_source_format *fmt, pc_format_verdict *verdict)
{
	if (!s || !fmt || !verdict)
		return pc_error(PC_EINVAL, "pc_source_try_format: missing argument");
	int rc = need_state(s, ST(PC_SOURCE_OPEN), "try_format");
	if (!rc)
		rc = check_request(fmt);
	if (rc)
		return rc;
	if (!s->ops->try_format)
		return notsup(s, "try_format");
	pc_source_format req = *fmt;
	*verdict = PC_FORMAT_INVALID;
	rc = after(s, s->ops->try_format(s, fmt, verdict));
	if (rc)
		return rc;
	if (*verdict == PC_FORMAT_INVALID)
		return 0;
	/* The backend's answer must be self-consistent; a valid verdict must keep every field
	 * that was asked for. */
	size_t row;
	if (pc_format_row_bytes(fmt->format, fmt->width, &row) || fmt->height == 0 ||
	    fmt->stride < row || fmt->frame_bytes < fmt->stride * (fmt->height - 1) + row)
		return pc_error(
		    PC_EIO,
		    "%s: source answered an inconsistent format (%s %ux%u stride "
		    "%zu, %zu bytes)",
		    s->scheme,
		    pc_format_info_get(fmt->format) ? pc_format_info_get(fmt->format)->name : "?",
		    fmt->width, fmt->height, fmt->stride, fmt->frame_bytes);
	/* an all-zero request asks for the source's default format, whatever its ROI */
	bool empty = !req.format && !req.format_name[0] && !req.width && !req.height &&
	             !req.offset_x && !req.offset_y && !req.stride;
	bool changed =
	    !empty && ((req.format && req.format != fmt->format) ||
	               (req.format_name[0] && strcmp(req.format_name, fmt->format_name)) ||
	               (req.width && req.width != fmt->width) ||
	               (req.height && req.height != fmt->height) || req.offset_x != fmt->offset_x ||
	               req.offset_y != fmt->offset_y || (req.stride && req.stride != fmt->stride));
	if (changed && *verdict == PC_FORMAT_VALID)
		return pc_error(PC_EIO, "%s: source changed the request but called it valid",
		                s->scheme);
	return 0;
}

int pc_source_set_format(pc_source *s, const pc_source_format *fmt)
{
	if (!s || !fmt)
		return pc_error(PC_EINVAL, "pc_source_set_format: missing argument");
	int rc = need_state(s, ST(PC_SOURCE_OPEN), "set_format");
	if (rc)
		return rc;
	if (!s->ops->try_format || !s->ops->set_format)
		return notsup(s, "set_format");
	pc_source_format f = *fmt;
	pc_format_verdict v;
	rc = pc_source_try_format(s, &f, &v);
	if (rc)
		return rc;
	if (v == PC_FORMAT_INVALID)
		return pc_error_prefix(PC_EFORMAT, "set_format: invalid request: ");
	if (v == PC_FORMAT_ADJUSTED)
		return pc_error(PC_EFORMAT,
		                "set_format: the source would adjust this request to %s "
		                "%ux%u at (%u,%u) stride %zu: negotiate with try_format first",
		                f.format_name, f.width, f.height, f.offset_x, f.offset_y, f.stride);
	rc = after(s, s->ops->set_format(s, &f));
	if (rc)
		return rc;
	s->fmt = f;
	return 0;
}

/* ---- controls ---- */

static int check_ctrl(pc_source *s, pc_control_id id, const void *p, const char *op)
{
	if (!s || !p)
		return pc_error(PC_EINVAL, "%s: missing argument", op);
	if ((int)id < 0 || id >= PC_CTRL_COUNT)
		return pc_error(PC_EINVAL, "%s: control %d is not a known control", op, (int)id);
	return need_state(s, ST(PC_SOURCE_OPEN) | ST(PC_SOURCE_READY) | ST(PC_SOURCE_STREAMING),
	                  op);
}

int pc_source_control_query(pc_source *s, pc_control_id id, pc_control_info *info)
{
	int rc = check_ctrl(s, id, info, "control_query");
	if (rc)
		return rc;
	if (!s->ops->control_query)
		return notsup(s, "control_query");
	return after(s, s->ops->control_query(s, id, info));
}

int pc_source_control_get(pc_source *s, pc_control_id id, double *value)
{
	int rc = check_ctrl(s, id, value, "control_get");
	if (rc)
		return rc;
	if (!s->ops->control_get)
		return notsup(s, "control_get");
	return after(s, s->ops->control_get(s, id, value));
}

int pc_source_control_set(pc_source *s, pc_control_id id, double value, double *applied)
{
	int rc = check_ctrl(s, id, &value, "control_set");
	if (rc)
		return rc;
	if (!s->ops->control_set || !s->ops->control_query)
		return notsup(s, "control_set");
	if (!isfinite(value))
		return pc_error(PC_ERANGE, "%s = %g: expected a finite value", pc_control_name(id),
		                value);
	pc_control_info ci;
	rc = after(s, s->ops->control_query(s, id, &ci));
	if (rc)
		return rc;
	if (value < ci.min || value > ci.max)
		return pc_error(PC_ERANGE, "%s = %g: the source accepts [%g, %g]",
		                pc_control_name(id), value, ci.min, ci.max);
	if (s->state == PC_SOURCE_STREAMING && !ci.live)
		return pc_error(PC_ESTATE, "%s: cannot change while streaming on this source",
		                pc_control_name(id));
	double got = value;
	rc = after(s, s->ops->control_set(s, id, value, &got));
	if (!rc && applied)
		*applied = got;
	return rc;
}

/* ---- buffers ---- */

int pc_source_buffers_alloc(pc_source *s, unsigned count)
{
	if (!s)
		return pc_error(PC_EINVAL, "pc_source_buffers_alloc: source missing");
	int rc = need_state(s, ST(PC_SOURCE_OPEN), "buffers_alloc");
	if (rc)
		return rc;
	if (count < 1 || count > PC_SOURCE_MAX_BUFFERS)
		return pc_error(PC_EINVAL, "buffer count %u: expected 1..%u", count,
		                PC_SOURCE_MAX_BUFFERS);
	if (s->fmt.frame_bytes == 0)
		return pc_error(PC_ESTATE, "buffers_alloc: no format negotiated");
	s->bufs = calloc(count, sizeof *s->bufs);
	if (!s->bufs)
		return pc_error(PC_ENOMEM, "%u buffers", count);
	s->n_bufs = count;
	for (unsigned i = 0; i < count; i++) {
		s->bufs[i] = calloc(1, sizeof **s->bufs);
		if (!s->bufs[i]) {
			s->backend_memory = false;
			free_pool(s);
			return pc_error(PC_ENOMEM, "%u buffers", count);
		}
		s->bufs[i]->index = i;
		s->bufs[i]->state = PC_BUFFER_QUEUED;
	}
	if (s->ops->buffers_alloc) {
		s->backend_memory = true;
		rc = after(s, s->ops->buffers_alloc(s, s->bufs, count));
		for (unsigned i = 0; !rc && i < count; i++)
			if (!s->bufs[i]->data || s->bufs[i]->size < s->fmt.frame_bytes)
				rc =
				    pc_error(PC_EIO,
				             "%s: backend buffer %u holds %zu bytes, a frame needs "
				             "%zu",
				             s->scheme, i, s->bufs[i]->size, s->fmt.frame_bytes);
		if (rc) {
			free_pool(s);
			s->backend_memory = false;
			return rc;
		}
	} else {
		s->backend_memory = false;
		size_t sz = (s->fmt.frame_bytes + 63) / 64 * 64;
		for (unsigned i = 0; i < count; i++) {
			s->bufs[i]->data = aligned_alloc(64, sz);
			if (!s->bufs[i]->data) {
				free_pool(s);
				return pc_error(PC_ENOMEM, "%u buffers of %zu bytes", count, sz);
			}
			s->bufs[i]->size = s->fmt.frame_bytes;
		}
	}
	s->state = PC_SOURCE_READY;
	return 0;
}

int pc_source_buffers_free(pc_source *s)
{
	if (!s)
		return pc_error(PC_EINVAL, "pc_source_buffers_free: source missing");
	int rc = need_state(s, ST(PC_SOURCE_READY) | ST(PC_SOURCE_FAILED), "buffers_free");
	if (rc)
		return rc;
	for (unsigned i = 0; i < s->n_bufs; i++)
		if (s->bufs[i]->state == PC_BUFFER_DEQUEUED)
			return pc_error(PC_EBUSY,
			                "buffers_free: buffer %u is still held by the "
			                "application: requeue it first",
			                i);
	free_pool(s);
	if (s->state == PC_SOURCE_READY)
		s->state = PC_SOURCE_OPEN;
	return 0;
}

unsigned pc_source_buffer_count(const pc_source *s)
{
	return s ? s->n_bufs : 0;
}

/* ---- streaming ---- */

int pc_source_start(pc_source *s)
{
	if (!s)
		return pc_error(PC_EINVAL, "pc_source_start: source missing");
	int rc = need_state(s, ST(PC_SOURCE_READY), "start");
	if (rc)
		return rc;
	if (!s->ops->start || !s->ops->dequeue || !s->ops->queue)
		return notsup(s, "start");
	for (unsigned i = 0; i < s->n_bufs; i++)
		if (s->bufs[i]->state == PC_BUFFER_QUEUED) {
			rc = after(s, s->ops->queue(s, s->bufs[i]));
			if (rc) {
				char why[512];
				snprintf(why, sizeof why, "%s", pc_error_detail());
				if (s->ops->stop)
					(void)s->ops->stop(s);
				return pc_error(rc, "%s", why);
			}
		}
	rc = after(s, s->ops->start(s));
	if (rc) {
		char why[512];
		snprintf(why, sizeof why, "%s", pc_error_detail());
		if (s->ops->stop)
			(void)s->ops->stop(s); /* releases the queued buffers; keep start's error */
		return pc_error(rc, "%s", why);
	}
	s->have_last = false;
	s->state = PC_SOURCE_STREAMING;
	return 0;
}

static int check_frame(pc_source *s, pc_buffer *b)
{
	const pc_view *v = &b->frame.view;
	const pc_source_format *f = &s->fmt;
	if (v->format != f->format || v->width != f->width || v->height != f->height ||
	    v->stride != f->stride)
		return pc_error(
		    PC_EIO,
		    "%s: frame %llu is %s %ux%u stride %zu, the negotiated format "
		    "is %s %ux%u stride %zu",
		    s->scheme, (unsigned long long)b->frame.meta.sequence,
		    pc_format_info_get(v->format) ? pc_format_info_get(v->format)->name : "?",
		    v->width, v->height, v->stride, f->format_name, f->width, f->height, f->stride);
	size_t row;
	(void)pc_format_row_bytes(f->format, f->width, &row);
	const uint8_t *lo = b->data, *p = v->data;
	if (!p || p < lo || (size_t)(p - lo) > b->size ||
	    b->size - (size_t)(p - lo) < f->stride * (f->height - 1) + row)
		return pc_error(PC_EIO, "%s: frame %llu data lies outside its buffer", s->scheme,
		                (unsigned long long)b->frame.meta.sequence);
	const pc_frame_meta *m = &b->frame.meta;
	if (s->have_last) {
		if (m->sequence <= s->last_sequence)
			return pc_error(PC_EIO,
			                "%s: frame sequence %llu after %llu: sequence numbers must "
			                "increase",
			                s->scheme, (unsigned long long)m->sequence,
			                (unsigned long long)s->last_sequence);
		if (m->timestamp_ns < s->last_timestamp_ns)
			return pc_error(PC_EIO,
			                "%s: frame %llu timestamp %llu ns before the previous "
			                "frame's %llu ns",
			                s->scheme, (unsigned long long)m->sequence,
			                (unsigned long long)m->timestamp_ns,
			                (unsigned long long)s->last_timestamp_ns);
	}
	return 0;
}

int pc_source_dequeue(pc_source *s, int timeout_ms, pc_buffer **buf)
{
	if (!s || !buf)
		return pc_error(PC_EINVAL, "pc_source_dequeue: missing argument");
	*buf = NULL;
	int rc = need_state(s, ST(PC_SOURCE_STREAMING), "dequeue");
	if (rc)
		return s->state == PC_SOURCE_FAILED
		           ? pc_error(PC_EDISCONNECTED,
		                      "dequeue: the %s: source failed earlier "
		                      "(device lost)",
		                      s->scheme)
		           : rc;
	pc_buffer *b = NULL;
	rc = after(s, s->ops->dequeue(s, timeout_ms, &b));
	if (rc == PC_ETIMEDOUT)
		s->stats.timeouts++;
	if (rc)
		return rc;
	if (!b || b->index >= s->n_bufs || s->bufs[b->index] != b)
		return pc_error(PC_EIO, "%s: backend returned a buffer that is not in the pool",
		                s->scheme);
	if (b->state != PC_BUFFER_QUEUED)
		return pc_error(PC_EIO, "%s: backend returned buffer %u that the application holds",
		                s->scheme, b->index);
	b->state = PC_BUFFER_DEQUEUED;
	b->frame.mosaic = s->fmt.mosaic;
	b->frame.meta.offset_x = s->fmt.offset_x;
	b->frame.meta.offset_y = s->fmt.offset_y;
	rc = check_frame(s, b);
	if (rc) {
		/* The application never sees a frame that breaks the contract: the buffer goes back
		 * to the source and the error surfaces. */
		s->stats.failed++;
		b->state = PC_BUFFER_QUEUED;
		int rc2 = after(s, s->ops->queue(s, b));
		(void)rc2; /* the buffer stays in the pool either way; stop releases it */
		return rc;
	}
	const pc_frame_meta *m = &b->frame.meta;
	if (s->have_last && m->sequence > s->last_sequence + 1)
		s->stats.dropped += m->sequence - s->last_sequence - 1;
	s->have_last = true;
	s->last_sequence = m->sequence;
	s->last_timestamp_ns = m->timestamp_ns;
	if (m->status & (PC_FRAME_INCOMPLETE | PC_FRAME_CORRUPT)) {
		s->stats.failed++;
	} else {
		s->stats.completed++;
		s->stats.bytes += s->fmt.frame_bytes;
	}
	*buf = b;
	return 0;
}

int pc_source_requeue(pc_source *s, pc_buffer *b)
{
	if (!s || !b)
		return pc_error(PC_EINVAL, "pc_source_requeue: missing argument");
	if (b->index >= s->n_bufs || s->bufs[b->index] != b)
		return pc_error(PC_EINVAL, "requeue: the buffer does not belong to this source");
	if (b->state != PC_BUFFER_DEQUEUED)
		return pc_error(PC_EINVAL, "requeue: buffer %u is already queued", b->index);
	int rc = need_state(s, ST(PC_SOURCE_READY) | ST(PC_SOURCE_STREAMING) | ST(PC_SOURCE_FAILED),
	                    "requeue");
	if (rc)
		return rc;
	b->state = PC_BUFFER_QUEUED;
	if (s->state != PC_SOURCE_STREAMING)
		return 0; /* handed to the source at the next start */
	rc = after(s, s->ops->queue(s, b));
	if (rc == PC_EDISCONNECTED)
		return rc; /* the pool keeps it; stop releases everything */
	if (rc)
		b->state = PC_BUFFER_DEQUEUED; /* still the application's */
	return rc;
}

int pc_source_stop(pc_source *s)
{
	if (!s)
		return pc_error(PC_EINVAL, "pc_source_stop: source missing");
	int rc = need_state(s, ST(PC_SOURCE_STREAMING) | ST(PC_SOURCE_FAILED), "stop");
	if (rc)
		return rc;
	rc = s->ops->stop ? s->ops->stop(s) : 0;
	/* Whatever the backend says, it has forgotten every queued buffer: they are the pool's. */
	if (s->state == PC_SOURCE_STREAMING)
		s->state = PC_SOURCE_READY;
	if (rc == PC_EDISCONNECTED)
		rc = 0; /* stopping a lost device is not a new error */
	return rc;
}

int pc_source_get_stats(pc_source *s, pc_source_stats *st)
{
	if (!s || !st)
		return pc_error(PC_EINVAL, "pc_source_get_stats: missing argument");
	*st = s->stats;
	if (!s->ops->get_stats)
		return 0;
	pc_source_stats b;
	memset(&b, 0, sizeof b);
	int rc = s->ops->get_stats(s, &b);
	if (rc)
		return rc;
	st->underruns = b.underruns;
	st->transport_failures = b.transport_failures;
	st->has_packets = b.has_packets;
	st->missing_packets = b.missing_packets;
	st->resent_packets = b.resent_packets;
	return 0;
}
