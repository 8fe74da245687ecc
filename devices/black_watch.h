/* devices/black_watch.h - internal: watching for the black level a source declares only once
 * frames flow (a `libcamera:` camera reports SensorBlackLevels with its frames, and a pipeline
 * may attach it only from a later request), for devices/stream.c and devices/capture.c. */
#ifndef POLARCAM_DEVICES_BLACK_WATCH_H
#define POLARCAM_DEVICES_BLACK_WATCH_H

#include <math.h>
#include <stdbool.h>

#include "polarcam/error.h"
#include "polarcam/source.h"
#include "polarcam/stream.h"

typedef struct black_watch {
	bool open;       /* still asking */
	bool asked;      /* asked after at least one frame */
	bool taken;      /* a level was declared: level */
	unsigned frames; /* frames asked after */
	double level;
} black_watch;

/* open: no level was given and none declared before the first frame */
static inline void black_watch_init(black_watch *w, bool open)
{
	*w = (black_watch){open, false, false, 0, 0};
}

/* At the start: the black level to use now — given (not NaN), else what src declares (0 when
 * none, or when !ask: a calibration's dark map is the level) — and the watch opened when none
 * was given or declared and src declares its level with its frames (black_level_late; no src:
 * the levels come with the frames, pc_capture's writer). */
static inline double black_watch_start(black_watch *w, pc_source *src, double given, bool ask)
{
	if (!isnan(given)) {
		black_watch_init(w, false);
		return given;
	}
	double level = 0;
	bool late = src == NULL;
	pc_source_info info;
	if (ask && src && pc_source_get_info(src, &info) == 0) {
		level = info.black_level;
		late = info.black_level_late;
	}
	pc_error_clear();
	black_watch_init(w, ask && !(level > 0) && late);
	return level;
}

/* After each dequeued frame, before it is processed: asks src, until a level above 0 is declared
 * or PC_STREAM_BLACK_FRAMES frames were asked after. 1 when a level is taken now (w->level),
 * else 0; never an error (a source that cannot say declares none). */
static inline int black_watch_frame(black_watch *w, pc_source *src)
{
	if (!w->open || !src)
		return 0;
	w->asked = true;
	w->frames++;
	pc_source_info info;
	int taken = pc_source_get_info(src, &info) == 0 && info.black_level > 0 &&
	            isfinite(info.black_level);
	pc_error_clear();
	if (taken) {
		w->taken = true;
		w->level = info.black_level;
	}
	if (taken || w->frames >= PC_STREAM_BLACK_FRAMES)
		w->open = false;
	return taken;
}

/* True when frames were asked after and none brought a level: 0 DN was used throughout. */
static inline bool black_watch_missed(const black_watch *w)
{
	return w->asked && !w->taken;
}

#endif
