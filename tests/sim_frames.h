/* tests/sim_frames.h - what a recording of the simulator must hold, known independently of the
 * recording: the frames a sim: source regenerates from (scene, seed, frame number), as
 * checksums of their pixel values; and the check that a directory holds only whole, readable
 * files under final names (what a process killed at any moment may leave), with its temporary
 * leftovers recognisable (".NAME.tmpXXXXXX", pc_atomic_open); and where a command works on an
 * output folder before it puts it in place (the sibling ".NAME.tmp-HOST-PID-XXXXXX",
 * pc_outdir in polarcam/io.h). */
#ifndef POLARCAM_TESTS_SIM_FRAMES_H
#define POLARCAM_TESTS_SIM_FRAMES_H

#include <dirent.h>
#include <jansson.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "out_peek.h"
#include "polarcam/error.h"
#include "polarcam/io.h"
#include "polarcam/recording.h"
#include "polarcam/source.h"

/* FNV-1a (64-bit) over the pixel values row by row, each as two little-endian bytes, after the
 * size: independent of the stride and of how the values are stored. */
static inline uint64_t sf_checksum(const pc_view *v)
{
	uint64_t h = 1469598103934665603ull;
	uint32_t dims[2] = {v->width, v->height};
	const uint8_t *d = (const uint8_t *)dims;
	for (size_t i = 0; i < sizeof dims; i++)
		h = (h ^ d[i]) * 1099511628211ull;
	const bool b8 = pc_format_info_get(v->format)->group_bytes == 1;
	for (uint32_t y = 0; y < v->height; y++) {
		const uint8_t *row = PC_ROW(v, const uint8_t, y);
		for (uint32_t x = 0; x < v->width; x++) {
			uint16_t val = b8 ? row[x] : ((const uint16_t *)(const void *)row)[x];
			h = (h ^ (uint8_t)(val & 0xff)) * 1099511628211ull;
			h = (h ^ (uint8_t)(val >> 8)) * 1099511628211ull;
		}
	}
	return h;
}

typedef struct sf_frames {
	uint64_t *sum;     /* checksum of frame n */
	uint64_t *sum_cut; /* of frame n without its last row (frames damaged there on purpose) */
	uint64_t n;
	uint32_t width, height;
	pc_pixfmt format; /* the source's (unpacked) format */
	char uri[1024];   /* sim:SCENE?seed=S&fps=0, for frames beyond n (sf_sum) */
} sf_frames;

/* The source of uri opened with `buffers` buffers and streaming (*s to close in any case). */
static inline int sf_start(const char *uri, unsigned buffers, pc_source **s)
{
	int rc = pc_source_open(s, uri);
	if (!rc)
		rc = pc_source_buffers_alloc(*s, buffers);
	if (!rc)
		rc = pc_source_start(*s);
	return rc;
}

/* Frames 0..n-1 of sim:SCENE?seed=S, regenerated one by one. 0 on success. */
static inline int sf_regenerate(const char *scene, uint64_t seed, uint64_t n, sf_frames *out)
{
	memset(out, 0, sizeof *out);
	char *uri = out->uri;
	snprintf(uri, sizeof out->uri, "sim:%s?seed=%llu&fps=0", scene, (unsigned long long)seed);
	pc_source *s = NULL;
	int rc = sf_start(uri, 2, &s);
	out->sum = calloc(n ? n : 1, sizeof *out->sum);
	out->sum_cut = calloc(n ? n : 1, sizeof *out->sum_cut);
	for (uint64_t k = 0; !rc && k < n; k++) {
		pc_buffer *b = NULL;
		if ((rc = pc_source_dequeue(s, 600000, &b)))
			break;
		if (b->frame.meta.sequence != k)
			rc = PC_EIO;
		out->sum[k] = sf_checksum(&b->frame.view);
		pc_view cut = b->frame.view;
		cut.height--;
		out->sum_cut[k] = sf_checksum(&cut);
		out->width = b->frame.view.width;
		out->height = b->frame.view.height;
		out->format = b->frame.view.format;
		pc_source_requeue(s, b);
	}
	if (rc)
		fprintf(stderr, "regenerating %s: %s\n", uri, pc_error_detail());
	else
		out->n = n;
	pc_source_close(s);
	return rc;
}

/* The checksum of frame `number` (cut: without its last row): from the table below n, else
 * regenerated alone (`first=number`). A capture behind a slow writer skips frames, so its
 * sequence numbers can pass any table's end: the more it lags, the further (a writer of 250 ms
 * per frame at 30 frames/s records about every 8th number). 0 on success. */
static inline int sf_sum(const sf_frames *f, uint64_t number, bool cut, uint64_t *sum)
{
	if (number < f->n) {
		*sum = cut ? f->sum_cut[number] : f->sum[number];
		return 0;
	}
	char uri[1100];
	snprintf(uri, sizeof uri, "%s&first=%llu", f->uri, (unsigned long long)number);
	pc_source *s = NULL;
	int rc = sf_start(uri, 1, &s);
	pc_buffer *b = NULL;
	if (!rc)
		rc = pc_source_dequeue(s, 600000, &b);
	if (!rc && b->frame.meta.sequence != number)
		rc = PC_EIO;
	if (!rc) {
		pc_view v = b->frame.view;
		v.height -= cut;
		*sum = sf_checksum(&v);
	}
	if (rc)
		fprintf(stderr, "regenerating frame %llu of %s: %s\n", (unsigned long long)number,
		        uri, pc_error_detail());
	pc_source_close(s);
	return rc;
}

static inline void sf_free(sf_frames *f)
{
	free(f->sum);
	free(f->sum_cut);
	f->sum = f->sum_cut = NULL;
}

/* A PNG is whole when it ends with the IEND chunk (written last; a torn file does not). */
static inline bool sf_png_whole(const char *path)
{
	static const uint8_t iend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xae, 0x42, 0x60, 0x82};
	FILE *fp = fopen(path, "rb");
	uint8_t tail[12];
	bool ok = fp && fseek(fp, -12, SEEK_END) == 0 && fread(tail, 1, 12, fp) == 12 &&
	          !memcmp(tail, iend, 12);
	if (fp)
		fclose(fp);
	return ok;
}

/* ".NAME.tmpXXXXXX" */
static inline bool sf_is_tmp_name(const char *n)
{
	size_t len = strlen(n);
	if (len < 12 || n[0] != '.' || memcmp(n + len - 10, ".tmp", 4))
		return false;
	for (size_t i = len - 6; i < len; i++)
		if (!((n[i] >= 'a' && n[i] <= 'z') || (n[i] >= 'A' && n[i] <= 'Z') ||
		      (n[i] >= '0' && n[i] <= '9')))
			return false;
	return true;
}

typedef struct sf_dir_report {
	unsigned files;     /* under final names */
	unsigned frames;    /* frame files decoded and compared */
	unsigned listed;    /* frames meta.json lists */
	unsigned leftovers; /* temporary files */
	unsigned bad;       /* anything else: torn, unreadable, wrong content, unknown name */
	bool meta;          /* meta.json present */
	bool complete;      /* meta.json says so */
} sf_dir_report;

/* Frame file N of a recording of the simulator: the frame number is the sequence meta.json
 * lists for it, or N for a file written after meta.json's last rewrite (recordings that
 * start at frame 0 without gaps). */
static inline bool sf_frame_ok(const char *dir, const char *name, uint64_t number,
                               const sf_frames *f)
{
	char p[1200];
	snprintf(p, sizeof p, "%s/%s", dir, name);
	pc_raw_geometry g = {f->width, f->height, pc_recording_storage_format(f->format), 0, 0};
	bool raw = strstr(name, ".raw") != NULL;
	pc_view v;
	if (raw) { /* exactly W x H values of two bytes */
		struct stat st;
		if (stat(p, &st) || (uint64_t)st.st_size != (uint64_t)f->width * f->height * 2)
			return false;
	}
	if (pc_image_read(p, raw ? &g : NULL, &v, NULL)) {
		fprintf(stderr, "%s: %s\n", p, pc_error_detail());
		pc_error_clear();
		return false;
	}
	uint64_t want = 0;
	bool ok = sf_sum(f, number, false, &want) == 0 && sf_checksum(&v) == want;
	if (!ok)
		fprintf(stderr, "%s: not frame %llu of the simulator\n", p,
		        (unsigned long long)number);
	pc_view_free(&v);
	return ok;
}

static inline void sf_check_dir(const char *dir, const sf_frames *f, sf_dir_report *r);

/* meta.json read as JSON (not through the recording reader): the frames it lists. */
static inline void sf_check_meta(const char *dir, const sf_frames *f, sf_dir_report *r,
                                 char *listed, size_t n_listed_max)
{
	char p[1200];
	snprintf(p, sizeof p, "%s/meta.json", dir);
	json_error_t e;
	json_t *m = json_load_file(p, 0, &e);
	if (!m) {
		fprintf(stderr, "%s: not JSON: %s\n", p, e.text);
		r->bad++;
		return;
	}
	r->meta = true;
	r->complete = json_is_true(json_object_get(m, "complete"));
	json_t *fr = json_object_get(m, "frames");
	for (size_t i = 0; i < json_array_size(fr); i++) {
		json_t *o = json_array_get(fr, i);
		const char *file = json_string_value(json_object_get(o, "file"));
		json_int_t seq = json_integer_value(json_object_get(o, "sequence"));
		unsigned idx;
		if (!file || sscanf(file, "raw_%6u", &idx) != 1 || idx >= n_listed_max ||
		    !sf_frame_ok(dir, file, (uint64_t)seq, f)) {
			r->bad++;
			continue;
		}
		listed[idx] = 1;
		r->listed++;
		r->frames++;
	}
	json_decref(m);
}

static inline void sf_check_dir(const char *dir, const sf_frames *f, sf_dir_report *r)
{
	enum { MAXF = 100000 };
	char *listed = calloc(MAXF, 1);
	struct stat st;
	char p[1200];
	snprintf(p, sizeof p, "%s/meta.json", dir);
	if (stat(p, &st) == 0) {
		r->files++;
		sf_check_meta(dir, f, r, listed, MAXF);
	}
	DIR *d = opendir(dir);
	struct dirent *de;
	while (d && (de = readdir(d))) {
		const char *n = de->d_name;
		if (!strcmp(n, ".") || !strcmp(n, "..") || !strcmp(n, "meta.json"))
			continue;
		snprintf(p, sizeof p, "%s/%s", dir, n);
		if (n[0] == '.') {
			if (sf_is_tmp_name(n))
				r->leftovers++;
			else {
				fprintf(stderr, "%s: an unknown hidden file\n", p);
				r->bad++;
			}
			continue;
		}
		r->files++;
		unsigned idx;
		char ext[8];
		if (sscanf(n, "raw_%6u.%3s", &idx, ext) == 2) {
			if (idx < MAXF && listed[idx])
				continue; /* checked with its listed sequence */
			if (sf_frame_ok(dir, n, idx, f))
				r->frames++;
			else
				r->bad++;
		} else if (strstr(n, ".npy")) {
			pc_array a;
			if (pc_npy_read(p, &a) == 0)
				pc_array_free(&a);
			else {
				fprintf(stderr, "%s: %s\n", p, pc_error_detail());
				r->bad++;
			}
		} else if (strstr(n, ".png")) {
			if (!sf_png_whole(p)) {
				fprintf(stderr, "%s: torn PNG\n", p);
				r->bad++;
			}
		} else if (stat(p, &st) == 0 && S_ISDIR(st.st_mode)) {
			r->files--;
			sf_dir_report sub;
			memset(&sub, 0, sizeof sub);
			sf_check_dir(p, f, &sub); /* processed/: pictures and planes */
			r->files += sub.files;
			r->leftovers += sub.leftovers;
			r->bad += sub.bad;
		} else if (strcmp(n, "states.json") && strcmp(n, "capture.out") &&
		           strcmp(n, "capture.err")) {
			fprintf(stderr, "%s: an unexpected file\n", p);
			r->bad++;
		}
	}
	if (d)
		closedir(d);
	free(listed);
}

#endif
