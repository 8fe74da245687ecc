/* test_libcamera.c - the `libcamera:` source against the real libcamera CameraManager on this
 * machine (which has no camera): enumeration succeeds and lists only real cameras, opening an
 * unknown camera names what exists, bad URIs are refused. Skipped (77) when the build has no
 * libcamera backend (configure with -DPC_WITH_LIBCAMERA=ON; ./do test does). Streaming from a
 * camera needs one: the QEMU guest has none with libcamera (see docs/status/v4l2.md). */
#include "check.h"

#include <string.h>

#include "polarcam/error.h"
#include "polarcam/source.h"

static int count_cb(void *ctx, const pc_device_entry *e)
{
	unsigned *n = ctx;
	(*n)++;
	CHECK(strncmp(e->uri, "libcamera:", 10) == 0);
	CHECK(!strcmp(e->transport, "libcamera"));
	return 0;
}

int main(void)
{
	const pc_source_backend *b = pc_source_backend_find("libcamera");
	CHECK(b != NULL);
	if (!b || !b->ops)
		SKIP("the libcamera backend is not in this build (%s)",
		     b && b->missing ? b->missing : "?");

	unsigned n = 0;
	int rc = b->enumerate(0, count_cb, &n);
	CHECK_EQ_INT(rc, 0);
	printf("libcamera finds %u camera(s) here\n", n);

	pc_source *s = NULL;
	rc = pc_source_open(&s, "libcamera:no-such-camera");
	CHECK_EQ_INT(rc, PC_EUNAVAIL);
	CHECK(s == NULL);
	CHECK(strstr(pc_error_detail(), "no-such-camera") != NULL);
	CHECK(strstr(pc_error_detail(), "camera") != NULL);
	printf("open: %s\n", pc_error_detail());

	/* an index beyond the cameras present */
	rc = pc_source_open(&s, "libcamera:99");
	CHECK_EQ_INT(rc, PC_EUNAVAIL);
	rc = pc_source_open(&s, "libcamera:");
	CHECK_EQ_INT(rc, PC_EINVAL);
	rc = pc_source_open(&s, "libcamera:x?bogus=1");
	CHECK_EQ_INT(rc, PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "bogus") != NULL);
	rc = pc_source_open(&s, "libcamera:x?mosaic=1,2,3");
	CHECK_EQ_INT(rc, PC_EINVAL);

	/* the manager is released and can start again */
	n = 0;
	CHECK_EQ_INT(b->enumerate(0, count_cb, &n), 0);
	return pc_test_finish("test_libcamera");
}
