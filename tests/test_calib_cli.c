/* tests/test_calib_cli.c - polarcam calibrate end to end on rendered recordings of scenes/calib:
 * dark → flat → analyser → show, ECM → states file → polarcam mueller; bad input (too few
 * angles, another ROI, saturated sweep, a singular fit, a corrupt file) exits non-zero naming
 * the problem and writes nothing; the file opens with Python's zipfile (numpy's .npz
 * container) when python3 is there. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "polarcam/calib.h"
#include "run_cli.h"

static char tmp[64];

static bool exists(const char *p)
{
	struct stat st;
	return stat(p, &st) == 0;
}

static const char *P(const char *name)
{
	static char buf[8][1024];
	static int k;
	k = (k + 1) % 8;
	snprintf(buf[k], sizeof buf[k], "%s/%s", tmp, name);
	return buf[k];
}

static int render(const char *scene, const char *out, const char *first, const char *n)
{
	char sp[1024];
	const char *src = getenv("PC_SOURCE_DIR");
	snprintf(sp, sizeof sp, "%s/scenes/calib/%s.json", src ? src : ".", scene);
	return run_cli("render", sp, "-o", P(out), "--roi", "1000,800,32,32", "-n", n, "--first",
	               first, "--no-truth", NULL);
}

int main(void)
{
	const char *src = getenv("PC_SOURCE_DIR");
	char probe[1024];
	snprintf(probe, sizeof probe, "%s/scenes/calib/dark.json", src ? src : ".");
	if (access(probe, R_OK))
		SKIP("%s not found (PC_SOURCE_DIR unset?)", probe);
	if (!run_cli_exe())
		SKIP("POLARCAM (the built CLI) is not set or not executable: run through ctest");
	if (!pc_test_tmpdir(tmp, sizeof tmp, "pc_calib_cli"))
		SKIP("cannot create a temporary directory");

	CHECK_EQ_INT(render("dark", "dark", "0", "8"), 0);
	CHECK_EQ_INT(render("flat_low", "fl", "100", "8"), 0);
	CHECK_EQ_INT(render("flat_high", "fh", "200", "8"), 0);
	CHECK_EQ_INT(render("polarizer_000", "p0", "300", "8"), 0);
	CHECK_EQ_INT(render("polarizer_060", "p60", "400", "8"), 0);
	CHECK_EQ_INT(render("polarizer_120", "p120", "500", "8"), 0);
	CHECK_EQ_INT(render("polarizer_030", "p30", "600", "8"), 0);

	CHECK_EQ_INT(run_cli("calibrate", "dark", P("dark"), "-o", P("d.npz"), "--json", NULL), 0);
	CHECK_EQ_INT(run_cli("calibrate", "flat", P("fl"), P("fh"), "--dark", P("d.npz"), "-o",
	                     P("f.npz"), "--json", NULL),
	             0);
	CHECK_EQ_INT(run_cli("calibrate", "analyser", P("p0"), P("p60"), P("p120"), "--flat",
	                     P("f.npz"), "-o", P("a.npz"), "--json", NULL),
	             0);
	CHECK_EQ_INT(run_cli("calibrate", "show", P("a.npz"), "--pictures", P("pics"), NULL), 0);
	CHECK(exists(P("pics/gain.png")) && exists(P("pics/orientation_error.png")));
	pc_calib c;
	CHECK_EQ_INT(pc_calib_read(P("a.npz"), &c), 0);
	CHECK_EQ_INT(c.parts, PC_CAL_DARK | PC_CAL_FLAT | PC_CAL_ANALYSER);
	CHECK_EQ_INT(c.geo.offset_x, 1000);
	CHECK(c.provenance && strstr(c.provenance, "polarizer_060"));
	pc_calib_free(&c);
	/* explicit angles, the unknown-angles mode */
	CHECK_EQ_INT(run_cli("calibrate", "analyser", P("p0"), P("p60"), P("p120"), "--flat",
	                     P("f.npz"), "--angles", "0,60,120", "-o", P("a2.npz"), NULL),
	             0);
	CHECK_EQ_INT(run_cli("calibrate", "analyser", P("p0"), P("p30"), P("p60"), P("p120"),
	                     "--flat", P("f.npz"), "--unknown-angles", "-o", P("a3.npz"), NULL),
	             0);

	/* bad input: exit status, nothing written */
	CHECK_EQ_INT(run_cli("calibrate", "analyser", P("p0"), P("p60"), "--flat", P("f.npz"), "-o",
	                     P("bad1.npz"), NULL),
	             CLI_STATUS_USAGE);
	CHECK(!exists(P("bad1.npz")));
	CHECK_EQ_INT(run_cli("calibrate", "analyser", P("p0"), P("p60"), P("p120"), "--flat",
	                     P("f.npz"), "--saturation", "1000", "-o", P("bad2.npz"), NULL),
	             CLI_STATUS_USAGE);
	CHECK(!exists(P("bad2.npz")));
	CHECK(run_cli("calibrate", "analyser", P("p0"), P("p60"), P("p120"), "--flat", P("f.npz"),
	              "--angles", "0,90,0", "-o", P("bad3.npz"), NULL) != 0);
	CHECK(!exists(P("bad3.npz")));
	CHECK_EQ_INT(run_cli("calibrate", "analyser", P("p0"), P("p60"), P("p120"), "--flat",
	                     P("f.npz"), "--angles", "0,60", "-o", P("bad4.npz"), NULL),
	             CLI_STATUS_USAGE);
	CHECK(!exists(P("bad4.npz")));
	/* another ROI */
	{
		char sp[1024];
		snprintf(sp, sizeof sp, "%s/scenes/calib/polarizer_120.json", src);
		CHECK_EQ_INT(run_cli("render", sp, "-o", P("moved"), "--roi", "1002,800,32,32",
		                     "-n", "2", "--no-truth", NULL),
		             0);
		CHECK_EQ_INT(run_cli("calibrate", "analyser", P("p0"), P("p60"), P("moved"),
		                     "--flat", P("f.npz"), "-o", P("bad5.npz"), NULL),
		             CLI_STATUS_USAGE);
		CHECK(!exists(P("bad5.npz")));
	}
	/* a corrupt calibration file */
	{
		FILE *f = fopen(P("corrupt.npz"), "wb");
		fputs("PK\003\004 this is not a zip archive", f);
		fclose(f);
		CHECK(run_cli("calibrate", "analyser", P("p0"), P("p60"), P("p120"), "--flat",
		              P("corrupt.npz"), "-o", P("bad6.npz"), NULL) != 0);
		CHECK(!exists(P("bad6.npz")));
		CHECK(run_cli("calibrate", "show", P("corrupt.npz"), NULL) != 0);
	}
	/* a dark file given as --flat */
	CHECK_EQ_INT(run_cli("calibrate", "analyser", P("p0"), P("p60"), P("p120"), "--flat",
	                     P("d.npz"), "-o", P("bad7.npz"), NULL),
	             CLI_STATUS_USAGE);
	CHECK(!exists(P("bad7.npz")));

	/* the .npz opens with Python's zipfile and its members are NumPy 1.0 arrays */
	if (system("python3 -c 'import zipfile' >/dev/null 2>&1") == 0) {
		char cmd[2048];
		snprintf(
		    cmd, sizeof cmd,
		    "python3 -c \"import zipfile, ast, struct, json, sys\n"
		    "z = zipfile.ZipFile('%s')\n"
		    "names = set(z.namelist())\n"
		    "assert {'meta.npy', 'dark.npy', 'gain.npy', 'analysis.npy', 'valid.npy'} <= "
		    "names, names\n"
		    "b = z.read('analysis.npy')\n"
		    "assert b[:6] == b'\\\\x93NUMPY'\n"
		    "h = ast.literal_eval(b[10:10 + struct.unpack('<H', b[8:10])[0]].decode())\n"
		    "assert h['shape'] == (32, 32, 3) and h['descr'] == '<f4', h\n"
		    "m = z.read('meta.npy'); hl = struct.unpack('<H', m[8:10])[0]\n"
		    "meta = json.loads(m[10 + hl:].decode())\n"
		    "assert meta['polarcam_calibration'] == 1 and meta['offset_x'] == 1000, "
		    "meta\n\"",
		    P("a.npz"));
		CHECK_EQ_INT(system(cmd), 0);
	} else {
		printf("python3 not found: the zipfile check is skipped\n");
	}

	/* ECM end to end: references → calibration + states file → polarcam mueller */
	static const char *const refs[4] = {"ecm_air", "ecm_polarizer_000", "ecm_polarizer_090",
	                                    "ecm_retarder_030"};
	for (int i = 0; i < 4; i++)
		CHECK_EQ_INT(render(refs[i], refs[i], "1000", "16"), 0);
	CHECK_EQ_INT(render("ecm_sample", "sample", "2000", "8"), 0);
	char st[1024];
	snprintf(st, sizeof st, "%s/scenes/calib/ecm_nominal_states.json", src);
	CHECK_EQ_INT(run_cli("calibrate", "ecm", "--states", st, "--air", P("ecm_air"),
	                     "--polarizer", P("ecm_polarizer_000"), "--polarizer2",
	                     P("ecm_polarizer_090"), "--retarder", P("ecm_retarder_030"), "--dark",
	                     P("d.npz"), "-o", P("ecm.npz"), "--states-out", P("ecm_states.json"),
	                     "--json", NULL),
	             0);
	CHECK(exists(P("ecm_states.json")));
	CHECK_EQ_INT(
	    run_cli("mueller", P("sample"), "--states", P("ecm_states.json"), "-o", P("m"), NULL),
	    0);
	CHECK(exists(P("m/mueller.npy")));
	/* ECM with a missing reference: usage error, nothing written */
	CHECK_EQ_INT(run_cli("calibrate", "ecm", "--states", st, "--air", P("ecm_air"),
	                     "--polarizer", P("ecm_polarizer_000"), "--retarder",
	                     P("ecm_retarder_030"), "-o", P("bad8.npz"), NULL),
	             CLI_STATUS_USAGE);
	CHECK(!exists(P("bad8.npz")));

	char rm[1200];
	snprintf(rm, sizeof rm, "rm -rf '%s'", tmp);
	if (system(rm))
		fprintf(stderr, "could not remove %s\n", tmp);
	return pc_test_finish("test_calib_cli");
}
