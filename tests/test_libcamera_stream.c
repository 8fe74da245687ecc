/* test_libcamera_stream.c - streams from the first libcamera camera of this machine that offers
 * a raw monochrome format, through the frame-source compliance test. Skipped (77) when there is
 * none, which is the case in CI: the virtual camera vimc is not in Debian's kernel, and even
 * built out of tree its libcamera pipeline (0.0.3) offers only processed RGB888/BGR888, which
 * the `libcamera:` source refuses (polarcam reads raw mosaic formats: R8/R10/R12/R16 and the
 * CSI-2 packed ones). On a machine with such a camera (a mono sensor on a Raspberry Pi, say)
 * it runs for real. */
#include "check.h"

#include <stdio.h>
#include <string.h>

#include "polarcam/compliance.h"
#include "polarcam/error.h"
#include "polarcam/source.h"

static int first_usable(void *ctx, const pc_device_entry *e)
{
	char *uri = ctx;
	if (e->usable && !uri[0])
		snprintf(uri, 256, "%s", e->uri);
	return 0;
}

static void log_cb(void *ctx, pc_check_result r, const char *check, const char *detail)
{
	(void)ctx;
	static const char *const names[] = {"PASS", "FAIL", "SKIP"};
	printf("%s %s: %s\n", names[r], check, detail);
}

int main(void)
{
	const pc_source_backend *b = pc_source_backend_find("libcamera");
	if (!b || !b->ops)
		SKIP("the libcamera backend is not in this build (%s)",
		     b && b->missing ? b->missing : "?");
	char uri[256] = "";
	int rc = b->enumerate(0, first_usable, uri);
	CHECK_EQ_INT(rc, 0);
	if (rc == 0 && !uri[0])
		SKIP("no libcamera camera with a raw monochrome format on this machine (vimc, the "
		     "virtual camera, is not in Debian's kernel, and its libcamera pipeline offers "
		     "only "
		     "RGB888/BGR888)");
	pc_compliance_options o;
	memset(&o, 0, sizeof o);
	o.log = log_cb;
	pc_compliance_result res;
	rc = pc_source_compliance(uri, &o, &res);
	CHECK_EQ_INT(rc, 0);
	CHECK_EQ_INT(res.failed, 0);
	if (res.failed)
		fprintf(stderr, "%s: first failure: %s\n", uri, res.first_failure);
	return pc_test_finish("test_libcamera_stream");
}
