// stokes_pipeline RAW LAYOUT METHOD OUTDIR: the same files as `polarcam process` (stokes.npy,
// dolp.npy, aolp.npy), from C++ through find_package(polarcam).
// It also checks that the library it runs with is the version it was compiled against.
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <polarcam/polarcam.h>

namespace
{

struct failure {
	int rc;
};

void check(int rc)
{
	if (rc)
		throw failure{rc};
}

void save(const std::string &dir, const char *name, const std::vector<float> &a,
          std::vector<size_t> shape)
{
	check(pc_npy_write((dir + "/" + name).c_str(), a.data(), PC_DT_F32,
	                   static_cast<unsigned>(shape.size()), shape.data()));
}

} // namespace

int main(int argc, char **argv)
{
	if (argc != 5) {
		std::fprintf(stderr, "usage: stokes_pipeline RAW LAYOUT METHOD OUTDIR\n");
		return 2;
	}
	if (std::strcmp(pc_version(), PC_VERSION_STRING) != 0) {
		std::fprintf(stderr,
		             "stokes_pipeline: compiled against polarcam %s, runs with %s\n",
		             PC_VERSION_STRING, pc_version());
		return 1;
	}
	pc_view raw{};
	try {
		pc_mosaic mosaic;
		pc_demosaic_method method;
		check(pc_mosaic_parse(argv[2], &mosaic));
		check(pc_demosaic_method_from_name(argv[3], &method));
		check(pc_image_read_mosaic(argv[1], nullptr, 0, &raw, nullptr));
		uint32_t w, h;
		pc_demosaic_out_size(method, raw.width, raw.height, &w, &h);
		const size_t n = size_t(w) * h, row = 3 * size_t(w);
		std::vector<float> s(3 * n), dolp(n), aolp(n);
		pc_stokes_out out{{s.data(), row, 3},
		                  {s.data() + 1, row, 3},
		                  {s.data() + 2, row, 3},
		                  {dolp.data(), w, 1},
		                  {aolp.data(), w, 1}};
		// Default threads, as `polarcam process`: the row-band methods (ri, eari) round
		// differently with another number of bands (differences ~1e-6 relative).
		pc_demosaic_opts opts{};
		check(pc_stokes_from_raw(&raw, &mosaic, method, &opts, &out));
		check(pc_mkdir_p(argv[4]));
		save(argv[4], "stokes.npy", s, {h, w, 3});
		save(argv[4], "dolp.npy", dolp, {h, w});
		save(argv[4], "aolp.npy", aolp, {h, w});
	} catch (const failure &f) {
		std::fprintf(stderr, "stokes_pipeline: %s: %s\n", pc_strerror(f.rc),
		             pc_error_detail());
		pc_view_free(&raw);
		return 1;
	}
	pc_view_free(&raw);
	return 0;
}
