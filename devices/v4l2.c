/* V4L2 video nodes: open/query, formats, inputs and DV timings, controls, mmap streaming,
 * listing. See polarcam/v4l2.h. Written against the V4L2 uAPI (linux/videodev2.h). */

#include "polarcam/v4l2.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <linux/videodev2.h>
#include <math.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "polarcam/error.h"

typedef struct pc_v4l2_slot {
	void *data;
	size_t length;
	bool queued; /* owned by the driver */
	bool fresh;  /* output buffer never handed out yet */
} pc_v4l2_slot;

struct pc_v4l2 {
	int fd;
	pc_v4l2_dir dir;
	uint32_t type; /* V4L2_BUF_TYPE_VIDEO_CAPTURE or _OUTPUT (or their _MPLANE) */
	bool mplane;   /* the multi-planar API, with one plane */
	pc_v4l2_info info;
	pc_v4l2_format fmt; /* the format streaming uses */
	pc_v4l2_slot *slots;
	unsigned nslots;
	unsigned queued;
	bool streaming;
};

/* ---- errors ---- */

static const char *errtext(int e, char *buf, size_t size)
{
	/* XSI strerror_r (we do not define _GNU_SOURCE) */
	if (strerror_r(e, buf, size) != 0)
		snprintf(buf, size, "errno %d", e);
	return buf;
}

static int errno_code(int e)
{
	switch (e) {
	case ENODEV:
	case ENXIO:
		return PC_EDISCONNECTED;
	case ENOENT:
		return PC_ENOENT;
	case EACCES:
	case EPERM:
		return PC_EPERM;
	case EINVAL:
		return PC_EINVAL;
	case ENOTTY:
	case EOPNOTSUPP:
		return PC_ENOTSUP;
	case EBUSY:
		return PC_EBUSY;
	case ENOMEM:
		return PC_ENOMEM;
	case EAGAIN:
		return PC_EAGAIN;
	case ERANGE:
		return PC_ERANGE;
	case ETIMEDOUT:
		return PC_ETIMEDOUT;
	default:
		return PC_EIO;
	}
}

/* Reports the failure of `what` on dev with the current errno. */
static int io_fail(const pc_v4l2 *dev, const char *what)
{
	int e = errno;
	char b[96];
	int code = errno_code(e);
	if (code == PC_EDISCONNECTED)
		return pc_error(code, "%s: %s: the device was disconnected (%s)", dev->info.path,
		                what, errtext(e, b, sizeof b));
	return pc_error(code, "%s: %s failed: %s", dev->info.path, what, errtext(e, b, sizeof b));
}

/* ioctl restarted on EINTR (a signal during a blocking call is not an error). */
static int xioctl(int fd, unsigned long request, void *arg)
{
	int r;
	do
		r = ioctl(fd, request, arg);
	while (r == -1 && errno == EINTR);
	return r;
}

static int64_t now_ms(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

/* Copies a fixed-size, possibly unterminated kernel string. */
static void copy_kstr(char *dst, size_t dst_size, const uint8_t *src, size_t src_size)
{
	size_t n = 0;
	while (n < src_size && n + 1 < dst_size && src[n])
		n++;
	memcpy(dst, src, n);
	dst[n] = '\0';
}

static void describe_caps(uint32_t caps, char *buf, size_t size)
{
	static const struct {
		uint32_t bit;
		const char *name;
	} names[] = {
	    {V4L2_CAP_VIDEO_CAPTURE, "video capture"},
	    {V4L2_CAP_VIDEO_OUTPUT, "video output"},
	    {V4L2_CAP_VIDEO_CAPTURE_MPLANE, "multi-planar capture"},
	    {V4L2_CAP_VIDEO_OUTPUT_MPLANE, "multi-planar output"},
	    {V4L2_CAP_VIDEO_M2M | V4L2_CAP_VIDEO_M2M_MPLANE, "memory-to-memory"},
	    {V4L2_CAP_META_CAPTURE, "metadata capture"},
	    {V4L2_CAP_META_OUTPUT, "metadata output"},
	    {V4L2_CAP_VBI_CAPTURE | V4L2_CAP_SLICED_VBI_CAPTURE, "VBI capture"},
	    {V4L2_CAP_VBI_OUTPUT | V4L2_CAP_SLICED_VBI_OUTPUT, "VBI output"},
	    {V4L2_CAP_RADIO, "radio"},
	    {V4L2_CAP_SDR_CAPTURE, "SDR capture"},
	    {V4L2_CAP_TOUCH, "touch"},
	};
	size_t used = 0;
	buf[0] = '\0';
	for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
		if (!(caps & names[i].bit))
			continue;
		int n = snprintf(buf + used, size - used, "%s%s", used ? ", " : "", names[i].name);
		if (n < 0 || (size_t)n >= size - used)
			break;
		used += (size_t)n;
	}
	if (!used)
		snprintf(buf, size, "nothing polarcam knows");
}

static void fill_info(pc_v4l2_info *info, const char *path, const struct v4l2_capability *cap)
{
	memset(info, 0, sizeof *info);
	snprintf(info->path, sizeof info->path, "%s", path);
	copy_kstr(info->driver, sizeof info->driver, cap->driver, sizeof cap->driver);
	copy_kstr(info->card, sizeof info->card, cap->card, sizeof cap->card);
	copy_kstr(info->bus_info, sizeof info->bus_info, cap->bus_info, sizeof cap->bus_info);
	info->version = cap->version;
	uint32_t c =
	    (cap->capabilities & V4L2_CAP_DEVICE_CAPS) ? cap->device_caps : cap->capabilities;
	info->device_caps = c;
	info->capture = (c & V4L2_CAP_VIDEO_CAPTURE) != 0;
	info->output = (c & V4L2_CAP_VIDEO_OUTPUT) != 0;
	info->capture_mplane = (c & V4L2_CAP_VIDEO_CAPTURE_MPLANE) != 0;
	info->output_mplane = (c & V4L2_CAP_VIDEO_OUTPUT_MPLANE) != 0;
	info->multiplanar = info->capture_mplane || info->output_mplane;
	info->metadata = (c & (V4L2_CAP_META_CAPTURE | V4L2_CAP_META_OUTPUT)) != 0;
	info->streaming = (c & V4L2_CAP_STREAMING) != 0;
	info->readwrite = (c & V4L2_CAP_READWRITE) != 0;
}

/* Opens a node and reads its capabilities; used by pc_v4l2_open and the listing. */
static int open_node(const char *path, int *fd_out, struct v4l2_capability *cap)
{
	char b[96];
	int fd;
	do
		fd = open(path, O_RDWR | O_NONBLOCK | O_CLOEXEC);
	while (fd < 0 && errno == EINTR);
	if (fd < 0) {
		int e = errno;
		switch (e) {
		case ENOENT:
			return pc_error(PC_ENOENT, "%s: no such device node", path);
		case EACCES:
		case EPERM:
			return pc_error(PC_EPERM,
			                "%s: permission denied (is the user in the 'video' "
			                "group?)",
			                path);
		case ENODEV:
		case ENXIO:
			return pc_error(PC_ENOENT, "%s: no device behind this node (%s)", path,
			                errtext(e, b, sizeof b));
		default:
			return pc_error(errno_code(e), "%s: cannot open: %s", path,
			                errtext(e, b, sizeof b));
		}
	}
	struct stat st;
	if (fstat(fd, &st) != 0 || !S_ISCHR(st.st_mode)) {
		close(fd);
		return pc_error(PC_EINVAL, "%s: not a character device, so not a V4L2 node", path);
	}
	memset(cap, 0, sizeof *cap);
	if (xioctl(fd, VIDIOC_QUERYCAP, cap) != 0) {
		int e = errno;
		close(fd);
		if (e == ENOTTY || e == EINVAL)
			return pc_error(PC_ENOTSUP, "%s: not a V4L2 device (VIDIOC_QUERYCAP: %s)",
			                path, errtext(e, b, sizeof b));
		return pc_error(errno_code(e), "%s: VIDIOC_QUERYCAP failed: %s", path,
		                errtext(e, b, sizeof b));
	}
	*fd_out = fd;
	return 0;
}

int pc_v4l2_open(const char *path, pc_v4l2_dir dir, pc_v4l2 **out)
{
	if (out)
		*out = NULL;
	if (!out || !path || !*path)
		return pc_error(PC_EINVAL, "v4l2: device path missing");
	if (dir != PC_V4L2_CAPTURE && dir != PC_V4L2_OUTPUT)
		return pc_error(PC_EINVAL, "v4l2: direction %d: expected capture or output",
		                (int)dir);
	if (strlen(path) >= sizeof((pc_v4l2_info *)0)->path)
		return pc_error(PC_EINVAL, "v4l2: device path too long (%zu characters)",
		                strlen(path));
	int fd;
	struct v4l2_capability cap;
	int rc = open_node(path, &fd, &cap);
	if (rc)
		return rc;
	pc_v4l2 *dev = calloc(1, sizeof *dev);
	if (!dev) {
		close(fd);
		return pc_error(PC_ENOMEM, "v4l2: out of memory");
	}
	dev->fd = fd;
	dev->dir = dir;
	fill_info(&dev->info, path, &cap);
	const pc_v4l2_info *in = &dev->info;
	bool single = dir == PC_V4L2_CAPTURE ? in->capture : in->output;
	bool multi = dir == PC_V4L2_CAPTURE ? in->capture_mplane : in->output_mplane;
	if (!(single || multi) || !in->streaming) {
		char offers[160];
		describe_caps(in->device_caps, offers, sizeof offers);
		const char *want = dir == PC_V4L2_CAPTURE ? "capture" : "output";
		if (!(single || multi))
			rc = pc_error(PC_ENOTSUP,
			              "%s (%s, '%s'): not a video %s node (it offers: %s)", path,
			              in->driver, in->card, want, offers);
		else
			rc = pc_error(PC_ENOTSUP, "%s (%s, '%s'): no streaming I/O (read() only)",
			              path, in->driver, in->card);
		close(fd);
		free(dev);
		return rc;
	}
	dev->mplane = !single;
	if (dir == PC_V4L2_CAPTURE)
		dev->type =
		    dev->mplane ? V4L2_BUF_TYPE_VIDEO_CAPTURE_MPLANE : V4L2_BUF_TYPE_VIDEO_CAPTURE;
	else
		dev->type =
		    dev->mplane ? V4L2_BUF_TYPE_VIDEO_OUTPUT_MPLANE : V4L2_BUF_TYPE_VIDEO_OUTPUT;
	*out = dev;
	return 0;
}

void pc_v4l2_close(pc_v4l2 *dev)
{
	if (!dev)
		return;
	pc_v4l2_stream_stop(dev);
	close(dev->fd);
	free(dev);
}

const pc_v4l2_info *pc_v4l2_get_info(const pc_v4l2 *dev)
{
	return dev ? &dev->info : NULL;
}

/* ---- formats ---- */

static int enum_formats_fd(int fd, uint32_t type, uint32_t *fourccs, size_t cap, size_t *count)
{
	size_t n = 0;
	for (uint32_t i = 0; i < 1024; i++) {
		struct v4l2_fmtdesc d;
		memset(&d, 0, sizeof d);
		d.index = i;
		d.type = type;
		if (xioctl(fd, VIDIOC_ENUM_FMT, &d) != 0) {
			if (errno == EINVAL)
				break;
			return -errno;
		}
		if (n < cap)
			fourccs[n] = d.pixelformat;
		n++;
	}
	*count = n;
	return 0;
}

int pc_v4l2_enum_formats(pc_v4l2 *dev, uint32_t *fourccs, size_t cap, size_t *count)
{
	if (!dev || !count || (cap && !fourccs))
		return pc_error(PC_EINVAL, "v4l2: enum_formats: missing argument");
	int rc = enum_formats_fd(dev->fd, dev->type, fourccs, cap, count);
	if (rc) {
		errno = -rc;
		return io_fail(dev, "VIDIOC_ENUM_FMT");
	}
	return 0;
}

int pc_v4l2_frame_sizes(pc_v4l2 *dev, uint32_t fourcc, pc_v4l2_size_range *out)
{
	if (!dev || !out)
		return pc_error(PC_EINVAL, "v4l2: frame_sizes: missing argument");
	char f4[5];
	struct v4l2_frmsizeenum fs;
	memset(&fs, 0, sizeof fs);
	fs.pixel_format = fourcc;
	if (xioctl(dev->fd, VIDIOC_ENUM_FRAMESIZES, &fs) != 0) {
		if (errno == ENOTTY || errno == EINVAL)
			return pc_error(PC_ENOTSUP,
			                "%s: the driver does not enumerate frame sizes for '%s'",
			                dev->info.path, pc_fourcc_str(fourcc, f4));
		return io_fail(dev, "VIDIOC_ENUM_FRAMESIZES");
	}
	memset(out, 0, sizeof *out);
	if (fs.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
		out->discrete = true;
		out->min_width = out->max_width = fs.discrete.width;
		out->min_height = out->max_height = fs.discrete.height;
		for (uint32_t i = 1; i < 4096; i++) {
			memset(&fs, 0, sizeof fs);
			fs.index = i;
			fs.pixel_format = fourcc;
			if (xioctl(dev->fd, VIDIOC_ENUM_FRAMESIZES, &fs) != 0 ||
			    fs.type != V4L2_FRMSIZE_TYPE_DISCRETE)
				break;
			if (fs.discrete.width < out->min_width)
				out->min_width = fs.discrete.width;
			if (fs.discrete.width > out->max_width)
				out->max_width = fs.discrete.width;
			if (fs.discrete.height < out->min_height)
				out->min_height = fs.discrete.height;
			if (fs.discrete.height > out->max_height)
				out->max_height = fs.discrete.height;
		}
		return 0;
	}
	out->min_width = fs.stepwise.min_width;
	out->max_width = fs.stepwise.max_width;
	out->min_height = fs.stepwise.min_height;
	out->max_height = fs.stepwise.max_height;
	bool cont = fs.type == V4L2_FRMSIZE_TYPE_CONTINUOUS;
	out->step_width = cont ? 1 : fs.stepwise.step_width;
	out->step_height = cont ? 1 : fs.stepwise.step_height;
	return 0;
}

static int fill_format(const pc_v4l2 *dev, const struct v4l2_format *f, pc_v4l2_format *got)
{
	uint32_t field;
	memset(got, 0, sizeof *got);
	if (dev->mplane) {
		const struct v4l2_pix_format_mplane *mp = &f->fmt.pix_mp;
		char f4[5];
		if (mp->num_planes != 1)
			return pc_error(PC_EFORMAT,
			                "%s: the driver stores '%s' in %u planes; polarcam "
			                "reads one-plane formats",
			                dev->info.path, pc_fourcc_str(mp->pixelformat, f4),
			                mp->num_planes);
		got->fourcc = mp->pixelformat;
		got->width = mp->width;
		got->height = mp->height;
		got->bytesperline = mp->plane_fmt[0].bytesperline;
		got->sizeimage = mp->plane_fmt[0].sizeimage;
		field = mp->field;
	} else {
		const struct v4l2_pix_format *p = &f->fmt.pix;
		got->fourcc = p->pixelformat;
		got->width = p->width;
		got->height = p->height;
		got->bytesperline = p->bytesperline;
		got->sizeimage = p->sizeimage;
		field = p->field;
	}
	got->format = pc_format_from_v4l2(got->fourcc);
	if (field != V4L2_FIELD_NONE && field != V4L2_FIELD_ANY)
		return pc_error(PC_ENOTSUP,
		                "%s: the driver delivers fields (V4L2 field %u); polarcam "
		                "needs progressive frames",
		                dev->info.path, field);
	/* Old drivers leave bytesperline 0 for packed-pixel formats: the table's row size is then
	 * the stride by definition (V4L2 spec, "Single-planar format structure"). */
	size_t row;
	if (got->format != PC_FMT_INVALID && got->bytesperline == 0 && got->width &&
	    pc_format_row_bytes(got->format, got->width, &row) == 0)
		got->bytesperline = row;
	return 0;
}

/* The driver's answer must describe a buffer polarcam can address with the table's row size. */
static int check_layout(const pc_v4l2 *dev, const pc_v4l2_format *g)
{
	char f4[5];
	if (g->format == PC_FMT_INVALID)
		return pc_error(PC_EFORMAT,
		                "%s: the driver chose pixel format '%s', which polarcam "
		                "cannot read",
		                dev->info.path, pc_fourcc_str(g->fourcc, f4));
	if (g->width == 0 || g->height == 0)
		return pc_error(PC_EFORMAT, "%s: the driver reports a %ux%u image", dev->info.path,
		                g->width, g->height);
	size_t row;
	int rc = pc_format_row_bytes(g->format, g->width, &row);
	if (rc)
		return pc_error_prefix(PC_EFORMAT, "%s: ", dev->info.path);
	if (g->bytesperline < row)
		return pc_error(PC_EFORMAT,
		                "%s: bytesperline %zu is less than the %zu bytes one "
		                "%u-pixel %s row needs",
		                dev->info.path, g->bytesperline, row, g->width,
		                pc_format_info_get(g->format)->name);
	if (g->bytesperline > SIZE_MAX / g->height)
		return pc_error(PC_EOVERFLOW, "%s: image size overflows", dev->info.path);
	size_t need = g->bytesperline * (g->height - 1) + row;
	if (g->sizeimage < need)
		return pc_error(PC_EFORMAT,
		                "%s: sizeimage %zu is less than the %zu bytes of %u rows of "
		                "%zu bytes",
		                dev->info.path, g->sizeimage, need, g->height, g->bytesperline);
	return 0;
}

static int do_format(pc_v4l2 *dev, unsigned long request, const char *name, uint32_t fourcc,
                     uint32_t width, uint32_t height, size_t bytesperline, pc_v4l2_format *got)
{
	if (!dev || !got)
		return pc_error(PC_EINVAL, "v4l2: %s: missing argument", name);
	if (bytesperline > UINT32_MAX)
		return pc_error(PC_ERANGE, "%s: bytesperline %zu too large", dev->info.path,
		                bytesperline);
	struct v4l2_format f;
	memset(&f, 0, sizeof f);
	f.type = dev->type;
	if (dev->mplane) {
		f.fmt.pix_mp.width = width;
		f.fmt.pix_mp.height = height;
		f.fmt.pix_mp.pixelformat = fourcc;
		f.fmt.pix_mp.field = V4L2_FIELD_NONE;
		f.fmt.pix_mp.num_planes = 1;
		f.fmt.pix_mp.plane_fmt[0].bytesperline = (uint32_t)bytesperline;
	} else {
		f.fmt.pix.width = width;
		f.fmt.pix.height = height;
		f.fmt.pix.pixelformat = fourcc;
		f.fmt.pix.field = V4L2_FIELD_NONE;
		f.fmt.pix.bytesperline = (uint32_t)bytesperline;
	}
	if (xioctl(dev->fd, request, &f) != 0) {
		char f4[5];
		if (errno == EINVAL)
			return pc_error(PC_EINVAL, "%s: %s rejected '%s' %ux%u", dev->info.path,
			                name, pc_fourcc_str(fourcc, f4), width, height);
		if (errno == EBUSY)
			return pc_error(PC_EBUSY,
			                "%s: %s: the node is busy (streaming, or buffers held "
			                "by another process)",
			                dev->info.path, name);
		return io_fail(dev, name);
	}
	return fill_format(dev, &f, got);
}

int pc_v4l2_try_format(pc_v4l2 *dev, uint32_t fourcc, uint32_t width, uint32_t height,
                       size_t bytesperline, pc_v4l2_format *got)
{
	return do_format(dev, VIDIOC_TRY_FMT, "VIDIOC_TRY_FMT", fourcc, width, height, bytesperline,
	                 got);
}

int pc_v4l2_set_format(pc_v4l2 *dev, uint32_t fourcc, uint32_t width, uint32_t height,
                       size_t bytesperline, pc_v4l2_format *got)
{
	if (dev && dev->streaming)
		return pc_error(PC_ESTATE, "%s: cannot change the format while streaming",
		                dev->info.path);
	pc_v4l2_format g;
	int rc =
	    do_format(dev, VIDIOC_S_FMT, "VIDIOC_S_FMT", fourcc, width, height, bytesperline, &g);
	if (rc)
		return rc;
	rc = check_layout(dev, &g);
	if (rc)
		return rc;
	dev->fmt = g;
	if (got)
		*got = g;
	return 0;
}

int pc_v4l2_get_format(pc_v4l2 *dev, pc_v4l2_format *got)
{
	if (!dev || !got)
		return pc_error(PC_EINVAL, "v4l2: get_format: missing argument");
	struct v4l2_format f;
	memset(&f, 0, sizeof f);
	f.type = dev->type;
	if (xioctl(dev->fd, VIDIOC_G_FMT, &f) != 0)
		return io_fail(dev, "VIDIOC_G_FMT");
	return fill_format(dev, &f, got);
}

/* ---- inputs, outputs, DV timings ---- */

static int input_count(pc_v4l2 *dev, unsigned *count)
{
	if (!dev || !count)
		return pc_error(PC_EINVAL, "v4l2: input_count: missing argument");
	unsigned n = 0;
	for (;; n++) {
		int r;
		if (dev->dir == PC_V4L2_CAPTURE) {
			struct v4l2_input in;
			memset(&in, 0, sizeof in);
			in.index = n;
			r = xioctl(dev->fd, VIDIOC_ENUMINPUT, &in);
		} else {
			struct v4l2_output o;
			memset(&o, 0, sizeof o);
			o.index = n;
			r = xioctl(dev->fd, VIDIOC_ENUMOUTPUT, &o);
		}
		if (r != 0) {
			if (errno == EINVAL || errno == ENOTTY)
				break;
			return io_fail(dev, "VIDIOC_ENUMINPUT/OUTPUT");
		}
		if (n > 256)
			break;
	}
	*count = n;
	return 0;
}

int pc_v4l2_select_io(pc_v4l2 *dev, unsigned index)
{
	if (!dev)
		return pc_error(PC_EINVAL, "v4l2: select_io: missing device");
	if (index > INT_MAX)
		return pc_error(PC_EINVAL, "v4l2: input index %u too large", index);
	int i = (int)index;
	bool cap = dev->dir == PC_V4L2_CAPTURE;
	if (xioctl(dev->fd, cap ? VIDIOC_S_INPUT : VIDIOC_S_OUTPUT, &i) != 0) {
		if (errno == EINVAL) {
			unsigned n = 0;
			input_count(dev, &n);
			return pc_error(PC_EINVAL, "%s: no %s %u (the node has %u)", dev->info.path,
			                cap ? "input" : "output", index, n);
		}
		if (errno == EBUSY)
			return pc_error(PC_EBUSY, "%s: cannot switch %s while streaming",
			                dev->info.path, cap ? "input" : "output");
		return io_fail(dev, cap ? "VIDIOC_S_INPUT" : "VIDIOC_S_OUTPUT");
	}
	return 0;
}

/* VESA Coordinated Video Timings standard 1.2 (2013), section 3.4 ("Reduced Blanking Timing
 * Parameters", version 2) and the reduced-blanking computation of section 5.4:
 *   horizontal blanking 80 px = front porch 8 + sync 32 + back porch 40;
 *   vertical sync 8 lines, back porch 6 lines, front porch >= 1 line;
 *   vertical blanking >= 460 us; pixel clock a multiple of 1 kHz.
 * The estimated line period is (1/refresh - 460 us) / active lines; the blanking gets
 * floor(460 us / period) + 1 lines. Sync polarities: H positive, V negative; a vertical sync
 * of 8 lines is how receivers recognise RB v2. */
int pc_dv_timings_cvt_rb2(uint32_t width, uint32_t height, double refresh_hz, pc_dv_timings *out)
{
	if (!out)
		return pc_error(PC_EINVAL, "cvt: missing output");
	if (width == 0 || width > 32768 || height == 0 || height > 32768)
		return pc_error(PC_EINVAL, "cvt: size %ux%u: expected 1..32768 in each direction",
		                width, height);
	const double min_vblank_us = 460.0;
	if (!(refresh_hz > 0.0) || !isfinite(refresh_hz) || 1e6 / refresh_hz <= min_vblank_us)
		return pc_error(PC_EINVAL,
		                "cvt: refresh %g Hz: expected > 0 and a frame period longer "
		                "than the 460 us minimum vertical blanking",
		                refresh_hz);
	const unsigned h_fp = 8, h_sync = 32, h_bp = 40;
	const unsigned v_sync = 8, v_bp = 6, v_fp_min = 1;
	double h_period_est_us = (1e6 / refresh_hz - min_vblank_us) / height;
	double vbi = floor(min_vblank_us / h_period_est_us) + 1.0;
	unsigned vbi_lines = vbi > 100000.0 ? 100000u : (unsigned)vbi;
	if (vbi_lines < v_fp_min + v_sync + v_bp)
		vbi_lines = v_fp_min + v_sync + v_bp;
	uint64_t total_v = (uint64_t)height + vbi_lines;
	uint64_t total_h = (uint64_t)width + h_fp + h_sync + h_bp;
	double khz = floor(refresh_hz * (double)total_v * (double)total_h / 1000.0);
	memset(out, 0, sizeof *out);
	out->width = width;
	out->height = height;
	out->interlaced = false;
	out->hsync_pos = true;
	out->vsync_pos = false;
	out->pixelclock_hz = (uint64_t)khz * 1000u;
	out->hfrontporch = h_fp;
	out->hsync = h_sync;
	out->hbackporch = h_bp;
	out->vfrontporch = vbi_lines - v_sync - v_bp;
	out->vsync = v_sync;
	out->vbackporch = v_bp;
	out->cvt = true;
	out->reduced_blanking = true;
	return 0;
}

double pc_dv_timings_fps(const pc_dv_timings *t)
{
	if (!t)
		return 0.0;
	double tw = (double)t->width + t->hfrontporch + t->hsync + t->hbackporch;
	double th = (double)t->height + t->vfrontporch + t->vsync + t->vbackporch;
	if (tw <= 0.0 || th <= 0.0)
		return 0.0;
	return (double)t->pixelclock_hz / (tw * th);
}

static void timings_to_kernel(const pc_dv_timings *t, struct v4l2_dv_timings *k)
{
	memset(k, 0, sizeof *k);
	k->type = V4L2_DV_BT_656_1120;
	struct v4l2_bt_timings *bt = &k->bt;
	bt->width = t->width;
	bt->height = t->height;
	bt->interlaced = t->interlaced ? V4L2_DV_INTERLACED : V4L2_DV_PROGRESSIVE;
	bt->polarities = (t->vsync_pos ? V4L2_DV_VSYNC_POS_POL : 0u) |
	                 (t->hsync_pos ? V4L2_DV_HSYNC_POS_POL : 0u);
	bt->pixelclock = t->pixelclock_hz;
	bt->hfrontporch = t->hfrontporch;
	bt->hsync = t->hsync;
	bt->hbackporch = t->hbackporch;
	bt->vfrontporch = t->vfrontporch;
	bt->vsync = t->vsync;
	bt->vbackporch = t->vbackporch;
	bt->standards = t->cvt ? V4L2_DV_BT_STD_CVT : 0u;
	bt->flags = t->reduced_blanking ? V4L2_DV_FL_REDUCED_BLANKING : 0u;
}

static void timings_from_kernel(const struct v4l2_dv_timings *k, pc_dv_timings *t)
{
	const struct v4l2_bt_timings *bt = &k->bt;
	memset(t, 0, sizeof *t);
	t->width = bt->width;
	t->height = bt->height;
	t->interlaced = bt->interlaced == V4L2_DV_INTERLACED;
	t->vsync_pos = (bt->polarities & V4L2_DV_VSYNC_POS_POL) != 0;
	t->hsync_pos = (bt->polarities & V4L2_DV_HSYNC_POS_POL) != 0;
	t->pixelclock_hz = bt->pixelclock;
	t->hfrontporch = bt->hfrontporch;
	t->hsync = bt->hsync;
	t->hbackporch = bt->hbackporch;
	t->vfrontporch = bt->vfrontporch;
	t->vsync = bt->vsync;
	t->vbackporch = bt->vbackporch;
	t->cvt = (bt->standards & V4L2_DV_BT_STD_CVT) != 0;
	t->reduced_blanking = (bt->flags & V4L2_DV_FL_REDUCED_BLANKING) != 0;
}

int pc_v4l2_get_dv_timings(pc_v4l2 *dev, pc_dv_timings *t)
{
	if (!dev || !t)
		return pc_error(PC_EINVAL, "v4l2: get_dv_timings: missing argument");
	struct v4l2_dv_timings k;
	memset(&k, 0, sizeof k);
	if (xioctl(dev->fd, VIDIOC_G_DV_TIMINGS, &k) != 0) {
		if (errno == ENODATA || errno == ENOTTY)
			return pc_error(PC_ENOTSUP,
			                "%s: the current %s has no DV timings (not a digital "
			                "video interface such as HDMI)",
			                dev->info.path,
			                dev->dir == PC_V4L2_CAPTURE ? "input" : "output");
		return io_fail(dev, "VIDIOC_G_DV_TIMINGS");
	}
	timings_from_kernel(&k, t);
	return 0;
}

int pc_v4l2_set_dv_timings(pc_v4l2 *dev, const pc_dv_timings *t)
{
	if (!dev || !t)
		return pc_error(PC_EINVAL, "v4l2: set_dv_timings: missing argument");
	struct v4l2_dv_timings k;
	timings_to_kernel(t, &k);
	if (xioctl(dev->fd, VIDIOC_S_DV_TIMINGS, &k) != 0) {
		if (errno == ENODATA || errno == ENOTTY)
			return pc_error(PC_ENOTSUP,
			                "%s: the current %s takes no DV timings (not a "
			                "digital video interface such as HDMI)",
			                dev->info.path,
			                dev->dir == PC_V4L2_CAPTURE ? "input" : "output");
		if (errno == EINVAL)
			return pc_error(PC_EINVAL,
			                "%s: the node rejected %ux%u timings (pixel clock %llu "
			                "Hz, %s)",
			                dev->info.path, t->width, t->height,
			                (unsigned long long)t->pixelclock_hz,
			                t->cvt ? "CVT" : "custom");
		if (errno == EBUSY)
			return pc_error(PC_EBUSY,
			                "%s: cannot change DV timings while buffers are "
			                "allocated",
			                dev->info.path);
		return io_fail(dev, "VIDIOC_S_DV_TIMINGS");
	}
	pc_dv_timings now;
	int rc = pc_v4l2_get_dv_timings(dev, &now);
	if (rc)
		return rc;
	if (now.width != t->width || now.height != t->height || now.interlaced != t->interlaced)
		return pc_error(PC_EINVAL, "%s: asked for %ux%u%s timings, the node kept %ux%u%s",
		                dev->info.path, t->width, t->height, t->interlaced ? "i" : "p",
		                now.width, now.height, now.interlaced ? "i" : "p");
	return 0;
}

/* ---- controls ---- */

static pc_v4l2_ctrl_type map_ctrl_type(uint32_t t)
{
	switch (t) {
	case V4L2_CTRL_TYPE_INTEGER:
		return PC_V4L2_CTRL_INTEGER;
	case V4L2_CTRL_TYPE_BOOLEAN:
		return PC_V4L2_CTRL_BOOLEAN;
	case V4L2_CTRL_TYPE_MENU:
	case V4L2_CTRL_TYPE_INTEGER_MENU:
		return PC_V4L2_CTRL_MENU;
	case V4L2_CTRL_TYPE_INTEGER64:
		return PC_V4L2_CTRL_INTEGER64;
	case V4L2_CTRL_TYPE_BUTTON:
		return PC_V4L2_CTRL_BUTTON;
	default:
		return PC_V4L2_CTRL_OTHER;
	}
}

static void fill_ctrl(const struct v4l2_query_ext_ctrl *q, pc_v4l2_ctrl *out)
{
	memset(out, 0, sizeof *out);
	out->id = q->id;
	copy_kstr(out->name, sizeof out->name, (const uint8_t *)q->name, sizeof q->name);
	out->type = map_ctrl_type(q->type);
	out->minimum = q->minimum;
	out->maximum = q->maximum;
	out->step = (int64_t)q->step;
	out->default_value = q->default_value;
	out->read_only = (q->flags & V4L2_CTRL_FLAG_READ_ONLY) != 0;
	out->inactive = (q->flags & V4L2_CTRL_FLAG_INACTIVE) != 0;
}

/* VIDIOC_QUERY_EXT_CTRL, with VIDIOC_QUERYCTRL for drivers older than Linux 3.17. */
static int query_ctrl_raw(pc_v4l2 *dev, uint32_t id, struct v4l2_query_ext_ctrl *q)
{
	memset(q, 0, sizeof *q);
	q->id = id;
	if (xioctl(dev->fd, VIDIOC_QUERY_EXT_CTRL, q) == 0)
		return 0;
	if (errno != ENOTTY)
		return -1;
	struct v4l2_queryctrl o;
	memset(&o, 0, sizeof o);
	o.id = id;
	if (xioctl(dev->fd, VIDIOC_QUERYCTRL, &o) != 0)
		return -1;
	memset(q, 0, sizeof *q);
	q->id = o.id;
	q->type = o.type;
	memcpy(q->name, o.name, sizeof o.name);
	q->minimum = o.minimum;
	q->maximum = o.maximum;
	q->step = (uint64_t)(o.step > 0 ? o.step : 1);
	q->default_value = o.default_value;
	q->flags = o.flags;
	return 0;
}

int pc_v4l2_ctrl_query(pc_v4l2 *dev, uint32_t id, pc_v4l2_ctrl *out)
{
	if (!dev || !out)
		return pc_error(PC_EINVAL, "v4l2: ctrl_query: missing argument");
	struct v4l2_query_ext_ctrl q;
	if (query_ctrl_raw(dev, id, &q) != 0) {
		if (errno == EINVAL)
			return pc_error(PC_ENOENT, "%s: no control 0x%08x", dev->info.path, id);
		return io_fail(dev, "VIDIOC_QUERY_EXT_CTRL");
	}
	if (q.flags & V4L2_CTRL_FLAG_DISABLED)
		return pc_error(PC_ENOENT, "%s: control 0x%08x is disabled", dev->info.path, id);
	fill_ctrl(&q, out);
	return 0;
}

int pc_v4l2_ctrl_find(pc_v4l2 *dev, const char *name, pc_v4l2_ctrl *out)
{
	if (!dev || !name || !out)
		return pc_error(PC_EINVAL, "v4l2: ctrl_find: missing argument");
	uint32_t id = 0;
	for (int guard = 0; guard < 4096; guard++) {
		struct v4l2_query_ext_ctrl q;
		if (query_ctrl_raw(dev,
		                   id | V4L2_CTRL_FLAG_NEXT_CTRL | V4L2_CTRL_FLAG_NEXT_COMPOUND,
		                   &q) != 0) {
			if (errno == EINVAL)
				break;
			return io_fail(dev, "VIDIOC_QUERY_EXT_CTRL");
		}
		id = q.id;
		if (q.type == V4L2_CTRL_TYPE_CTRL_CLASS || (q.flags & V4L2_CTRL_FLAG_DISABLED))
			continue;
		char qn[33];
		copy_kstr(qn, sizeof qn, (const uint8_t *)q.name, sizeof q.name);
		if (strcasecmp(qn, name) == 0) {
			fill_ctrl(&q, out);
			return 0;
		}
	}
	return pc_error(PC_ENOENT, "%s: no control named '%s'", dev->info.path, name);
}

int pc_v4l2_ctrl_set(pc_v4l2 *dev, uint32_t id, int64_t value)
{
	if (!dev)
		return pc_error(PC_EINVAL, "v4l2: ctrl_set: missing device");
	pc_v4l2_ctrl c;
	int rc = pc_v4l2_ctrl_query(dev, id, &c);
	if (rc)
		return rc;
	if (c.read_only)
		return pc_error(PC_EPERM, "%s: control '%s' is read-only", dev->info.path, c.name);
	if (c.type == PC_V4L2_CTRL_OTHER)
		return pc_error(PC_ENOTSUP, "%s: control '%s' is not a number", dev->info.path,
		                c.name);
	if (c.type != PC_V4L2_CTRL_BUTTON) {
		if (value < c.minimum || value > c.maximum)
			return pc_error(PC_ERANGE, "%s: control '%s' = %lld: outside [%lld, %lld]",
			                dev->info.path, c.name, (long long)value,
			                (long long)c.minimum, (long long)c.maximum);
		if (c.step > 1 && (value - c.minimum) % c.step != 0)
			return pc_error(PC_ERANGE,
			                "%s: control '%s' = %lld: not on the grid %lld + k*%lld",
			                dev->info.path, c.name, (long long)value,
			                (long long)c.minimum, (long long)c.step);
	}
	struct v4l2_ext_control ec;
	memset(&ec, 0, sizeof ec);
	ec.id = id;
	if (c.type == PC_V4L2_CTRL_INTEGER64)
		ec.value64 = value;
	else
		ec.value = (int32_t)value;
	struct v4l2_ext_controls ecs;
	memset(&ecs, 0, sizeof ecs);
	ecs.which = V4L2_CTRL_WHICH_CUR_VAL;
	ecs.count = 1;
	ecs.controls = &ec;
	if (xioctl(dev->fd, VIDIOC_S_EXT_CTRLS, &ecs) != 0) {
		if (errno == EBUSY)
			return pc_error(PC_EBUSY, "%s: control '%s' cannot change now (streaming?)",
			                dev->info.path, c.name);
		if (errno == EACCES)
			return pc_error(PC_EPERM, "%s: control '%s' is not writable now%s",
			                dev->info.path, c.name,
			                c.inactive ? " (inactive: an automatic "
			                             "mode controls it)"
			                           : "");
		if (errno == EINVAL || errno == ERANGE)
			return pc_error(PC_ERANGE, "%s: control '%s' rejected %lld", dev->info.path,
			                c.name, (long long)value);
		return io_fail(dev, "VIDIOC_S_EXT_CTRLS");
	}
	return 0;
}

int pc_v4l2_ctrl_get(pc_v4l2 *dev, uint32_t id, int64_t *value)
{
	if (!dev || !value)
		return pc_error(PC_EINVAL, "v4l2: ctrl_get: missing argument");
	pc_v4l2_ctrl c;
	int rc = pc_v4l2_ctrl_query(dev, id, &c);
	if (rc)
		return rc;
	if (c.type == PC_V4L2_CTRL_OTHER || c.type == PC_V4L2_CTRL_BUTTON)
		return pc_error(PC_ENOTSUP, "%s: control '%s' has no numeric value", dev->info.path,
		                c.name);
	struct v4l2_ext_control ec;
	memset(&ec, 0, sizeof ec);
	ec.id = id;
	struct v4l2_ext_controls ecs;
	memset(&ecs, 0, sizeof ecs);
	ecs.which = V4L2_CTRL_WHICH_CUR_VAL;
	ecs.count = 1;
	ecs.controls = &ec;
	if (xioctl(dev->fd, VIDIOC_G_EXT_CTRLS, &ecs) != 0)
		return io_fail(dev, "VIDIOC_G_EXT_CTRLS");
	*value = c.type == PC_V4L2_CTRL_INTEGER64 ? ec.value64 : ec.value;
	return 0;
}

int pc_v4l2_frame_rates(pc_v4l2 *dev, uint32_t fourcc, uint32_t width, uint32_t height,
                        pc_v4l2_rate_range *out)
{
	if (!dev || !out)
		return pc_error(PC_EINVAL, "v4l2: frame_rates: missing argument");
	memset(out, 0, sizeof *out);
	double rates[256];
	unsigned n = 0;
	for (uint32_t i = 0; i < 256; i++) {
		struct v4l2_frmivalenum fi;
		memset(&fi, 0, sizeof fi);
		fi.index = i;
		fi.pixel_format = fourcc;
		fi.width = width;
		fi.height = height;
		if (xioctl(dev->fd, VIDIOC_ENUM_FRAMEINTERVALS, &fi) != 0) {
			if (i == 0) {
				if (errno == EINVAL || errno == ENOTTY)
					return pc_error(PC_ENOTSUP,
					                "%s: the driver does not enumerate frame "
					                "intervals for %ux%u",
					                dev->info.path, width, height);
				return io_fail(dev, "VIDIOC_ENUM_FRAMEINTERVALS");
			}
			break;
		}
		if (fi.type != V4L2_FRMIVAL_TYPE_DISCRETE) {
			const struct v4l2_fract *lo = &fi.stepwise.min, *hi = &fi.stepwise.max;
			if (!lo->numerator || !hi->numerator || !lo->denominator ||
			    !hi->denominator)
				return pc_error(PC_EIO, "%s: malformed frame interval range",
				                dev->info.path);
			/* shortest interval = highest rate */
			out->max_fps = (double)lo->denominator / lo->numerator;
			out->min_fps = (double)hi->denominator / hi->numerator;
			out->step_fps = 0.0;
			out->discrete = false;
			return 0;
		}
		if (fi.discrete.numerator && fi.discrete.denominator)
			rates[n++] = (double)fi.discrete.denominator / fi.discrete.numerator;
	}
	if (n == 0)
		return pc_error(PC_EIO, "%s: the driver lists no usable frame interval",
		                dev->info.path);
	/* sort ascending (a handful of entries) */
	for (unsigned i = 1; i < n; i++)
		for (unsigned j = i; j > 0 && rates[j - 1] > rates[j]; j--) {
			double t = rates[j];
			rates[j] = rates[j - 1];
			rates[j - 1] = t;
		}
	out->discrete = true;
	out->count = n;
	out->min_fps = rates[0];
	out->max_fps = rates[n - 1];
	for (unsigned i = 1; i < n; i++)
		if (rates[i] - rates[i - 1] > out->step_fps)
			out->step_fps = rates[i] - rates[i - 1];
	return 0;
}

static int get_parm(pc_v4l2 *dev, struct v4l2_streamparm *p, struct v4l2_fract **tpf)
{
	memset(p, 0, sizeof *p);
	p->type = dev->type;
	if (xioctl(dev->fd, VIDIOC_G_PARM, p) != 0) {
		if (errno == ENOTTY || errno == EINVAL)
			return pc_error(PC_ENOTSUP, "%s: no frame-rate control (VIDIOC_G_PARM)",
			                dev->info.path);
		return io_fail(dev, "VIDIOC_G_PARM");
	}
	uint32_t capability =
	    dev->dir == PC_V4L2_CAPTURE ? p->parm.capture.capability : p->parm.output.capability;
	if (!(capability & V4L2_CAP_TIMEPERFRAME))
		return pc_error(PC_ENOTSUP, "%s: the frame rate is not settable on this %s",
		                dev->info.path, dev->dir == PC_V4L2_CAPTURE ? "input" : "output");
	*tpf = dev->dir == PC_V4L2_CAPTURE ? &p->parm.capture.timeperframe
	                                   : &p->parm.output.timeperframe;
	return 0;
}

int pc_v4l2_get_frame_rate(pc_v4l2 *dev, double *fps)
{
	if (!dev || !fps)
		return pc_error(PC_EINVAL, "v4l2: get_frame_rate: missing argument");
	struct v4l2_streamparm p;
	struct v4l2_fract *tpf;
	int rc = get_parm(dev, &p, &tpf);
	if (rc)
		return rc;
	if (tpf->numerator == 0 || tpf->denominator == 0)
		return pc_error(PC_EIO, "%s: the driver reports a frame interval of %u/%u s",
		                dev->info.path, tpf->numerator, tpf->denominator);
	*fps = (double)tpf->denominator / (double)tpf->numerator;
	return 0;
}

int pc_v4l2_set_frame_rate(pc_v4l2 *dev, double fps, double *actual_fps)
{
	if (!dev)
		return pc_error(PC_EINVAL, "v4l2: set_frame_rate: missing device");
	if (!(fps > 0.0) || !(fps <= 1e6))
		return pc_error(PC_ERANGE, "%s: frame rate %g: expected 0 < fps <= 1e6",
		                dev->info.path, fps);
	struct v4l2_streamparm p;
	struct v4l2_fract *tpf;
	int rc = get_parm(dev, &p, &tpf);
	if (rc)
		return rc;
	/* interval = 1000 / (1000 fps) s: exact for rates given to 1/1000 fps (29.97 -> 1000/29970)
	 */
	tpf->numerator = 1000;
	tpf->denominator = (uint32_t)llround(fps * 1000.0);
	if (xioctl(dev->fd, VIDIOC_S_PARM, &p) != 0) {
		if (errno == EBUSY)
			return pc_error(PC_EBUSY,
			                "%s: cannot change the frame rate while streaming",
			                dev->info.path);
		return io_fail(dev, "VIDIOC_S_PARM");
	}
	if (actual_fps)
		return pc_v4l2_get_frame_rate(dev, actual_fps);
	return 0;
}

/* ---- streaming ---- */

/* A v4l2_buffer with room for the planes of the multi-planar API. */
typedef struct vbuf {
	struct v4l2_buffer b;
	struct v4l2_plane planes[VIDEO_MAX_PLANES];
} vbuf;

static void vbuf_init(const pc_v4l2 *dev, vbuf *v, unsigned index)
{
	memset(v, 0, sizeof *v);
	v->b.type = dev->type;
	v->b.memory = V4L2_MEMORY_MMAP;
	v->b.index = index;
	if (dev->mplane) {
		v->b.m.planes = v->planes;
		v->b.length = VIDEO_MAX_PLANES;
	}
}

static size_t vbuf_length(const pc_v4l2 *dev, const vbuf *v)
{
	return dev->mplane ? v->planes[0].length : v->b.length;
}

static size_t vbuf_bytesused(const pc_v4l2 *dev, const vbuf *v)
{
	return dev->mplane ? v->planes[0].bytesused : v->b.bytesused;
}

static void release_buffers(pc_v4l2 *dev)
{
	for (unsigned i = 0; i < dev->nslots; i++)
		if (dev->slots[i].data && dev->slots[i].data != MAP_FAILED)
			munmap(dev->slots[i].data, dev->slots[i].length);
	free(dev->slots);
	dev->slots = NULL;
	dev->nslots = 0;
	dev->queued = 0;
	struct v4l2_requestbuffers rb;
	memset(&rb, 0, sizeof rb);
	rb.count = 0;
	rb.type = dev->type;
	rb.memory = V4L2_MEMORY_MMAP;
	xioctl(dev->fd, VIDIOC_REQBUFS,
	       &rb); /* may fail after a disconnect: nothing to free then */
}

int pc_v4l2_buffers_alloc(pc_v4l2 *dev, unsigned count, unsigned *granted)
{
	if (!dev)
		return pc_error(PC_EINVAL, "v4l2: buffers_alloc: missing device");
	if (dev->slots)
		return pc_error(PC_ESTATE, "%s: buffers are already allocated", dev->info.path);
	if (count < 1 || count > 64)
		return pc_error(PC_EINVAL, "%s: %u buffers: expected 1..64", dev->info.path, count);
	pc_v4l2_format g;
	int rc = pc_v4l2_get_format(dev, &g);
	if (!rc)
		rc = check_layout(dev, &g);
	if (rc)
		return rc;
	dev->fmt = g;
	struct v4l2_requestbuffers rb;
	memset(&rb, 0, sizeof rb);
	rb.count = count;
	rb.type = dev->type;
	rb.memory = V4L2_MEMORY_MMAP;
	if (xioctl(dev->fd, VIDIOC_REQBUFS, &rb) != 0) {
		if (errno == EINVAL)
			return pc_error(PC_ENOTSUP,
			                "%s: the driver offers no memory-mapped streaming",
			                dev->info.path);
		if (errno == EBUSY)
			return pc_error(PC_EBUSY,
			                "%s: buffers are held by another user of the node",
			                dev->info.path);
		return io_fail(dev, "VIDIOC_REQBUFS");
	}
	if (rb.count == 0) {
		release_buffers(dev);
		return pc_error(PC_ENOMEM, "%s: the driver granted no buffers", dev->info.path);
	}
	dev->slots = calloc(rb.count, sizeof *dev->slots);
	if (!dev->slots) {
		release_buffers(dev);
		return pc_error(PC_ENOMEM, "%s: out of memory", dev->info.path);
	}
	dev->nslots = rb.count;
	for (unsigned i = 0; i < rb.count; i++) {
		vbuf vb;
		vbuf_init(dev, &vb, i);
		if (xioctl(dev->fd, VIDIOC_QUERYBUF, &vb.b) != 0) {
			rc = io_fail(dev, "VIDIOC_QUERYBUF");
			break;
		}
		if (dev->mplane && vb.b.length != 1) {
			rc = pc_error(PC_EFORMAT, "%s: buffer %u has %u planes, polarcam reads one",
			              dev->info.path, i, vb.b.length);
			break;
		}
		size_t len = vbuf_length(dev, &vb);
		if (len < dev->fmt.sizeimage) {
			rc = pc_error(PC_EFORMAT,
			              "%s: buffer %u holds %zu bytes, the format needs %zu",
			              dev->info.path, i, len, dev->fmt.sizeimage);
			break;
		}
		off_t offset =
		    dev->mplane ? (off_t)vb.planes[0].m.mem_offset : (off_t)vb.b.m.offset;
		void *p = mmap(NULL, len, PROT_READ | PROT_WRITE, MAP_SHARED, dev->fd, offset);
		if (p == MAP_FAILED) {
			rc = io_fail(dev, "mmap");
			break;
		}
		dev->slots[i].data = p;
		dev->slots[i].length = len;
		dev->slots[i].fresh = dev->dir == PC_V4L2_OUTPUT;
	}
	if (rc) {
		release_buffers(dev);
		return rc;
	}
	if (granted)
		*granted = rb.count;
	return 0;
}

int pc_v4l2_buffer_memory(const pc_v4l2 *dev, unsigned index, void **data, size_t *length)
{
	if (!dev || !data || !length)
		return pc_error(PC_EINVAL, "v4l2: buffer_memory: missing argument");
	if (index >= dev->nslots)
		return pc_error(PC_EINVAL, "%s: buffer %u: only %u buffers exist", dev->info.path,
		                index, dev->nslots);
	*data = dev->slots[index].data;
	*length = dev->slots[index].length;
	return 0;
}

int pc_v4l2_stream_on(pc_v4l2 *dev)
{
	if (!dev)
		return pc_error(PC_EINVAL, "v4l2: stream_on: missing device");
	if (!dev->slots)
		return pc_error(PC_ESTATE, "%s: stream_on without buffers", dev->info.path);
	if (dev->streaming)
		return pc_error(PC_ESTATE, "%s: already streaming", dev->info.path);
	int type = (int)dev->type;
	if (xioctl(dev->fd, VIDIOC_STREAMON, &type) != 0)
		return io_fail(dev, "VIDIOC_STREAMON");
	dev->streaming = true;
	return 0;
}

int pc_v4l2_stream_off(pc_v4l2 *dev)
{
	if (!dev)
		return pc_error(PC_EINVAL, "v4l2: stream_off: missing device");
	int rc = 0;
	if (dev->streaming || dev->queued) {
		int type = (int)dev->type;
		/* STREAMOFF also takes back buffers queued before STREAMON */
		if (xioctl(dev->fd, VIDIOC_STREAMOFF, &type) != 0 && errno != ENODEV)
			rc = io_fail(dev, "VIDIOC_STREAMOFF");
	}
	dev->streaming = false;
	for (unsigned i = 0; i < dev->nslots; i++) {
		if (dev->slots[i].queued && dev->dir == PC_V4L2_OUTPUT)
			dev->slots[i].fresh = true;
		dev->slots[i].queued = false;
	}
	dev->queued = 0;
	return rc;
}

int pc_v4l2_buffers_free(pc_v4l2 *dev)
{
	if (!dev)
		return pc_error(PC_EINVAL, "v4l2: buffers_free: missing device");
	if (dev->streaming)
		return pc_error(PC_ESTATE, "%s: buffers_free while streaming", dev->info.path);
	if (dev->slots)
		release_buffers(dev);
	return 0;
}

static int qbuf(pc_v4l2 *dev, unsigned index, size_t bytesused)
{
	vbuf vb;
	vbuf_init(dev, &vb, index);
	if (dev->mplane)
		vb.b.length = 1;
	if (dev->dir == PC_V4L2_OUTPUT) {
		if (dev->mplane) {
			vb.planes[0].bytesused = (uint32_t)bytesused;
			vb.planes[0].length = (uint32_t)dev->slots[index].length;
		} else {
			vb.b.bytesused = (uint32_t)bytesused;
		}
		vb.b.field = V4L2_FIELD_NONE;
	}
	if (xioctl(dev->fd, VIDIOC_QBUF, &vb.b) != 0)
		return io_fail(dev, "VIDIOC_QBUF");
	dev->slots[index].queued = true;
	dev->slots[index].fresh = false;
	dev->queued++;
	return 0;
}

int pc_v4l2_stream_start(pc_v4l2 *dev, unsigned nbuf)
{
	if (!dev)
		return pc_error(PC_EINVAL, "v4l2: stream_start: missing device");
	if (dev->streaming || dev->slots)
		return pc_error(PC_ESTATE, "%s: already streaming", dev->info.path);
	int rc = pc_v4l2_buffers_alloc(dev, nbuf, NULL);
	if (rc)
		return rc;
	if (dev->dir == PC_V4L2_CAPTURE)
		for (unsigned i = 0; !rc && i < dev->nslots; i++)
			rc = qbuf(dev, i, 0);
	if (!rc)
		rc = pc_v4l2_stream_on(dev);
	if (rc) {
		pc_v4l2_stream_off(dev);
		release_buffers(dev);
	}
	return rc;
}

unsigned pc_v4l2_buffer_count(const pc_v4l2 *dev)
{
	return dev ? dev->nslots : 0;
}

static int fill_buffer(pc_v4l2 *dev, const vbuf *v, pc_v4l2_buffer *b)
{
	const struct v4l2_buffer *vb = &v->b;
	if (vb->index >= dev->nslots || !dev->slots[vb->index].queued)
		return pc_error(PC_EIO, "%s: the driver returned buffer %u, which was not queued",
		                dev->info.path, vb->index);
	pc_v4l2_slot *s = &dev->slots[vb->index];
	s->queued = false;
	dev->queued--;
	memset(b, 0, sizeof *b);
	b->index = vb->index;
	b->data = s->data;
	b->length = s->length;
	b->bytesused = vbuf_bytesused(dev, v);
	b->sequence = vb->sequence;
	b->timestamp_ns =
	    (uint64_t)vb->timestamp.tv_sec * 1000000000u + (uint64_t)vb->timestamp.tv_usec * 1000u;
	b->error = (vb->flags & V4L2_BUF_FLAG_ERROR) != 0;
	b->timestamp_monotonic =
	    (vb->flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
	if (dev->dir == PC_V4L2_CAPTURE && b->bytesused > b->length)
		return pc_error(PC_EIO, "%s: buffer %u: bytesused %zu exceeds its %zu bytes",
		                dev->info.path, vb->index, b->bytesused, b->length);
	return 0;
}

/* Nothing is queued, so nothing can arrive: wait out the timeout (restarting after signals). */
static int starve(const pc_v4l2 *dev, int timeout_ms)
{
	if (timeout_ms < 0)
		return pc_error(PC_ESTATE, "%s: no buffer is queued, so none can ever be dequeued",
		                dev->info.path);
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	t.tv_sec += timeout_ms / 1000;
	t.tv_nsec += (long)(timeout_ms % 1000) * 1000000L;
	if (t.tv_nsec >= 1000000000L) {
		t.tv_sec++;
		t.tv_nsec -= 1000000000L;
	}
	while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &t, NULL) == EINTR)
		;
	return pc_error(PC_ETIMEDOUT, "%s: no %s within %d ms (no buffer was queued)",
	                dev->info.path, dev->dir == PC_V4L2_CAPTURE ? "frame" : "free buffer",
	                timeout_ms);
}

int pc_v4l2_dequeue(pc_v4l2 *dev, int timeout_ms, pc_v4l2_buffer *buf)
{
	if (!dev || !buf)
		return pc_error(PC_EINVAL, "v4l2: dequeue: missing argument");
	if (!dev->streaming)
		return pc_error(PC_ESTATE, "%s: dequeue while not streaming", dev->info.path);
	if (dev->queued == 0)
		return starve(dev, timeout_ms);
	int64_t deadline = timeout_ms >= 0 ? now_ms() + timeout_ms : -1;
	for (;;) {
		vbuf vb;
		vbuf_init(dev, &vb, 0);
		if (xioctl(dev->fd, VIDIOC_DQBUF, &vb.b) == 0)
			return fill_buffer(dev, &vb, buf);
		if (errno == EIO)
			return pc_error(PC_EIO,
			                "%s: VIDIOC_DQBUF: the driver reports a fatal streaming "
			                "error",
			                dev->info.path);
		if (errno != EAGAIN)
			return io_fail(dev, "VIDIOC_DQBUF");
		int wait = -1;
		if (deadline >= 0) {
			int64_t left = deadline - now_ms();
			if (left <= 0)
				return pc_error(
				    PC_ETIMEDOUT, "%s: no %s within %d ms", dev->info.path,
				    dev->dir == PC_V4L2_CAPTURE ? "frame" : "free buffer",
				    timeout_ms);
			wait = left > INT_MAX ? INT_MAX : (int)left;
		}
		struct pollfd p = {.fd = dev->fd,
		                   .events = dev->dir == PC_V4L2_CAPTURE ? POLLIN : POLLOUT};
		int r = poll(&p, 1, wait);
		if (r < 0) {
			if (errno == EINTR)
				continue; /* deadline re-checked above */
			return io_fail(dev, "poll");
		}
		if (r > 0 && (p.revents & (POLLERR | POLLHUP | POLLNVAL))) {
			vbuf_init(dev, &vb, 0);
			if (xioctl(dev->fd, VIDIOC_DQBUF, &vb.b) == 0)
				return fill_buffer(dev, &vb, buf);
			if (errno == EAGAIN)
				return pc_error(PC_EIO,
				                "%s: the driver signals an error (poll revents "
				                "0x%x)",
				                dev->info.path, (unsigned)p.revents);
			if (errno == EIO)
				return pc_error(PC_EIO,
				                "%s: VIDIOC_DQBUF: the driver reports a fatal "
				                "streaming error",
				                dev->info.path);
			return io_fail(dev, "VIDIOC_DQBUF");
		}
	}
}

int pc_v4l2_queue(pc_v4l2 *dev, unsigned index, size_t bytesused)
{
	if (!dev)
		return pc_error(PC_EINVAL, "v4l2: queue: missing device");
	if (!dev->slots)
		return pc_error(PC_ESTATE, "%s: queue without buffers", dev->info.path);
	if (index >= dev->nslots)
		return pc_error(PC_EINVAL, "%s: buffer %u: only %u buffers exist", dev->info.path,
		                index, dev->nslots);
	if (dev->slots[index].queued)
		return pc_error(PC_ESTATE, "%s: buffer %u is already queued", dev->info.path,
		                index);
	if (dev->dir == PC_V4L2_OUTPUT) {
		if (bytesused == 0)
			bytesused = dev->fmt.sizeimage;
		if (bytesused > dev->slots[index].length)
			return pc_error(PC_ERANGE,
			                "%s: bytesused %zu exceeds buffer %u's %zu bytes",
			                dev->info.path, bytesused, index, dev->slots[index].length);
	}
	return qbuf(dev, index, bytesused);
}

int pc_v4l2_output_acquire(pc_v4l2 *dev, int timeout_ms, pc_v4l2_buffer *buf)
{
	if (!dev || !buf)
		return pc_error(PC_EINVAL, "v4l2: output_acquire: missing argument");
	if (dev->dir != PC_V4L2_OUTPUT)
		return pc_error(PC_EINVAL, "%s: output_acquire on a capture node", dev->info.path);
	if (!dev->slots)
		return pc_error(PC_ESTATE, "%s: output_acquire without buffers", dev->info.path);
	for (unsigned i = 0; i < dev->nslots; i++) {
		pc_v4l2_slot *s = &dev->slots[i];
		if (s->fresh) {
			s->fresh = false;
			memset(buf, 0, sizeof *buf);
			buf->index = i;
			buf->data = s->data;
			buf->length = s->length;
			return 0;
		}
	}
	return pc_v4l2_dequeue(dev, timeout_ms, buf);
}

int pc_v4l2_stream_stop(pc_v4l2 *dev)
{
	if (!dev)
		return pc_error(PC_EINVAL, "v4l2: stream_stop: missing device");
	int rc = pc_v4l2_stream_off(dev);
	if (dev->slots)
		release_buffers(dev);
	return rc;
}

/* ---- listing ---- */

static int cmp_unsigned(const void *a, const void *b)
{
	unsigned x = *(const unsigned *)a, y = *(const unsigned *)b;
	return (x > y) - (x < y);
}

/* "video12" -> 12; false for anything else ("video", "video1a", "vide0"). */
static bool parse_video_name(const char *name, unsigned *n)
{
	if (strncmp(name, "video", 5) != 0 || !name[5])
		return false;
	unsigned long v = 0;
	for (const char *p = name + 5; *p; p++) {
		if (*p < '0' || *p > '9')
			return false;
		v = v * 10 + (unsigned long)(*p - '0');
		if (v > 1000000)
			return false;
	}
	*n = (unsigned)v;
	return true;
}

static void query_listed_node(pc_v4l2_node *node)
{
	int fd;
	struct v4l2_capability cap;
	int rc = open_node(node->info.path, &fd, &cap);
	if (rc) {
		node->error = rc;
		snprintf(node->error_detail, sizeof node->error_detail, "%s", pc_error_detail());
		return;
	}
	char path[sizeof node->info.path];
	memcpy(path, node->info.path, sizeof path);
	fill_info(&node->info, path, &cap);
	uint32_t type = 0;
	uint32_t c = node->info.device_caps;
	if (c & V4L2_CAP_VIDEO_CAPTURE)
		type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
	else if (c & V4L2_CAP_VIDEO_CAPTURE_MPLANE)
		type = V4L2_BUF_TYPE_VIDEO_CAPTURE_MPLANE;
	else if (c & V4L2_CAP_VIDEO_OUTPUT)
		type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
	else if (c & V4L2_CAP_VIDEO_OUTPUT_MPLANE)
		type = V4L2_BUF_TYPE_VIDEO_OUTPUT_MPLANE;
	if (type) {
		size_t n = 0;
		if (enum_formats_fd(fd, type, node->fourccs, PC_V4L2_LIST_MAX_FORMATS, &n) == 0) {
			node->nformats =
			    n < PC_V4L2_LIST_MAX_FORMATS ? n : PC_V4L2_LIST_MAX_FORMATS;
			node->nformats_total = n;
		}
	}
	close(fd);
}

int pc_v4l2_list(const char *dev_dir, pc_v4l2_node **nodes, size_t *count)
{
	if (!nodes || !count)
		return pc_error(PC_EINVAL, "v4l2: list: missing argument");
	*nodes = NULL;
	*count = 0;
	const char *dir = dev_dir ? dev_dir : "/dev";
	DIR *d = opendir(dir);
	if (!d) {
		if (errno == ENOENT || errno == ENOTDIR)
			return 0;
		char b[96];
		return pc_error(errno_code(errno), "%s: cannot list: %s", dir,
		                errtext(errno, b, sizeof b));
	}
	unsigned *nums = NULL;
	size_t n = 0, cap = 0;
	struct dirent *e;
	while ((e = readdir(d)) != NULL) {
		unsigned k;
		if (!parse_video_name(e->d_name, &k))
			continue;
		if (n == cap) {
			size_t nc = cap ? cap * 2 : 16;
			unsigned *nn = realloc(nums, nc * sizeof *nn);
			if (!nn) {
				free(nums);
				closedir(d);
				return pc_error(PC_ENOMEM, "v4l2: list: out of memory");
			}
			nums = nn;
			cap = nc;
		}
		nums[n++] = k;
	}
	closedir(d);
	if (n == 0) {
		free(nums);
		return 0;
	}
	qsort(nums, n, sizeof *nums, cmp_unsigned);
	pc_v4l2_node *out = calloc(n, sizeof *out);
	if (!out) {
		free(nums);
		return pc_error(PC_ENOMEM, "v4l2: list: out of memory");
	}
	for (size_t i = 0; i < n; i++) {
		snprintf(out[i].info.path, sizeof out[i].info.path, "%s/video%u", dir, nums[i]);
		query_listed_node(&out[i]);
	}
	free(nums);
	*nodes = out;
	*count = n;
	return 0;
}
