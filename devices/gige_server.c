/* The GigE Vision camera of `polarcam serve` (polarcam/gige_server.h). */
#include "polarcam/gige_server.h"

#include <arv.h>
#include <assert.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "backend_util.h"
#include "polarcam/camera_profile.h"
#include "polarcam/error.h"
#include "polarcam/source.h"

/* Registers of Aravis's fake camera model (arvfakecamera.h) and two of ours for ReverseX/Y, in
 * the model's free register space. */
#define REG_REVERSE_X 0xf000u
#define REG_REVERSE_Y 0xf004u
/* and two read-only ones: the sensor's black level (IEEE float, DN at the sensor's bit depth)
 * and its ADC bit depth (SFNC AdcBitDepth: BitsN has the value N) */
#define REG_BLACK_LEVEL 0xf008u
#define REG_ADC_BITS    0xf00cu
/* GigE Vision bootstrap registers (GigE Vision specification, bootstrap register map):
 * manufacturer name 0x0048 (32 bytes), model name 0x0068 (32), manufacturer info 0x00A8 (48). */
#define GVBS_MANUFACTURER 0x0048u
#define GVBS_MODEL        0x0068u
#define GVBS_INFO         0x00a8u

/* The pixel formats the camera offers, by GenICam name, with their enumeration values (0: the
 * value in pc_genicam_formats). A monochrome-polarization source is served as a LUCID-style
 * camera. A colour-polarization source (IMX250MYR mosaic) is served with FLIR's
 * BayerRGPolarized names; their values live in each camera's description, and ours reuse
 * LUCID's PolarizeMono values of the same size on purpose (0x81100007 is also Aravis's
 * CUSTOM_BAYER_RG_16): a client that went by value instead of name would see a monochrome or a
 * plain Bayer camera. */
typedef struct served_name {
	const char *name;
	uint32_t code;
} served_name;
static const served_name served_mono[] = {
    {"PolarizeMono8", 0},  {"PolarizeMono12", 0}, {"PolarizeMono12p", 0},
    {"PolarizeMono16", 0}, {"Mono8", 0},          {"Mono10", 0},
    {"Mono12", 0},         {"Mono12p", 0},        {"Mono16", 0},
};
static const served_name served_colour[] = {
    {"BayerRGPolarized8", 0x81080001u},
    {"BayerRGPolarized10p", 0x810A0046u},
    {"BayerRGPolarized12p", 0x810C0047u},
    {"BayerRGPolarized16", 0x81100007u},
};
#define N_SERVED (sizeof served_mono / sizeof served_mono[0])
/* fmts[] holds either list: the colour list must not be the longer one */
_Static_assert(sizeof served_colour / sizeof served_colour[0] <= N_SERVED,
               "served_colour longer than fmts[]");
/* GigE Vision model names; polarcam/camera_profile.h holds what clients learn from them */
#define MODEL_MONO   "polarcam-sim"
#define MODEL_COLOUR "polarcam-sim-colour"

typedef struct served_fmt {
	const char *name;
	uint32_t code;
	pc_pixfmt fmt;
} served_fmt;

struct pc_gige_server {
	ArvGvFakeCamera *gv;
	ArvFakeCamera *fc;
	char *xml;
	char xml_path[4096];
	served_fmt fmts[N_SERVED];
	unsigned n_fmts;
	pc_source *src;
	pc_source_format sfmt; /* the source's full frame */
	unsigned bits;
	bool colour; /* the source's mosaic is colour-polarization */
	unsigned ahead;
	GThread *thread;
	GMutex lock;
	GCond cond;
	bool quit;
	int error;
	char errmsg[256];
	/* frames ready for the camera, and consumed frames for the producer to requeue */
	pc_buffer *ready[64];
	unsigned r_head, r_count;
	pc_buffer *done[64];
	unsigned d_count;
	bool restart; /* the producer must restart the source at frame 0 */
	uint64_t gen; /* acquisition generation: frames rendered for an older one are dropped */
	bool fresh;   /* the source is at frame 0 and nothing was served since */
	/* cycle mode */
	pc_view *cyc;
	unsigned n_cyc;
	uint64_t k; /* frames served in this acquisition */
	double exposure_applied, gain_applied;
	uint16_t *row16; /* callback thread only */
	pc_gige_server_stats st;
};

/* ---- the GenICam description: Aravis's fake camera's, with our formats and ReverseX/Y ---- */

static char *make_xml(pc_gige_server *srv)
{
	ArvFakeCamera *tmp = arv_fake_camera_new("POLARCAMXML");
	if (!tmp)
		return NULL;
	size_t n = 0;
	const char *base = arv_fake_camera_get_genicam_xml(tmp, &n);
	char *in = base ? g_strndup(base, n) : NULL;
	g_object_unref(tmp);
	if (!in)
		return NULL;
	char *enum_start = strstr(in, "<Enumeration Name=\"PixelFormat\"");
	char *first = enum_start ? strstr(enum_start, "<EnumEntry") : NULL;
	char *pvalue =
	    enum_start ? strstr(enum_start, "<pValue>PixelFormatRegister</pValue>") : NULL;
	char *port = strstr(in, "<Port Name=\"Device\"");
	if (!first || !pvalue || pvalue < first || !port || port < pvalue) {
		g_free(in);
		return NULL;
	}
	GString *out = g_string_new_len(in, first - in);
	for (unsigned i = 0; i < srv->n_fmts; i++)
		g_string_append_printf(out,
		                       "<EnumEntry Name=\"%s\" NameSpace=\"%s\">\n"
		                       "\t\t\t<Value>%u</Value>\n\t\t</EnumEntry>\n\t\t",
		                       srv->fmts[i].name,
		                       srv->fmts[i].code >> 31 ? "Custom" : "Standard",
		                       srv->fmts[i].code);
	g_string_append_len(out, pvalue, port - pvalue);
	static const char *const rev[2] = {"ReverseX", "ReverseY"};
	for (int i = 0; i < 2; i++)
		g_string_append_printf(
		    out,
		    "<Boolean Name=\"%s\" NameSpace=\"Standard\">\n"
		    "\t\t<Description>Mirror the readout (polarcam: mirrors the "
		    "mosaic)</Description>\n"
		    "\t\t<pValue>%sRegister</pValue>\n\t\t<OnValue>1</OnValue>\n"
		    "\t\t<OffValue>0</OffValue>\n\t</Boolean>\n\n"
		    "\t<IntReg Name=\"%sRegister\" NameSpace=\"Custom\">\n"
		    "\t\t<Address>0x%x</Address>\n\t\t<Length>4</Length>\n"
		    "\t\t<AccessMode>RW</AccessMode>\n\t\t<pPort>Device</pPort>\n"
		    "\t\t<Sign>Unsigned</Sign>\n\t\t<Endianess>BigEndian</Endianess>\n"
		    "\t</IntReg>\n\n\t",
		    rev[i], rev[i], rev[i], i ? REG_REVERSE_Y : REG_REVERSE_X);
	/* SFNC BlackLevel (Analog Control) and AdcBitDepth (Image Format Control): the source's
	 * declared black level, so that clients subtract it without being told
	 * (docs/calibration.md, "Black level") */
	g_string_append_printf(
	    out,
	    "<Float Name=\"BlackLevel\" NameSpace=\"Standard\">\n"
	    "\t\t<Description>Black level (offset) of the sensor's samples, DN at AdcBitDepth "
	    "(polarcam: the source's declared offset)</Description>\n"
	    "\t\t<pValue>BlackLevelRegister</pValue>\n\t\t<Unit>DN</Unit>\n\t</Float>\n\n"
	    "\t<FloatReg Name=\"BlackLevelRegister\" NameSpace=\"Custom\">\n"
	    "\t\t<Address>0x%x</Address>\n\t\t<Length>4</Length>\n"
	    "\t\t<AccessMode>RO</AccessMode>\n\t\t<pPort>Device</pPort>\n"
	    "\t\t<Endianess>BigEndian</Endianess>\n\t</FloatReg>\n\n\t"
	    "<Enumeration Name=\"AdcBitDepth\" NameSpace=\"Standard\">\n"
	    "\t\t<Description>Bit depth of the sensor's samples</Description>\n",
	    REG_BLACK_LEVEL);
	static const unsigned adc[] = {8, 10, 12, 14, 16};
	for (unsigned i = 0; i < sizeof adc / sizeof adc[0]; i++)
		g_string_append_printf(out,
		                       "\t\t<EnumEntry Name=\"Bits%u\" NameSpace=\"Standard\">\n"
		                       "\t\t\t<Value>%u</Value>\n\t\t</EnumEntry>\n",
		                       adc[i], adc[i]);
	g_string_append_printf(out,
	                       "\t\t<pValue>AdcBitDepthRegister</pValue>\n\t</Enumeration>\n\n"
	                       "\t<IntReg Name=\"AdcBitDepthRegister\" NameSpace=\"Custom\">\n"
	                       "\t\t<Address>0x%x</Address>\n\t\t<Length>4</Length>\n"
	                       "\t\t<AccessMode>RO</AccessMode>\n\t\t<pPort>Device</pPort>\n"
	                       "\t\t<Sign>Unsigned</Sign>\n\t\t<Endianess>BigEndian</Endianess>\n"
	                       "\t</IntReg>\n\n\t",
	                       REG_ADC_BITS);
	g_string_append(out, port);
	g_free(in);
	return g_string_free(out, FALSE);
}

static const served_fmt *served_by_code(const pc_gige_server *srv, uint32_t code)
{
	for (unsigned i = 0; i < srv->n_fmts; i++)
		if (srv->fmts[i].code == code)
			return &srv->fmts[i];
	return NULL;
}

/* ---- the camera's image callback (Aravis's camera thread) ---- */

static uint32_t reg(ArvFakeCamera *fc, uint32_t addr)
{
	guint32 v = 0;
	arv_fake_camera_read_register(fc, addr, &v);
	return v;
}

/* Copies the ROI of the full frame src into the camera buffer, mirrored and packed. */
static void render_roi(pc_gige_server *srv, const pc_view *src, ArvBuffer *buffer,
                       const served_fmt *sf)
{
	uint32_t w = (uint32_t)arv_buffer_get_image_width(buffer);
	uint32_t h = (uint32_t)arv_buffer_get_image_height(buffer);
	uint32_t ox = reg(srv->fc, ARV_FAKE_CAMERA_REGISTER_X_OFFSET);
	uint32_t oy = reg(srv->fc, ARV_FAKE_CAMERA_REGISTER_Y_OFFSET);
	bool rx = reg(srv->fc, REG_REVERSE_X) != 0, ry = reg(srv->fc, REG_REVERSE_Y) != 0;
	if (w == 0 || h == 0 || ox > src->width || oy > src->height || w > src->width - ox ||
	    h > src->height - oy)
		return; /* the model refused such a region already; nothing sensible to send */
	const pc_format_info *di = pc_format_info_get(sf->fmt);
	size_t row;
	if (pc_format_row_bytes(sf->fmt, w, &row))
		return;
	/* the callback's buffer is the one the camera sends (Aravis's API hands it as const) */
	uint8_t *data = (uint8_t *)arv_buffer_get_data(buffer, NULL);
	unsigned shift = di->bits < srv->bits ? srv->bits - di->bits : 0;
	bool same = !rx && shift == 0 && di->packing == PC_PACK_NONE &&
	            pc_format_info_get(src->format)->group_bytes == di->group_bytes;
	for (uint32_t y = 0; y < h; y++) {
		uint32_t sy = ry ? src->height - 1 - (oy + y) : oy + y;
		const uint16_t *srow = PC_ROW(src, const uint16_t, sy);
		uint8_t *drow = data + (size_t)y * row;
		if (same) {
			memcpy(drow, srow + ox, row);
			continue;
		}
		for (uint32_t x = 0; x < w; x++) {
			uint32_t sx = rx ? src->width - 1 - (ox + x) : ox + x;
			srv->row16[x] = (uint16_t)(srow[sx] >> shift);
		}
		pc_view d = {drow, w, 1, row, sf->fmt};
		(void)pc_view_from_u16(srv->row16, (size_t)w * 2, &d);
	}
}

/* A new acquisition starts at the source's frame 0: frames rendered ahead for the previous one
 * go back, the producer restarts the source, and a frame it is rendering for the previous one
 * is dropped when it arrives (gen). Nothing happens while the source is still at frame 0
 * (fresh), so the two detectors below never restart it twice. Lock held. */
static void new_acquisition_locked(pc_gige_server *srv)
{
	if (srv->fresh)
		return;
	while (srv->r_count) {
		srv->done[srv->d_count++] = srv->ready[srv->r_head];
		srv->r_head = (srv->r_head + 1) % 64;
		srv->r_count--;
	}
	srv->k = 0;
	srv->restart = !srv->n_cyc;
	srv->gen++;
	srv->fresh = true;
	g_cond_broadcast(&srv->cond);
}

/* Aravis's GigE Vision camera thread (arvgvfakecamera.c, 0.8) handles one control packet at a
 * time and, after each, drops its ArvBuffer when the acquisition register reads 0; the next
 * AcquisitionStart creates a new ArvBuffer that it fills frame after frame. A buffer without
 * our mark is therefore the first frame of a new acquisition, however quickly a client stopped
 * and restarted (the register poll in the producer misses a stop shorter than its period). */
static bool first_of_acquisition(ArvBuffer *buffer)
{
	GQuark q = g_quark_from_static_string("polarcam-serve-acquisition");
	if (g_object_get_qdata(G_OBJECT(buffer), q))
		return false;
	g_object_set_qdata(G_OBJECT(buffer), q, GINT_TO_POINTER(1));
	return true;
}

static void fill_cb(ArvBuffer *buffer, void *user, guint32 exposure_us, guint32 gain,
                    ArvPixelFormat pixel_format)
{
	(void)exposure_us;
	(void)gain;
	pc_gige_server *srv = user;
	const served_fmt *sf = served_by_code(srv, (uint32_t)pixel_format);
	if (!sf || !buffer)
		return;
	bool first = first_of_acquisition(buffer);
	g_mutex_lock(&srv->lock);
	if (first) {
		srv->st.acquisitions++;
		new_acquisition_locked(srv);
	}
	if (srv->n_cyc) {
		uint64_t k = srv->k++;
		srv->st.served++;
		srv->fresh = false;
		g_mutex_unlock(&srv->lock);
		render_roi(srv, &srv->cyc[k % srv->n_cyc], buffer, sf);
		return;
	}
	bool waited = false;
	while (!srv->r_count && !srv->quit && !srv->error) {
		waited = true;
		g_cond_wait_until(&srv->cond, &srv->lock, g_get_monotonic_time() + 100000);
	}
	if (!srv->r_count) {
		g_mutex_unlock(&srv->lock);
		return;
	}
	pc_buffer *b = srv->ready[srv->r_head];
	srv->r_head = (srv->r_head + 1) % 64;
	srv->r_count--;
	srv->k++;
	srv->st.served++;
	srv->st.late += waited;
	srv->fresh = false;
	g_mutex_unlock(&srv->lock);

	render_roi(srv, &b->frame.view, buffer, sf);

	g_mutex_lock(&srv->lock);
	srv->done[srv->d_count++] = b;
	g_cond_broadcast(&srv->cond);
	g_mutex_unlock(&srv->lock);
}

/* ---- the producer thread ---- */

static void fail(pc_gige_server *srv, int rc)
{
	g_mutex_lock(&srv->lock);
	if (!srv->error) {
		srv->error = rc;
		snprintf(srv->errmsg, sizeof srv->errmsg, "%s", pc_error_detail());
	}
	g_cond_broadcast(&srv->cond);
	g_mutex_unlock(&srv->lock);
}

/* The camera's exposure and gain registers, applied to the source when they change. */
static void apply_controls(pc_gige_server *srv)
{
	double e = reg(srv->fc, ARV_FAKE_CAMERA_REGISTER_EXPOSURE_TIME_US);
	double g = reg(srv->fc, ARV_FAKE_CAMERA_REGISTER_GAIN_RAW);
	if (e != srv->exposure_applied) {
		srv->exposure_applied = e;
		if (pc_source_control_set(srv->src, PC_CTRL_EXPOSURE_US, e, NULL))
			pc_error_clear(); /* outside the source's range: frames keep the old value
			                   */
	}
	if (g != srv->gain_applied) {
		srv->gain_applied = g;
		if (pc_source_control_set(srv->src, PC_CTRL_GAIN_DB, g, NULL))
			pc_error_clear();
	}
}

static void *producer(void *arg)
{
	pc_gige_server *srv = arg;
	for (;;) {
		g_mutex_lock(&srv->lock);
		if (srv->quit) {
			g_mutex_unlock(&srv->lock);
			break;
		}
		/* The early detector: acquisition stopped, so frame 0 is rendered before the client
		 * starts again. Read under the lock: a callback that saw the start meanwhile waits
		 * for it, so a register read before the start cannot restart the new acquisition
		 * after it served its first frame. */
		if (reg(srv->fc, ARV_FAKE_CAMERA_REGISTER_ACQUISITION) == 0)
			new_acquisition_locked(srv);
		pc_buffer *requeue[64];
		unsigned n_requeue = srv->d_count;
		memcpy(requeue, srv->done, n_requeue * sizeof requeue[0]);
		srv->d_count = 0;
		bool restart = srv->restart;
		srv->restart = false;
		uint64_t gen = srv->gen;
		bool want = !srv->n_cyc && !srv->error && srv->r_count < srv->ahead;
		g_mutex_unlock(&srv->lock);

		int rc = 0;
		if (restart)
			rc = pc_source_stop(srv->src);
		for (unsigned i = 0; !rc && i < n_requeue; i++)
			rc = pc_source_requeue(srv->src, requeue[i]);
		if (!rc && restart)
			rc = pc_source_start(srv->src);
		if (rc) {
			fail(srv, rc);
			want = false;
		}
		if (!want) {
			g_mutex_lock(&srv->lock);
			if (!srv->quit)
				g_cond_wait_until(&srv->cond, &srv->lock,
				                  g_get_monotonic_time() + 2000);
			g_mutex_unlock(&srv->lock);
			continue;
		}
		apply_controls(srv);
		pc_buffer *b = NULL;
		rc = pc_source_dequeue(srv->src, 20, &b);
		if (rc == PC_ETIMEDOUT)
			continue;
		if (rc) {
			fail(srv, rc);
			continue;
		}
		g_mutex_lock(&srv->lock);
		if (gen != srv->gen) {
			/* rendered for an acquisition that has ended: back to the source */
			srv->done[srv->d_count++] = b;
		} else {
			srv->st.rendered++;
			srv->ready[(srv->r_head + srv->r_count) % 64] = b;
			srv->r_count++;
			g_cond_broadcast(&srv->cond);
		}
		g_mutex_unlock(&srv->lock);
	}
	return NULL;
}

/* ---- start / stop ---- */

static int open_source(pc_gige_server *srv, const pc_gige_server_options *o)
{
	int rc = pc_source_open(&srv->src, o->source_uri);
	if (rc)
		return rc;
	pc_source_format f;
	pc_source_get_format(srv->src, &f);
	const pc_format_info *fi = pc_format_info_get(f.format);
	if (fi->packing != PC_PACK_NONE || fi->is_float) {
		/* ask for the unpacked 16-bit container of the same bits */
		pc_source_format r = f;
		r.format = fi->bits <= 8 ? PC_FMT_MONO8 : PC_FMT_MONO16;
		r.format_name[0] = '\0';
		pc_format_verdict v;
		rc = pc_source_try_format(srv->src, &r, &v);
		if (!rc && v != PC_FORMAT_VALID)
			rc = pc_error(PC_EFORMAT, "serve: source %s cannot deliver unpacked frames",
			              o->source_uri);
		if (!rc)
			rc = pc_source_set_format(srv->src, &r);
		if (rc)
			return rc;
		pc_source_get_format(srv->src, &f);
	}
	if (f.offset_x || f.offset_y)
		return pc_error(PC_EINVAL, "serve: the source must deliver its whole sensor");
	srv->sfmt = f;
	srv->bits = pc_format_info_get(f.format)->bits;
	if (f.format != PC_FMT_MONO8 && pc_format_info_get(f.format)->group_bytes != 2)
		return pc_error(PC_EFORMAT, "serve: unexpected source format %s", f.format_name);
	if (f.format == PC_FMT_MONO8)
		return pc_error(PC_ENOTSUP, "serve: 8-bit sources are not served yet (the camera "
		                            "model expands 16-bit frames)");
	return 0;
}

/* The served formats for the source's kind of mosaic, and a check that the mosaic is the one
 * clients will take from the camera's model name (GenICam has no feature for it). */
static int choose_formats(pc_gige_server *srv)
{
	srv->colour = srv->sfmt.mosaic.period == 4;
	const served_name *list = srv->colour ? served_colour : served_mono;
	size_t n = srv->colour ? sizeof served_colour / sizeof served_colour[0] : N_SERVED;
	size_t nt;
	const pc_genicam_format *gt = pc_genicam_formats(&nt);
	for (size_t i = 0; i < n; i++)
		for (size_t j = 0; j < nt; j++)
			if (!strcmp(gt[j].name, list[i].name)) {
				uint32_t code = list[i].code ? list[i].code : gt[j].code;
				assert(code != 0);
				srv->fmts[srv->n_fmts++] =
				    (served_fmt){gt[j].name, code, gt[j].fmt};
			}
	const char *model = srv->colour ? MODEL_COLOUR : MODEL_MONO;
	const pc_camera_profile *p = pc_camera_profile_find("polarcam", model);
	pc_mosaic want;
	int rc = p ? pc_mosaic_parse(p->mosaic, &want) : PC_EINVAL;
	assert(rc == 0);
	if (rc)
		return rc;
	if (!pc_mosaic_equal(&want, &srv->sfmt.mosaic)) {
		char have[64];
		pc_mosaic_format(&srv->sfmt.mosaic, have, sizeof have);
		return pc_error(PC_ENOTSUP,
		                "serve: the source's mosaic is %s; the camera (model %s) can only "
		                "describe %s to its clients",
		                have, model, p->mosaic);
	}
	return 0;
}

static int prepare_cycle(pc_gige_server *srv, unsigned k_frames, const pc_progress *progress)
{
	srv->cyc = calloc(k_frames, sizeof *srv->cyc);
	if (!srv->cyc)
		return pc_error(PC_ENOMEM, "serve: cycle frames");
	for (unsigned i = 0; i < k_frames; i++) {
		pc_buffer *b = NULL;
		int rc = pc_source_dequeue(srv->src, 600000, &b);
		if (!rc)
			rc = pc_view_alloc(&srv->cyc[i], srv->sfmt.format, srv->sfmt.width,
			                   srv->sfmt.height, 64);
		if (rc) {
			if (b)
				pc_source_requeue(srv->src, b);
			return rc;
		}
		for (uint32_t y = 0; y < srv->sfmt.height; y++)
			memcpy(PC_ROW(&srv->cyc[i], uint8_t, y), PC_ROW(&b->frame.view, uint8_t, y),
			       (size_t)srv->sfmt.width * 2);
		srv->n_cyc = i + 1;
		srv->st.rendered++;
		rc = pc_source_requeue(srv->src, b);
		if (rc)
			return rc;
		if (pc_progress_report(progress, "cycle", i + 1, k_frames))
			return pc_error(PC_ECANCELED,
			                "serve: stopped after rendering %u of the %u "
			                "cycle frames",
			                i + 1, k_frames);
	}
	return 0;
}

int pc_gige_server_start(pc_gige_server **out, const pc_gige_server_options *o)
{
	if (!out || !o || !o->source_uri)
		return pc_error(PC_EINVAL, "serve: missing options (a frame source is required)");
	*out = NULL;
	if (o->ahead > 60)
		return pc_error(PC_EINVAL, "serve: ahead = %u: at most 60 frames", o->ahead);
	if (o->cycle > 256)
		return pc_error(PC_EINVAL, "serve: cycle = %u: at most 256 frames", o->cycle);
	if (!(o->lost_packet_ratio >= 0 && o->lost_packet_ratio < 1))
		return pc_error(PC_EINVAL, "serve: lost packet ratio %g: expected [0, 1)",
		                o->lost_packet_ratio);
	double fps = o->frame_rate_hz > 0 ? o->frame_rate_hz : 25;
	if (fps > 1000)
		return pc_error(PC_ERANGE,
		                "serve: frame rate %g Hz: the camera model's frame period "
		                "has a 1000 us minimum",
		                fps);
	pc_gige_server *srv = calloc(1, sizeof *srv);
	if (!srv)
		return pc_error(PC_ENOMEM, "serve");
	g_mutex_init(&srv->lock);
	g_cond_init(&srv->cond);
	srv->ahead = o->ahead ? o->ahead : 4;
	srv->fresh = true; /* the source starts at frame 0 */
	*out = srv;        /* pc_gige_server_stop cleans up whatever was made */

	int rc = open_source(srv, o);
	if (!rc)
		rc = choose_formats(srv);
	if (!rc) {
		/* the pool: `ahead` ready frames, one being copied, one being rendered */
		rc = pc_source_buffers_alloc(srv->src, o->cycle ? 1 : srv->ahead + 2);
		if (!rc)
			rc = pc_source_start(srv->src);
		if (!rc && o->cycle)
			rc = prepare_cycle(srv, o->cycle, &o->progress);
	}
	if (!rc) {
		srv->row16 = malloc((size_t)srv->sfmt.width * sizeof *srv->row16);
		srv->xml = make_xml(srv);
		if (!srv->row16 || !srv->xml)
			rc = pc_error(PC_ENOMEM, "serve: GenICam description");
	}
	if (!rc) {
		/* Aravis reads the description from a file: a private one under $TMPDIR */
		const char *tmp = getenv("TMPDIR");
		if (!tmp || !*tmp)
			tmp = "/tmp";
		int n = snprintf(srv->xml_path, sizeof srv->xml_path, "%s/polarcam-genicam-XXXXXX",
		                 tmp);
		int fd = n > 0 && (size_t)n < sizeof srv->xml_path ? mkstemp(srv->xml_path) : -1;
		size_t len = strlen(srv->xml);
		if (fd < 0 || write(fd, srv->xml, len) != (ssize_t)len)
			rc = pc_error(PC_EIO, "serve: cannot write the GenICam description to %s",
			              tmp);
		if (fd < 0)
			srv->xml_path[0] = 0; /* nothing to unlink */
		else
			close(fd);
	}
	if (!rc) {
		const char *addr = o->address ? o->address : "127.0.0.1";
		srv->gv = arv_gv_fake_camera_new_full(addr, o->serial ? o->serial : "POLARCAM0001",
		                                      srv->xml_path);
		if (!srv->gv || !arv_gv_fake_camera_is_running(srv->gv))
			rc = pc_error(PC_EBUSY,
			              "serve: cannot run a GigE Vision camera on %s (not an "
			              "interface address, or the GVCP port 3956 is taken)",
			              addr);
	}
	if (srv->xml_path[0])
		unlink(srv->xml_path); /* read by the camera when it was created */
	if (!rc) {
		srv->fc = arv_gv_fake_camera_get_fake_camera(srv->gv);
		char name[32] = "polarcam", model[32], info[48];
		snprintf(model, sizeof model, "%s", srv->colour ? MODEL_COLOUR : MODEL_MONO);
		snprintf(info, sizeof info, "simulated %s, %u-bit",
		         srv->colour ? "IMX250MYR" : "IMX250MZR", srv->bits);
		arv_fake_camera_write_memory(srv->fc, GVBS_MANUFACTURER, sizeof name, name);
		arv_fake_camera_write_memory(srv->fc, GVBS_MODEL, sizeof model, model);
		arv_fake_camera_write_memory(srv->fc, GVBS_INFO, sizeof info, info);
		arv_fake_camera_write_register(srv->fc, ARV_FAKE_CAMERA_REGISTER_SENSOR_WIDTH,
		                               srv->sfmt.width);
		arv_fake_camera_write_register(srv->fc, ARV_FAKE_CAMERA_REGISTER_SENSOR_HEIGHT,
		                               srv->sfmt.height);
		arv_fake_camera_write_register(srv->fc, ARV_FAKE_CAMERA_REGISTER_WIDTH,
		                               srv->sfmt.width);
		arv_fake_camera_write_register(srv->fc, ARV_FAKE_CAMERA_REGISTER_HEIGHT,
		                               srv->sfmt.height);
		/* the default format keeps every bit of the sensor */
		const char *def = srv->colour ? (srv->bits <= 8    ? "BayerRGPolarized8"
		                                 : srv->bits <= 10 ? "BayerRGPolarized10p"
		                                 : srv->bits <= 12 ? "BayerRGPolarized12p"
		                                                   : "BayerRGPolarized16")
		                              : (srv->bits <= 8    ? "PolarizeMono8"
		                                 : srv->bits <= 12 ? "PolarizeMono12"
		                                                   : "PolarizeMono16");
		for (unsigned i = 0; i < srv->n_fmts; i++)
			if (!strcmp(srv->fmts[i].name, def))
				arv_fake_camera_write_register(
				    srv->fc, ARV_FAKE_CAMERA_REGISTER_PIXEL_FORMAT,
				    srv->fmts[i].code);
		arv_fake_camera_write_register(srv->fc,
		                               ARV_FAKE_CAMERA_REGISTER_ACQUISITION_FRAME_PERIOD_US,
		                               (guint32)(1e6 / fps + 0.5));
		double e = 0, g = 0;
		if (pc_source_control_get(srv->src, PC_CTRL_EXPOSURE_US, &e) == 0 && e >= 1)
			arv_fake_camera_write_register(
			    srv->fc, ARV_FAKE_CAMERA_REGISTER_EXPOSURE_TIME_US, (guint32)(e + 0.5));
		if (pc_source_control_get(srv->src, PC_CTRL_GAIN_DB, &g) == 0 && g >= 0)
			arv_fake_camera_write_register(srv->fc, ARV_FAKE_CAMERA_REGISTER_GAIN_RAW,
			                               (guint32)(g + 0.5));
		/* the black level the source declares (0: none) and the sensor's bit depth */
		pc_source_info si;
		memset(&si, 0, sizeof si);
		float bl = pc_source_get_info(srv->src, &si) == 0 && si.black_level > 0
		               ? (float)si.black_level
		               : 0.0f;
		guint32 blbits;
		memcpy(&blbits, &bl, sizeof blbits);
		arv_fake_camera_write_register(srv->fc, REG_BLACK_LEVEL, blbits);
		arv_fake_camera_write_register(srv->fc, REG_ADC_BITS, srv->bits);
		srv->st.black_level = bl;
		pc_error_clear();
		srv->exposure_applied = reg(srv->fc, ARV_FAKE_CAMERA_REGISTER_EXPOSURE_TIME_US);
		srv->gain_applied = reg(srv->fc, ARV_FAKE_CAMERA_REGISTER_GAIN_RAW);
		if (o->lost_packet_ratio > 0)
			g_object_set(srv->gv, "gvsp-lost-ratio", o->lost_packet_ratio, NULL);
		srv->st.sensor_width = srv->sfmt.width;
		srv->st.sensor_height = srv->sfmt.height;
		srv->st.bits = srv->bits;
		snprintf(srv->st.model, sizeof srv->st.model, "%s", model);
		pc_mosaic_format(&srv->sfmt.mosaic, srv->st.mosaic, sizeof srv->st.mosaic);
		arv_fake_camera_set_fill_pattern(srv->fc, fill_cb, srv);
		srv->thread = g_thread_try_new("polarcam-serve", producer, srv, NULL);
		if (!srv->thread)
			rc = pc_error(PC_ENOMEM, "serve: cannot start the producer thread");
	}
	if (rc) {
		char msg[512];
		snprintf(msg, sizeof msg, "%s", pc_error_detail());
		pc_gige_server_stop(srv);
		*out = NULL;
		return pc_error(rc, "%s", msg);
	}
	return 0;
}

void pc_gige_server_get_stats(pc_gige_server *srv, pc_gige_server_stats *st)
{
	g_mutex_lock(&srv->lock);
	*st = srv->st;
	g_mutex_unlock(&srv->lock);
}

int pc_gige_server_error(pc_gige_server *srv, char *msg, unsigned size)
{
	g_mutex_lock(&srv->lock);
	int rc = srv->error;
	if (msg && size)
		snprintf(msg, size, "%s", srv->errmsg);
	g_mutex_unlock(&srv->lock);
	return rc;
}

const char *pc_gige_server_genicam(pc_gige_server *srv)
{
	return srv ? srv->xml : NULL;
}

void pc_gige_server_stop(pc_gige_server *srv)
{
	if (!srv)
		return;
	g_mutex_lock(&srv->lock);
	srv->quit = true;
	g_cond_broadcast(&srv->cond);
	g_mutex_unlock(&srv->lock);
	if (srv->thread)
		g_thread_join(srv->thread);
	if (srv->gv)
		g_object_unref(srv->gv); /* stops the camera thread (and its callbacks) */
	pc_source_close(srv->src);
	for (unsigned i = 0; i < srv->n_cyc; i++)
		pc_view_free(&srv->cyc[i]);
	free(srv->cyc);
	free(srv->row16);
	g_free(srv->xml);
	g_mutex_clear(&srv->lock);
	g_cond_clear(&srv->cond);
	free(srv);
}

void pc_devices_shutdown(void)
{
	arv_shutdown();
}
