// polarcam/display.h through OpenCV highgui: the only C++ of the devices layer. Every entry
// point catches exceptions and answers an error code; images are wrapped, not copied.
#include "polarcam/display.h"

#include <opencv2/core.hpp>
#include <opencv2/highgui.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdlib>
#include <new>
#include <string>

#include "polarcam/error.h"

struct pc_display {
	std::string title;
	cv::Mat bgr;
	int w = 0, h = 0; // the window's size, kept equal to the picture's
};

extern "C" bool pc_display_available(void)
{
	return true;
}

extern "C" int pc_display_open(pc_display **out, const char *title)
{
	*out = nullptr;
	if (!std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY"))
		return pc_error(PC_EUNAVAIL,
		                "no display: $DISPLAY is not set (run under X, or Xvfb)");
	pc_display *d = new (std::nothrow) pc_display;
	if (!d)
		return pc_error(PC_ENOMEM, "window");
	try {
		d->title = title ? title : "polarcam";
		// GUI_NORMAL: no Qt toolbar or status bar. The window is sized to each picture
		// explicitly (resizeWindow) so that it shows at 1:1: Qt's AUTOSIZE does not always
		// follow the picture without a window manager.
		cv::namedWindow(d->title,
		                cv::WINDOW_NORMAL | cv::WINDOW_GUI_NORMAL | cv::WINDOW_KEEPRATIO);
	} catch (const std::exception &e) {
		delete d;
		return pc_error(PC_EIO, "cannot open a window: %s", e.what());
	}
	*out = d;
	return 0;
}

extern "C" int pc_display_show(pc_display *d, const uint8_t *rgb, uint32_t width, uint32_t height,
                               size_t stride, const char *overlay)
{
	if (!d || !rgb || !width || !height || stride < (size_t)width * 3)
		return pc_error(PC_EINVAL, "display: bad image");
	try {
		cv::Mat in((int)height, (int)width, CV_8UC3, const_cast<uint8_t *>(rgb), stride);
		cv::cvtColor(in, d->bgr, cv::COLOR_RGB2BGR);
		if (overlay && *overlay) {
			// black on the white status strip the viewer leaves above its panels
			cv::putText(d->bgr, overlay, cv::Point(8, 22), cv::FONT_HERSHEY_SIMPLEX,
			            0.6, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
		}
		if ((int)width != d->w || (int)height != d->h) {
			cv::resizeWindow(d->title, (int)width, (int)height);
			d->w = (int)width;
			d->h = (int)height;
		}
		cv::imshow(d->title, d->bgr);
		int key = cv::waitKey(1);
		if (cv::getWindowProperty(d->title, cv::WND_PROP_AUTOSIZE) < 0)
			return pc_error(PC_ECANCELED, "the window was closed");
		return key < 0 ? -1 : key & 0xff;
	} catch (const std::exception &e) {
		return pc_error(PC_EIO, "display: %s", e.what());
	}
}

extern "C" void pc_display_close(pc_display *d)
{
	if (!d)
		return;
	try {
		cv::destroyWindow(d->title);
		cv::waitKey(1);
	} catch (...) {
	}
	delete d;
}
