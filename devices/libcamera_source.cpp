/* The `libcamera:` frame source: libcamera (C++) behind the C frame-source ops
 * (polarcam/source.h). The one C++ file of the devices layer; nothing C++ leaks out: every op
 * catches exceptions and answers with a PC_E* code.
 *
 *   libcamera:ID[?mosaic=LAYOUT|none]     ID = the camera id libcamera reports, or its index
 *
 * Formats: libcamera's monochrome raw formats map to the format table: R8 -> Mono8,
 * R10 -> Mono10, R12 -> Mono12, R16 -> Mono16 (LSB-aligned in 16 bits), R10/R12 with the MIPI
 * CSI-2 packing modifier -> Y10P/Y12P. Negotiation is libcamera's own CameraConfiguration::
 * validate() (Valid / Adjusted / Invalid, the model of polarcam's verdicts) on a fresh
 * configuration, so trying changes nothing. Strides are libcamera's (not requestable). ROI
 * offsets are not offered (adjusted to 0, 0).
 * Controls: exposure_us = controls::ExposureTime (µs), gain_db = 20 log10(AnalogueGain),
 * frame_rate_hz = 1 / FrameDurationLimits; values set are carried by the next queued request.
 * Black level: the per-frame metadata controls::SensorBlackLevels (a 16-bit scale), converted
 * to DN of the delivered format (libcamera_black.h); get_info declares the level of the latest
 * frame that carried one, and none (0) before the first such frame.
 * Buffers: one FrameBufferAllocator buffer and one Request per pool buffer, mapped once.
 * Completed requests arrive on libcamera's thread and wait in a queue for pc_source_dequeue.
 * libcamera's log goes nowhere unless LIBCAMERA_LOG_LEVELS or LIBCAMERA_LOG_FILE is set (the
 * library never prints behind the caller's back).
 */
#include "polarcam/source.h"

#include <sys/mman.h>

#include <libcamera/libcamera.h>
#include <libcamera/logging.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <memory>
#include <mutex>
#include <new>
#include <string>
#include <vector>

#include "libcamera_black.h"

extern "C" {
#include "backends.h"
#include "polarcam/error.h"
}

using namespace libcamera;

namespace
{

/* ---- one CameraManager per process (libcamera allows no more), shared by users ---- */

std::mutex cm_mutex;
std::unique_ptr<CameraManager> cm;
unsigned cm_users;

int cm_get(CameraManager **out)
{
	std::lock_guard<std::mutex> lock(cm_mutex);
	if (!cm) {
		if (!std::getenv("LIBCAMERA_LOG_LEVELS") && !std::getenv("LIBCAMERA_LOG_FILE"))
			logSetTarget(LoggingTargetNone);
		auto m = std::make_unique<CameraManager>();
		int r = m->start();
		if (r)
			return pc_error(PC_EIO, "libcamera: the camera manager did not start (%s)",
			                std::strerror(-r));
		cm = std::move(m);
	}
	cm_users++;
	*out = cm.get();
	return 0;
}

void cm_put()
{
	std::lock_guard<std::mutex> lock(cm_mutex);
	if (cm_users && --cm_users == 0) {
		cm->stop();
		cm.reset();
	}
}

/* ---- formats ---- */

constexpr uint32_t fourcc(char a, char b, char c, char d)
{
	return (uint32_t)a | ((uint32_t)b << 8) | ((uint32_t)c << 16) | ((uint32_t)d << 24);
}

/* The MIPI CSI-2 packing modifier, as libcamera's R10_CSI2P carries it. */
uint64_t mipi_modifier()
{
	return formats::R10_CSI2P.modifier();
}

pc_pixfmt pc_from_libcamera(const PixelFormat &pf)
{
	bool mipi = pf.modifier() != 0 && pf.modifier() == mipi_modifier();
	if (pf.modifier() != 0 && !mipi)
		return PC_FMT_INVALID;
	switch (pf.fourcc()) {
	case fourcc('R', '8', ' ', ' '):
		return mipi ? PC_FMT_INVALID : PC_FMT_MONO8;
	case fourcc('R', '1', '0', ' '):
		return mipi ? PC_FMT_Y10P : PC_FMT_MONO10;
	case fourcc('R', '1', '2', ' '):
		return mipi ? PC_FMT_Y12P : PC_FMT_MONO12;
	case fourcc('R', '1', '6', ' '):
		return mipi ? PC_FMT_INVALID : PC_FMT_MONO16;
	default:
		return PC_FMT_INVALID;
	}
}

PixelFormat libcamera_from_pc(pc_pixfmt f)
{
	switch (f) {
	case PC_FMT_MONO8:
		return PixelFormat(fourcc('R', '8', ' ', ' '));
	case PC_FMT_MONO10:
		return PixelFormat(fourcc('R', '1', '0', ' '));
	case PC_FMT_MONO12:
		return PixelFormat(fourcc('R', '1', '2', ' '));
	case PC_FMT_MONO16:
		return PixelFormat(fourcc('R', '1', '6', ' '));
	case PC_FMT_Y10P:
		return PixelFormat(fourcc('R', '1', '0', ' '), mipi_modifier());
	case PC_FMT_Y12P:
		return PixelFormat(fourcc('R', '1', '2', ' '), mipi_modifier());
	default:
		return PixelFormat();
	}
}

/* ---- the source ---- */

struct lc_src {
	CameraManager *mgr = nullptr;
	std::shared_ptr<Camera> cam;
	bool acquired = false;
	std::unique_ptr<CameraConfiguration> config; /* the applied one */
	Stream *stream = nullptr;
	std::unique_ptr<FrameBufferAllocator> alloc;
	std::vector<std::unique_ptr<Request>> requests; /* one per pool buffer */
	std::vector<std::pair<void *, size_t>> maps;
	pc_buffer **bufs = nullptr;
	unsigned nbufs = 0;
	std::vector<unsigned> waiting; /* queued before start */
	bool started = false;

	std::mutex mtx;
	std::condition_variable cv;
	std::deque<Request *> done;
	bool disconnected = false;
	double black_dn = 0; /* of the latest frame whose metadata declared one (under mtx) */

	ControlList pending; /* controls for the next queued request */
	double exposure_us = 0, gain_db = 0, fps = 0;
	bool have_exposure = false, have_gain = false, have_fps = false;

	uint32_t sensor_w = 0, sensor_h = 0;
	bool polarized = true;
	pc_mosaic mosaic{};

	bool have_last = false;
	uint32_t last_raw = 0;
	uint64_t last_drv = 0, last_out = 0;

	void on_request(Request *r)
	{
		std::lock_guard<std::mutex> lock(mtx);
		if (r->status() == Request::RequestCancelled)
			return; /* stop() takes every buffer back */
		done.push_back(r);
		cv.notify_one();
	}
	void on_disconnect()
	{
		std::lock_guard<std::mutex> lock(mtx);
		disconnected = true;
		cv.notify_all();
	}
};

lc_src *priv(pc_source *s)
{
	return static_cast<lc_src *>(pc_source_priv(s));
}

const char *cam_name(const lc_src *v)
{
	return v->cam ? v->cam->id().c_str() : "?";
}

std::unique_ptr<CameraConfiguration> fresh_config(lc_src *v)
{
	auto c = v->cam->generateConfiguration({StreamRole::Raw});
	if (!c || c->empty())
		c = v->cam->generateConfiguration({StreamRole::Viewfinder});
	return c;
}

/* Wraps an op: C++ exceptions never cross into C. */
template <typename F> int guarded(const char *what, F f)
{
	try {
		return f();
	} catch (const std::bad_alloc &) {
		return pc_error(PC_ENOMEM, "libcamera: %s: out of memory", what);
	} catch (const std::exception &e) {
		return pc_error(PC_EIO, "libcamera: %s: %s", what, e.what());
	} catch (...) {
		return pc_error(PC_EIO, "libcamera: %s: unexpected exception", what);
	}
}

void release_buffers(lc_src *v)
{
	for (auto &m : v->maps)
		if (m.first && m.first != MAP_FAILED)
			munmap(m.first, m.second);
	v->maps.clear();
	v->requests.clear();
	if (v->alloc && v->stream)
		v->alloc->free(v->stream);
	v->alloc.reset();
	v->bufs = nullptr;
	v->nbufs = 0;
	v->waiting.clear();
}

void lc_close(pc_source *s)
{
	lc_src *v = priv(s);
	if (!v)
		return;
	try {
		if (v->started)
			v->cam->stop();
		release_buffers(v);
		if (v->cam) {
			v->cam->requestCompleted.disconnect(v);
			v->cam->disconnected.disconnect(v);
			if (v->acquired)
				v->cam->release();
		}
		v->config.reset();
		v->cam.reset();
	} catch (...) {
	}
	if (v->mgr)
		cm_put();
	delete v;
	pc_source_set_priv(s, nullptr);
}

int lc_open(pc_source *s, const char *arg)
{
	return guarded("open", [&]() -> int {
		if (!arg || !*arg)
			return pc_error(PC_EINVAL,
			                "libcamera: camera id missing: expected libcamera:ID "
			                "(see polarcam devices)");
		lc_src *v = new lc_src;
		pc_source_set_priv(s, v);
		v->mosaic = pc_mosaic_imx250mzr();
		const char *mos = pc_source_option(s, "mosaic");
		int rc = 0;
		if (mos) {
			if (!std::strcmp(mos, "none")) {
				v->polarized = false;
				std::memset(&v->mosaic, 0, sizeof v->mosaic);
			} else if ((rc = pc_mosaic_parse(mos, &v->mosaic))) {
				rc = pc_error_prefix(rc, "URI option mosaic=%s: ", mos);
			}
		}
		if (!rc)
			rc = cm_get(&v->mgr);
		if (rc) {
			lc_close(s);
			return rc;
		}
		auto cams = v->mgr->cameras();
		v->cam = v->mgr->get(arg);
		if (!v->cam && std::strspn(arg, "0123456789") == std::strlen(arg)) {
			unsigned long i = std::strtoul(arg, nullptr, 10);
			if (i < cams.size())
				v->cam = cams[i];
		}
		if (!v->cam) {
			std::string ids;
			for (auto &c : cams)
				ids += (ids.empty() ? "" : ", ") + c->id();
			rc = pc_error(PC_ENOENT, "libcamera: no camera '%s' (%zu camera%s: %s)",
			              arg, cams.size(), cams.size() == 1 ? "" : "s",
			              ids.empty() ? "none" : ids.c_str());
			lc_close(s);
			return rc;
		}
		int r = v->cam->acquire();
		if (r) {
			rc = pc_error(r == -EBUSY ? PC_EBUSY : PC_EIO,
			              "libcamera: camera '%s' cannot be "
			              "acquired (%s)",
			              arg, std::strerror(-r));
			lc_close(s);
			return rc;
		}
		v->acquired = true;
		v->cam->requestCompleted.connect(v, &lc_src::on_request);
		v->cam->disconnected.connect(v, &lc_src::on_disconnect);
		/* sensor size: the pixel array, else the largest size of the default format */
		auto pa = v->cam->properties().get(properties::PixelArraySize);
		auto cfg = fresh_config(v);
		if (!cfg) {
			rc = pc_error(PC_EIO,
			              "libcamera: camera '%s' offers no stream configuration", arg);
			lc_close(s);
			return rc;
		}
		if (pa) {
			v->sensor_w = pa->width;
			v->sensor_h = pa->height;
		}
		const StreamConfiguration &sc = cfg->at(0);
		SizeRange range = sc.formats().range(sc.pixelFormat);
		if (!v->sensor_w && range.max.width) {
			v->sensor_w = range.max.width;
			v->sensor_h = range.max.height;
		}
		if (!v->sensor_w) {
			v->sensor_w = sc.size.width;
			v->sensor_h = sc.size.height;
		}
		return 0;
	});
}

int lc_get_info(pc_source *s, pc_source_info *info)
{
	return guarded("get_info", [&]() -> int {
		lc_src *v = priv(s);
		auto model = v->cam->properties().get(properties::Model);
		std::snprintf(info->vendor, sizeof info->vendor, "libcamera");
		std::snprintf(info->model, sizeof info->model, "%s",
		              model ? model->c_str() : v->cam->id().c_str());
		std::snprintf(info->serial, sizeof info->serial, "%.63s", v->cam->id().c_str());
		std::snprintf(info->driver, sizeof info->driver, "libcamera %s",
		              CameraManager::version().c_str());
		info->sensor_width = v->sensor_w;
		info->sensor_height = v->sensor_h;
		info->polarized = v->polarized;
		if (v->polarized)
			info->mosaic = v->mosaic;
		std::lock_guard<std::mutex> lock(v->mtx);
		info->black_level = v->black_dn;
		info->black_level_late = true; /* per-frame metadata */
		return 0;
	});
}

/* The formats of a configuration that polarcam reads. */
std::vector<PixelFormat> readable(const StreamConfiguration &sc)
{
	std::vector<PixelFormat> out;
	for (const PixelFormat &pf : sc.formats().pixelformats())
		if (pc_from_libcamera(pf) != PC_FMT_INVALID)
			out.push_back(pf);
	return out;
}

/* Fills *cfg from a request; returns the verdict or -1 with the detail set (invalid). */
int negotiate(lc_src *v, const pc_source_format &req, CameraConfiguration *cfg, bool *adjusted)
{
	StreamConfiguration &sc = cfg->at(0);
	std::vector<PixelFormat> have = readable(sc);
	if (have.empty()) {
		pc_error(PC_EFORMAT,
		         "libcamera: camera '%s' offers no raw monochrome format polarcam "
		         "reads (R8, R10, R12, R16, R10/R12 CSI-2 packed)",
		         cam_name(v));
		return -1;
	}
	PixelFormat want;
	if (req.format_name[0]) {
		want = PixelFormat::fromString(req.format_name);
		if (!want.isValid())
			want = libcamera_from_pc(pc_format_from_name(req.format_name));
		if (!want.isValid()) {
			pc_error(PC_EINVAL,
			         "format name '%s': neither a libcamera nor a polarcam format "
			         "name",
			         req.format_name);
			return -1;
		}
	}
	if (req.format != PC_FMT_INVALID) {
		PixelFormat p = libcamera_from_pc(req.format);
		if (!p.isValid())
			*adjusted = true;
		else
			want = p;
	}
	if (!want.isValid())
		want =
		    pc_from_libcamera(sc.pixelFormat) != PC_FMT_INVALID ? sc.pixelFormat : have[0];
	bool offered = false;
	for (auto &p : have)
		offered = offered || p == want;
	if (!offered) {
		want = have[0];
		*adjusted = true;
	}
	if (req.offset_x || req.offset_y)
		*adjusted = true;
	uint32_t w = req.width ? req.width : v->sensor_w, h = req.height ? req.height : v->sensor_h;
	if (w > v->sensor_w || h > v->sensor_h) {
		w = std::min(w, v->sensor_w);
		h = std::min(h, v->sensor_h);
		*adjusted = true;
	}
	sc.pixelFormat = want;
	sc.size = Size(w, h);
	CameraConfiguration::Status st = cfg->validate();
	if (st == CameraConfiguration::Invalid) {
		pc_error(PC_EFORMAT, "libcamera: camera '%s' refuses %s %ux%u", cam_name(v),
		         want.toString().c_str(), w, h);
		return -1;
	}
	if (st == CameraConfiguration::Adjusted &&
	    (sc.pixelFormat != want || (req.width && sc.size.width != req.width) ||
	     (req.height && sc.size.height != req.height)))
		*adjusted = true;
	if (pc_from_libcamera(sc.pixelFormat) == PC_FMT_INVALID) {
		pc_error(PC_EFORMAT,
		         "libcamera: camera '%s' answers %s, which polarcam cannot read",
		         cam_name(v), sc.pixelFormat.toString().c_str());
		return -1;
	}
	if (req.stride && req.stride != sc.stride)
		*adjusted = true;
	return 0;
}

void fill_format(lc_src *v, const StreamConfiguration &sc, pc_source_format *fmt)
{
	std::memset(fmt, 0, sizeof *fmt);
	fmt->format = pc_from_libcamera(sc.pixelFormat);
	std::snprintf(fmt->format_name, sizeof fmt->format_name, "%s",
	              sc.pixelFormat.toString().c_str());
	fmt->width = sc.size.width;
	fmt->height = sc.size.height;
	fmt->stride = sc.stride;
	fmt->frame_bytes = sc.frameSize;
	fmt->polarized = v->polarized;
	fmt->sensor_width = v->sensor_w;
	fmt->sensor_height = v->sensor_h;
}

int lc_try_format(pc_source *s, pc_source_format *fmt, pc_format_verdict *verdict)
{
	return guarded("try_format", [&]() -> int {
		lc_src *v = priv(s);
		*verdict = PC_FORMAT_INVALID;
		auto cfg = fresh_config(v);
		if (!cfg)
			return pc_error(PC_EIO, "libcamera: no configuration");
		bool adjusted = false;
		pc_source_format req = *fmt;
		if (negotiate(v, req, cfg.get(), &adjusted) < 0)
			return 0;
		fill_format(v, cfg->at(0), fmt);
		if (!adjusted && req.format_name[0])
			std::snprintf(fmt->format_name, sizeof fmt->format_name, "%s",
			              req.format_name);
		int rc = pc_source_format_complete(fmt, v->polarized ? &v->mosaic : nullptr);
		if (rc)
			return rc;
		*verdict = adjusted ? PC_FORMAT_ADJUSTED : PC_FORMAT_VALID;
		return 0;
	});
}

/* Configures the camera for fmt with count buffers (0 = libcamera's choice). */
int configure(lc_src *v, const pc_source_format &fmt, unsigned count)
{
	auto cfg = fresh_config(v);
	if (!cfg)
		return pc_error(PC_EIO, "libcamera: no configuration");
	bool adjusted = false;
	pc_source_format req = fmt;
	req.format_name[0] = '\0';
	if (negotiate(v, req, cfg.get(), &adjusted) < 0)
		return PC_EFORMAT;
	StreamConfiguration &sc = cfg->at(0);
	if (count) {
		sc.bufferCount = count;
		if (cfg->validate() == CameraConfiguration::Invalid || sc.bufferCount < count)
			return pc_error(PC_EINVAL,
			                "libcamera: camera '%s' cannot run with %u buffers",
			                cam_name(v), count);
	}
	if (adjusted || sc.size.width != fmt.width || sc.size.height != fmt.height ||
	    sc.stride != fmt.stride || pc_from_libcamera(sc.pixelFormat) != fmt.format)
		return pc_error(PC_EIO, "libcamera: camera '%s' changed the negotiated format",
		                cam_name(v));
	int r = v->cam->configure(cfg.get());
	if (r)
		return pc_error(r == -EACCES ? PC_ESTATE : PC_EIO, "libcamera: configure: %s",
		                std::strerror(-r));
	v->stream = sc.stream();
	v->config = std::move(cfg);
	std::lock_guard<std::mutex> lock(v->mtx);
	v->black_dn = 0; /* a level of the previous format's bits no longer holds */
	return 0;
}

int lc_set_format(pc_source *s, const pc_source_format *fmt)
{
	return guarded("set_format", [&]() -> int { return configure(priv(s), *fmt, 0); });
}

/* ---- controls ---- */

const ControlInfo *find_ctrl(lc_src *v, const ControlId &id)
{
	const ControlInfoMap &m = v->cam->controls();
	auto it = m.find(id.id());
	return it == m.end() ? nullptr : &it->second;
}

int notsup(lc_src *v, const char *what)
{
	return pc_error(PC_ENOTSUP, "libcamera: camera '%s' has no %s control", cam_name(v), what);
}

int lc_control_query(pc_source *s, pc_control_id id, pc_control_info *info)
{
	return guarded("control_query", [&]() -> int {
		lc_src *v = priv(s);
		std::memset(info, 0, sizeof *info);
		info->live = true;
		switch (id) {
		case PC_CTRL_EXPOSURE_US: {
			const ControlInfo *ci = find_ctrl(v, controls::ExposureTime);
			if (!ci)
				return notsup(v, "ExposureTime");
			info->min = ci->min().get<int32_t>();
			info->max = ci->max().get<int32_t>();
			info->def = ci->def().isNone() ? info->min : ci->def().get<int32_t>();
			info->step = 1.0;
			return 0;
		}
		case PC_CTRL_GAIN_DB: {
			const ControlInfo *ci = find_ctrl(v, controls::AnalogueGain);
			if (!ci)
				return notsup(v, "AnalogueGain");
			float lo = ci->min().get<float>(), hi = ci->max().get<float>();
			if (!(lo > 0.0f) || hi < lo)
				return pc_error(PC_EIO,
				                "libcamera: AnalogueGain range [%g, %g] is not a "
				                "gain",
				                (double)lo, (double)hi);
			info->min = 20.0 * std::log10((double)lo);
			info->max = 20.0 * std::log10((double)hi);
			info->def = ci->def().isNone()
			                ? info->min
			                : 20.0 * std::log10((double)ci->def().get<float>());
			return 0;
		}
		case PC_CTRL_FRAME_RATE_HZ: {
			const ControlInfo *ci = find_ctrl(v, controls::FrameDurationLimits);
			if (!ci)
				return notsup(v, "FrameDurationLimits");
			int64_t dmin = ci->min().get<int64_t>(), dmax = ci->max().get<int64_t>();
			if (dmin <= 0 || dmax < dmin)
				return pc_error(PC_EIO,
				                "libcamera: frame durations [%lld, %lld] us",
				                (long long)dmin, (long long)dmax);
			info->min = 1e6 / (double)dmax;
			info->max = 1e6 / (double)dmin;
			info->def = info->max;
			return 0;
		}
		case PC_CTRL_COUNT:
			break;
		}
		return pc_error(PC_EINVAL, "control %d unknown", (int)id);
	});
}

int lc_control_get(pc_source *s, pc_control_id id, double *value)
{
	pc_control_info ci;
	int rc = lc_control_query(s, id, &ci);
	if (rc)
		return rc;
	lc_src *v = priv(s);
	switch (id) {
	case PC_CTRL_EXPOSURE_US:
		*value = v->have_exposure ? v->exposure_us : ci.def;
		return 0;
	case PC_CTRL_GAIN_DB:
		*value = v->have_gain ? v->gain_db : ci.def;
		return 0;
	case PC_CTRL_FRAME_RATE_HZ:
		*value = v->have_fps ? v->fps : ci.def;
		return 0;
	case PC_CTRL_COUNT:
		break;
	}
	return pc_error(PC_EINVAL, "control %d unknown", (int)id);
}

int lc_control_set(pc_source *s, pc_control_id id, double value, double *applied)
{
	return guarded("control_set", [&]() -> int {
		lc_src *v = priv(s);
		pc_control_info ci;
		int rc = lc_control_query(s, id, &ci);
		if (rc)
			return rc;
		switch (id) {
		case PC_CTRL_EXPOSURE_US: {
			int32_t us = (int32_t)std::lround(value);
			if (find_ctrl(v, controls::AeEnable))
				v->pending.set(controls::AeEnable, false);
			v->pending.set(controls::ExposureTime, us);
			v->exposure_us = *applied = us;
			v->have_exposure = true;
			return 0;
		}
		case PC_CTRL_GAIN_DB: {
			float g = (float)std::pow(10.0, value / 20.0);
			if (find_ctrl(v, controls::AeEnable))
				v->pending.set(controls::AeEnable, false);
			v->pending.set(controls::AnalogueGain, g);
			v->gain_db = *applied = value;
			v->have_gain = true;
			return 0;
		}
		case PC_CTRL_FRAME_RATE_HZ: {
			int64_t d = (int64_t)std::llround(1e6 / value);
			v->pending.set(controls::FrameDurationLimits, {d, d});
			v->fps = *applied = 1e6 / (double)d;
			v->have_fps = true;
			return 0;
		}
		case PC_CTRL_COUNT:
			break;
		}
		return pc_error(PC_EINVAL, "control %d unknown", (int)id);
	});
}

/* ---- buffers and streaming ---- */

int lc_buffers_alloc(pc_source *s, pc_buffer **bufs, unsigned count)
{
	return guarded("buffers_alloc", [&]() -> int {
		lc_src *v = priv(s);
		int rc = configure(v, *pc_source_current_format(s), count);
		if (rc)
			return rc;
		v->alloc = std::make_unique<FrameBufferAllocator>(v->cam);
		int n = v->alloc->allocate(v->stream);
		if (n < (int)count) {
			release_buffers(v);
			return pc_error(PC_ENOMEM, "libcamera: %d of %u buffers allocated",
			                n < 0 ? 0 : n, count);
		}
		const auto &fbs = v->alloc->buffers(v->stream);
		for (unsigned i = 0; i < count; i++) {
			FrameBuffer *fb = fbs[i].get();
			const FrameBuffer::Plane &p = fb->planes()[0];
			size_t len = (size_t)p.offset + p.length;
			void *m = mmap(nullptr, len, PROT_READ, MAP_SHARED, p.fd.get(), 0);
			if (m == MAP_FAILED) {
				release_buffers(v);
				return pc_error(PC_EIO, "libcamera: mmap of buffer %u: %s", i,
				                std::strerror(errno));
			}
			v->maps.emplace_back(m, len);
			bufs[i]->data = static_cast<uint8_t *>(m) + p.offset;
			bufs[i]->size = p.length;
			std::unique_ptr<Request> r = v->cam->createRequest(i);
			if (!r || r->addBuffer(v->stream, fb)) {
				release_buffers(v);
				return pc_error(PC_EIO, "libcamera: request for buffer %u", i);
			}
			v->requests.push_back(std::move(r));
		}
		v->bufs = bufs;
		v->nbufs = count;
		return 0;
	});
}

void lc_buffers_free(pc_source *s, pc_buffer **bufs, unsigned count)
{
	lc_src *v = priv(s);
	try {
		release_buffers(v);
	} catch (...) {
	}
	for (unsigned i = 0; i < count; i++) {
		bufs[i]->data = nullptr;
		bufs[i]->size = 0;
	}
}

int queue_now(lc_src *v, unsigned index)
{
	Request *r = v->requests[index].get();
	r->reuse(Request::ReuseBuffers);
	if (!v->pending.empty()) {
		r->controls().merge(v->pending);
		v->pending.clear();
	}
	int e = v->cam->queueRequest(r);
	if (e == -ENODEV)
		return pc_error(PC_EDISCONNECTED, "libcamera: camera '%s' was disconnected",
		                cam_name(v));
	if (e)
		return pc_error(PC_EIO, "libcamera: queueRequest: %s", std::strerror(-e));
	return 0;
}

int lc_queue(pc_source *s, pc_buffer *buf)
{
	return guarded("queue", [&]() -> int {
		lc_src *v = priv(s);
		if (buf->index >= v->nbufs)
			return pc_error(PC_EINVAL, "libcamera: buffer %u not in the pool",
			                buf->index);
		if (!v->started) {
			v->waiting.push_back(buf->index);
			return 0;
		}
		return queue_now(v, buf->index);
	});
}

int lc_start(pc_source *s)
{
	return guarded("start", [&]() -> int {
		lc_src *v = priv(s);
		{
			std::lock_guard<std::mutex> lock(v->mtx);
			v->done.clear();
			if (v->disconnected)
				return pc_error(PC_EDISCONNECTED, "libcamera: camera '%s' is gone",
				                cam_name(v));
		}
		v->have_last = false;
		int e = v->cam->start();
		if (e)
			return pc_error(e == -ENODEV ? PC_EDISCONNECTED : PC_EIO,
			                "libcamera: start: %s", std::strerror(-e));
		v->started = true;
		std::vector<unsigned> w;
		w.swap(v->waiting);
		for (unsigned i : w) {
			int rc = queue_now(v, i);
			if (rc)
				return rc;
		}
		return 0;
	});
}

uint64_t next_sequence(lc_src *v, uint32_t raw)
{
	if (!v->have_last) {
		v->have_last = true;
		v->last_raw = raw;
		v->last_drv = v->last_out = raw;
		return raw;
	}
	uint32_t delta = raw - v->last_raw;
	uint64_t drv =
	    delta < 0x80000000u
	        ? v->last_drv + delta
	        : (v->last_drv >= (uint64_t)(0u - delta) ? v->last_drv - (0u - delta) : 0);
	v->last_raw = raw;
	v->last_drv = drv;
	v->last_out = drv > v->last_out ? drv : v->last_out + 1;
	return v->last_out;
}

int lc_dequeue(pc_source *s, int timeout_ms, pc_buffer **out)
{
	return guarded("dequeue", [&]() -> int {
		lc_src *v = priv(s);
		Request *r = nullptr;
		{
			std::unique_lock<std::mutex> lock(v->mtx);
			auto ready = [&] { return !v->done.empty() || v->disconnected; };
			if (timeout_ms < 0)
				v->cv.wait(lock, ready);
			else if (!v->cv.wait_for(lock, std::chrono::milliseconds(timeout_ms),
			                         ready))
				return pc_error(PC_ETIMEDOUT, "libcamera: no frame within %d ms",
				                timeout_ms);
			if (v->done.empty())
				return pc_error(PC_EDISCONNECTED,
				                "libcamera: camera '%s' was disconnected",
				                cam_name(v));
			r = v->done.front();
			v->done.pop_front();
		}
		unsigned idx = (unsigned)r->cookie();
		if (idx >= v->nbufs)
			return pc_error(PC_EIO, "libcamera: completed request %u not in the pool",
			                idx);
		FrameBuffer *fb = r->findBuffer(v->stream);
		pc_buffer *pb = v->bufs[idx];
		const pc_source_format *f = pc_source_current_format(s);
		pc_frame *fr = &pb->frame;
		fr->view.data = pb->data;
		fr->view.width = f->width;
		fr->view.height = f->height;
		fr->view.stride = f->stride;
		fr->view.format = f->format;
		std::memset(&fr->meta, 0, sizeof fr->meta);
		const FrameMetadata &md = fb->metadata();
		fr->meta.sequence = next_sequence(v, md.sequence);
		fr->meta.timestamp_ns = md.timestamp;
		auto et = r->metadata().get(controls::ExposureTime);
		auto ag = r->metadata().get(controls::AnalogueGain);
		/* the request's metadata, else what was set, else unknown (NAN) */
		fr->meta.exposure_us = et ? (double)*et : v->have_exposure ? v->exposure_us : NAN;
		fr->meta.gain_db = ag && *ag > 0  ? 20.0 * std::log10((double)*ag)
		                   : v->have_gain ? v->gain_db
		                                  : NAN;
		double black = 0;
		const pc_format_info *fi = pc_format_info_get(f->format);
		if (fi && pc_libcamera_black_level_dn(r->metadata(), fi->bits, &black)) {
			std::lock_guard<std::mutex> lock(v->mtx);
			v->black_dn = black;
		}
		size_t row = 0;
		(void)pc_format_row_bytes(f->format, f->width, &row);
		if (md.status != FrameMetadata::FrameSuccess)
			fr->meta.status |= PC_FRAME_CORRUPT;
		if (md.planes().size() < 1 ||
		    md.planes()[0].bytesused < f->stride * (f->height - 1) + row)
			fr->meta.status |= PC_FRAME_INCOMPLETE;
		*out = pb;
		return 0;
	});
}

int lc_stop(pc_source *s)
{
	return guarded("stop", [&]() -> int {
		lc_src *v = priv(s);
		int e = 0;
		if (v->started)
			e = v->cam->stop(); /* cancels every queued request */
		v->started = false;
		v->waiting.clear();
		std::lock_guard<std::mutex> lock(v->mtx);
		v->done.clear();
		if (e && e != -ENODEV)
			return pc_error(PC_EIO, "libcamera: stop: %s", std::strerror(-e));
		return 0;
	});
}

const char *const lc_options[] = {"mosaic", nullptr};

} /* namespace */

bool pc_libcamera_black_level_dn(const ControlList &metadata, unsigned bits, double *dn)
{
	if (bits < 1 || bits > 16)
		return false;
	const auto levels = metadata.get(controls::SensorBlackLevels);
	if (!levels || levels->empty())
		return false;
	double sum = 0;
	for (int32_t l : *levels)
		sum += l;
	const double mean = sum / (double)levels->size();
	if (!(mean > 0))
		return false;
	*dn = std::ldexp(mean, (int)bits - 16);
	return true;
}

extern "C" {

int pc_libcamera_enumerate(unsigned flags, pc_device_fn fn, void *ctx)
{
	(void)flags; /* libcamera cameras are local */
	return guarded("enumerate", [&]() -> int {
		CameraManager *m;
		int rc = cm_get(&m);
		if (rc)
			return rc;
		for (const std::shared_ptr<Camera> &c : m->cameras()) {
			pc_device_entry e;
			std::memset(&e, 0, sizeof e);
			std::snprintf(e.uri, sizeof e.uri, "libcamera:%.240s", c->id().c_str());
			auto model = c->properties().get(properties::Model);
			std::snprintf(e.vendor, sizeof e.vendor, "libcamera");
			std::snprintf(e.model, sizeof e.model, "%.63s",
			              model ? model->c_str() : "");
			std::snprintf(e.transport, sizeof e.transport, "libcamera");
			std::snprintf(e.address, sizeof e.address, "%.63s", c->id().c_str());
			auto cfg = c->generateConfiguration({StreamRole::Raw});
			if (cfg && !cfg->empty()) {
				auto all = cfg->at(0).formats().pixelformats();
				e.formats_total = (unsigned)all.size();
				for (const PixelFormat &pf : all) {
					if (pc_from_libcamera(pf) == PC_FMT_INVALID)
						continue;
					size_t used = std::strlen(e.formats);
					std::snprintf(e.formats + used, sizeof e.formats - used,
					              "%s%s", used ? " " : "",
					              pf.toString().c_str());
				}
			}
			if (!e.formats[0])
				std::snprintf(e.note, sizeof e.note,
				              "no raw monochrome format polarcam "
				              "reads");
			e.usable = e.formats[0] != '\0';
			if ((rc = fn(ctx, &e)))
				break;
		}
		cm_put();
		return rc > 0 ? 0 : rc;
	});
}

extern const pc_source_ops pc_libcamera_source_ops;
const pc_source_ops pc_libcamera_source_ops = {
    lc_open,          lc_close,         lc_get_info,    lc_try_format,
    lc_set_format,    lc_control_query, lc_control_get, lc_control_set,
    lc_buffers_alloc, lc_buffers_free,  lc_queue,       lc_start,
    lc_dequeue,       lc_stop,          nullptr,        lc_options,
};

} /* extern "C" */
