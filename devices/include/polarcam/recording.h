/* polarcam/recording.h - recordings of raw frames: what `polarcam render` and `polarcam capture`
 * write and what the file: source reads.
 *
 * Layout of a recording directory:
 *
 *   DIR/raw_000000.png, raw_000001.png, ...   one grey PNG per frame, in recording order:
 *                                             8-bit for 8-bit formats; 16-bit with an sBIT chunk
 *                                             holding the significant bits for 9..16-bit formats
 *                                             (values LSB-aligned, as Mono10/12/16); packed
 *                                             device formats (Mono12p...) are unpacked first
 *   or raw_NNNNNN.npy                         the same pixels as a NumPy (H, W) array, u1 or <u2
 *   or raw_NNNNNN.raw                         the same pixels headerless: rows without padding,
 *                                             1 byte per pixel (8-bit) or 2 bytes little-endian,
 *                                             W, H and the format from meta.json
 *   DIR/meta.json                             the recording's description (below)
 *
 * The three stores (pc_recording_store) hold the same values; PNG is compressed (about half the
 * bytes of the others for 12-bit frames) and costs the most time to write, raw costs the least.
 *
 * meta.json (written atomically, rewritten while recording, complete=true at the end):
 *
 *   { "polarcam_recording": 1,
 *     "source": "sim:default?seed=3",           who produced the frames
 *     "format": "Mono12", "bits": 12,           what the PNGs hold
 *     "device_format": "PolarizeMono12p",       the device's pixel format name
 *     "width": 2448, "height": 2048,            frame size (the ROI)
 *     "offset_x": 0, "offset_y": 0,             ROI origin on the sensor
 *     "sensor_width": 2448, "sensor_height": 2048,
 *     "polarized": true, "mosaic": "90,45,135,0",  mosaic phase at pixel (0,0) of the frames
 *     "store": "png",                           how the frames are stored (png, npy, raw)
 *     "frames": [ { "file": "raw_000000.png", "sequence": 0, "timestamp_ns": 0,
 *                   "exposure_us": 10000, "gain_db": 0, "status": [] }, ... ],
 *                                           (exposure_us, gain_db: null when unknown)
 *     "complete": true, "error": null,         false + message when recording ended early
 *     "stats": { ... }, "extra": { ... } }      free-form objects (source statistics, ...)
 *
 * Every frame file is written atomically (temporary file + rename), so a recording that ended
 * early (a camera unplugged, the process killed) holds only whole frames, and meta.json lists
 * the frames written before its last rewrite. While a recording is being written meta.json says
 * complete = false with error null; it says complete = true only once every frame is in. A
 * process killed while writing a frame leaves its temporary file (".raw_NNNNNN.png.tmpXXXXXX",
 * never listed); the next recording made in the directory removes such leftovers
 * (pc_atomic_sweep).
 */
#ifndef POLARCAM_RECORDING_H
#define POLARCAM_RECORDING_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "polarcam/export.h"
#include "polarcam/frame.h"
#include "polarcam/mosaic.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pc_recording pc_recording;

/* How frames are stored (the files' extension). */
typedef enum pc_recording_store {
	PC_STORE_PNG = 0, /* raw_NNNNNN.png */
	PC_STORE_NPY,     /* raw_NNNNNN.npy */
	PC_STORE_RAW      /* raw_NNNNNN.raw */
} pc_recording_store;

/* "png", "npy", "raw"; NULL for anything else. */
PC_API const char *pc_recording_store_name(pc_recording_store s);
/* PC_EINVAL naming the choices for an unknown name. */
PC_API int pc_recording_store_from_name(const char *name, pc_recording_store *out);

typedef struct pc_recording_desc {
	const char *source;        /* URI or description, may be NULL */
	pc_pixfmt format;          /* the frames' pixel format (any integer format) */
	const char *device_format; /* device's name for it, may be NULL */
	uint32_t width, height, offset_x, offset_y, sensor_width, sensor_height;
	bool polarized;
	pc_mosaic mosaic;         /* phase at pixel (0,0) of the frames */
	pc_recording_store store; /* how frames are written (PNG by default) */
} pc_recording_desc;

typedef struct pc_recording_frame {
	char file[32];
	uint64_t sequence, timestamp_ns;
	double exposure_us, gain_db;
	uint32_t status; /* pc_frame_status flags */
} pc_recording_frame;

/* Starts a recording in dir (created if missing). Refuses (PC_EBUSY) a directory that already
 * holds a recording (meta.json or raw_000000.png/.npy/.raw) unless overwrite: then old raw_*
 * files beyond the new recording's end are left alone but meta.json only lists the new frames.
 * Temporary files that killed writers left in dir are removed (pc_atomic_sweep). */
PC_API int pc_recording_create(pc_recording **out, const char *dir, const pc_recording_desc *desc,
                               bool overwrite);
/* Appends a frame: checks it matches the description, writes raw_NNNNNN.png (.npy, .raw)
 * atomically and records its metadata. meta.json is rewritten at most every 0.25 s while
 * recording. */
PC_API int pc_recording_add(pc_recording *r, const pc_frame *frame);
/* Attaches JSON text objects written under "stats" / "extra" (NULL clears). PC_EINVAL when
 * the text is not a JSON object. */
PC_API int pc_recording_set_json(pc_recording *r, const char *key, const char *json_object_text);
/* Writes the final meta.json: complete when error is NULL, else complete=false with the error
 * text. The recording stays usable for reading. */
PC_API int pc_recording_finish(pc_recording *r, const char *error);

/* Opens a recording for reading and validates meta.json (every field; frames listed in
 * increasing sequence and non-decreasing time; files named raw_NNNNNN.png, .npy or .raw; a
 * raw frame's file holds exactly W x H pixels). A directory of
 * raw_NNNNNN.png files without meta.json is accepted with defaults: frames numbered from
 * 000000 without gaps, format from the first PNG's bit depth (sBIT), IMX250MZR mosaic,
 * timestamps 0 (callers pace them). Errors name the file and the field. */
PC_API int pc_recording_open(pc_recording **out, const char *dir);
PC_API void pc_recording_free(pc_recording *r);

/* Description and frames of an open recording (valid until freed). */
PC_API const pc_recording_desc *pc_recording_get_desc(const pc_recording *r);
PC_API size_t pc_recording_count(const pc_recording *r);
PC_API const pc_recording_frame *pc_recording_get_frame(const pc_recording *r, size_t i);
PC_API bool pc_recording_is_complete(const pc_recording *r);
PC_API const char *pc_recording_dir(const pc_recording *r);

/* The black level (DN) of the sensor that made the frames, when the recording says
 * (extra.sensor.offset_dn, as `polarcam render` and `polarcam capture` of a source that
 * declares one write it), else 0. */
PC_API double pc_recording_black_level(const pc_recording *r);

/* The mosaic of a raw file when it is a frame listed in its directory's meta.json (a recording
 * written by render or capture), or of a recording directory itself: 1 and *m set; 0 when it is
 * not (no such recording, not one of its frames, frames without a polarizer mosaic). An error
 * (negative, detail naming both files) only for a file named like a recording's frame
 * (raw_NNNNNN.png) beside a meta.json that does not open: its mosaic is unknown, and guessing
 * the monochrome default would be wrong for a colour recording. */
PC_API int pc_recording_frame_mosaic(const char *path, pc_mosaic *m);

/* What a recording says about one of its frames (pc_recording_frame_info). */
typedef struct pc_recording_frame_meta {
	pc_mosaic mosaic; /* the frames' mosaic (when polarized) */
	bool polarized;
	double black_level; /* pc_recording_black_level: DN, 0 when not said */
	unsigned bits;      /* significant bits of the frames */
	uint32_t offset_x, offset_y, sensor_width, sensor_height; /* ROI origin, sensor size */
} pc_recording_frame_meta;

/* pc_recording_frame_mosaic with everything the recording says about the frame: 1 and *m set
 * when path is a frame listed in its directory's meta.json, else 0; an error (negative) as
 * pc_recording_frame_mosaic's, for a frame named like a recording's beside a meta.json that
 * does not open. */
PC_API int pc_recording_frame_info(const char *path, pc_recording_frame_meta *m);

/* Reads frame i into an owned view of the recording's storage format (Mono8 or 16-bit
 * Mono10/12/14/16 by bits). Checks the file's size and bit depth against meta.json and every
 * value against the bit depth. Free with pc_view_free. */
PC_API int pc_recording_read(const pc_recording *r, size_t i, pc_view *out);

/* The storage format of a recording of frames in fmt: Mono8 for <= 8 bits, else Mono10/12/14/16
 * by the significant bits. */
PC_API pc_pixfmt pc_recording_storage_format(pc_pixfmt fmt);

#ifdef __cplusplus
}
#endif
#endif
