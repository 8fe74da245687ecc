/* The registry of frame-source backends: the only place in polarcam that knows which optional
 * backends this build has (PC_HAVE_* come from devices/CMakeLists.txt, set for this file only). */
#include "polarcam/source.h"

#include <string.h>

#include "backends.h"
#include "polarcam/error.h"
#include "polarcam/usb3v.h"

#if PC_HAVE_ARAVIS
#define ARAVIS_OPS     &pc_aravis_source_ops
#define ARAVIS_ENUM    pc_aravis_enumerate
#define ARAVIS_MISSING NULL
#else
#define ARAVIS_OPS     NULL
#define ARAVIS_ENUM    NULL
#define ARAVIS_MISSING "Aravis 0.8 was not found at configure time (Debian: libaravis-dev)"
#endif

#if PC_HAVE_V4L2
#define V4L2_OPS     &pc_v4l2_source_ops
#define V4L2_ENUM    pc_v4l2_enumerate
#define V4L2_MISSING NULL
#else
#define V4L2_OPS     NULL
#define V4L2_ENUM    NULL
#define V4L2_MISSING "the V4L2 backend is not in this build (needs Linux <linux/videodev2.h>)"
#endif

#if PC_HAVE_LIBCAMERA
#define LIBCAMERA_OPS     &pc_libcamera_source_ops
#define LIBCAMERA_ENUM    pc_libcamera_enumerate
#define LIBCAMERA_MISSING NULL
#else
#define LIBCAMERA_OPS  NULL
#define LIBCAMERA_ENUM NULL
#define LIBCAMERA_MISSING                                                                          \
	"libcamera is off unless asked for (cmake -DPC_WITH_LIBCAMERA=ON, Debian: "                \
	"libcamera-dev)"
#endif

/* sim: and file: are in every build of the library; programs that compile the registry alone
 * (the static V4L2 guest program of tests/v4l2.cmake) leave them out. */
#if PC_HAVE_SIM_SOURCE
#define SIM_OPS &pc_sim_source_ops
#else
#define SIM_OPS NULL
#endif
#if PC_HAVE_FILE_SOURCE
#define FILE_OPS &pc_file_source_ops
#else
#define FILE_OPS NULL
#endif

static const pc_source_backend pc_backends[] = {
    {"sim", "the simulator: renders a scene to raw mosaic frames, paced, with faults on demand",
     "sim:SCENE[?fps=F&seed=S&...]   SCENE = a scene file or 'default'", SIM_OPS,
     "not in this program", NULL},
    {"file", "a recording: raw_NNNNNN.png and metadata as written by render and capture",
     "file:DIR[?loop=1&fps=F]", FILE_OPS, "not in this program", NULL},
    {"aravis", "GigE Vision and USB3 Vision cameras through Aravis 0.8",
     "aravis:ID[?packet_size=N&...]   ID = device id, serial number or IP address", ARAVIS_OPS,
     ARAVIS_MISSING, ARAVIS_ENUM},
    {"v4l2", "Video4Linux2 capture nodes (mmap streaming)", "v4l2:/dev/videoN", V4L2_OPS,
     V4L2_MISSING, V4L2_ENUM},
    {"libcamera", "cameras through libcamera", "libcamera:ID", LIBCAMERA_OPS, LIBCAMERA_MISSING,
     LIBCAMERA_ENUM},
};

const pc_source_backend *pc_source_backend_get(unsigned index)
{
	return index < sizeof pc_backends / sizeof pc_backends[0] ? &pc_backends[index] : NULL;
}

const pc_source_backend *pc_source_backend_find(const char *scheme)
{
	if (!scheme)
		return NULL;
	for (unsigned i = 0; i < sizeof pc_backends / sizeof pc_backends[0]; i++)
		if (!strcmp(pc_backends[i].scheme, scheme))
			return &pc_backends[i];
	return NULL;
}

int pc_usb3v_list(pc_device_fn fn, void *ctx)
{
#if PC_HAVE_LIBUSB
	return pc_usb3v_enumerate(fn, ctx);
#else
	(void)fn;
	(void)ctx;
	return pc_error(PC_EUNAVAIL,
	                "USB3 Vision diagnosis needs libusb (Debian: libusb-1.0-0-dev, "
	                "then re-run cmake)");
#endif
}
