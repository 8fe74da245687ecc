// OpenCV's 16-bit bilinear Bayer demosaicking, for `polarcam bench demosaic` to compare with the
// same frame in the same run. The one C++ file of the benchmarks: extern "C" over caller-owned
// buffers (cv::Mat headers, no copies), exceptions caught.
#include <cstddef>
#include <cstdint>
#include <cstdio>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

extern "C" int pc_bench_opencv_bayer16(const uint16_t *src, size_t src_stride, uint16_t *dst,
                                       size_t dst_stride, int width, int height, int threads,
                                       char *err, size_t err_size);

extern "C" int pc_bench_opencv_bayer16(const uint16_t *src, size_t src_stride, uint16_t *dst,
                                       size_t dst_stride, int width, int height, int threads,
                                       char *err, size_t err_size)
{
	try {
		cv::setNumThreads(threads);
		cv::Mat s(height, width, CV_16UC1, const_cast<uint16_t *>(src), src_stride);
		cv::Mat d(height, width, CV_16UC3, dst, dst_stride);
		cv::cvtColor(s, d, cv::COLOR_BayerBG2BGR); // bilinear, OpenCV's default
		if (d.data != reinterpret_cast<uchar *>(dst)) {
			std::snprintf(err, err_size, "OpenCV reallocated the output");
			return -1;
		}
		return 0;
	} catch (const cv::Exception &e) {
		std::snprintf(err, err_size, "OpenCV: %s", e.what());
		return -1;
	}
}

extern "C" const char *pc_bench_opencv_version(void);
extern "C" const char *pc_bench_opencv_version(void)
{
	return CV_VERSION;
}
