#!/usr/bin/env bash
# polarcam set-up and entry points. On a fresh Debian 12 machine as root:
#   ./do demo [DIR]   install build packages, build, render the default scene and run the pipeline
#   ./do test         install build and test packages, build twice with -Wall -Wextra -Werror
#                     (clang Release, GCC ASan+UBSan), run the whole test suite in the GCC
#                     build and in the clang one the compiler-dependent part and what needs a
#                     binary without sanitizers (with the pip-built module: GCC Release again)
#   ./do build        install build packages and build (build/)
#   ./do fuzz [SECONDS] [HARNESS...]  build the libFuzzer harnesses (clang) and fuzz each for
#                     SECONDS (default 600) from its corpus (tests/fuzz/README.md)
#   ./do cross        build for AArch64 (64-bit ARM) with Debian's cross compiler and the arm64
#                     libraries (adds dpkg's arm64 architecture), run the test suite under
#                     qemu-aarch64 (build-aarch64/; not part of ./do test: about half an hour)
#   ./do format-check list the files that differ from .clang-format (exit 1 if any)
#   ./do format       reformat them in place
#   ./do deps [test]  only install the Debian packages
set -euo pipefail
cd "$(dirname "$0")"
JOBS=${JOBS:-$(nproc)}
export DEBIAN_FRONTEND=noninteractive

# Debian 12 packages. Build: compiler, CMake, libraries. Optional backends are auto-detected and
# installed here so that a fresh machine builds everything.
BUILD_PKGS="build-essential cmake pkg-config libpng-dev libtiff-dev libjansson-dev libcairo2-dev nettle-dev
  fonts-dejavu-core
  libaravis-dev aravis-tools-cli libusb-1.0-0-dev libopencv-core-dev libopencv-imgproc-dev
  libopencv-highgui-dev libzip-dev liblapack-dev
  python3-dev python3-numpy"
# Tests: network namespaces, the QEMU guest with Debian's kernel and vivid, Xvfb for the window;
# a single-node Slurm cluster (tests/slurm.sh starts its own daemons; none run otherwise);
# libudev-dev for `pkg-config --static --libs polarcam` (libusb-1.0.pc names -ludev); clang and
# its OpenMP runtime for the clang build; pytest and pip (the Python module's tests and its
# offline pip install).
TEST_PKGS="iproute2 util-linux qemu-system-x86 busybox-static cpio kmod v4l-utils xvfb xauth x11-apps
  libcamera-dev libudev-dev clang libomp-dev python3-pytest python3-pip python3-setuptools
  slurmctld slurmd slurm-client munge"
# Formatting: ./do format, ./do format-check.
FORMAT_PKGS="clang-format git"
# ./do cross: the cross compiler and the user-mode emulator on the host; the libraries the build
# links (and the runtimes the emulated tests load: libgomp1, libstdc++6) as arm64 packages.
CROSS_HOST_PKGS="cmake pkg-config gcc-aarch64-linux-gnu g++-aarch64-linux-gnu qemu-user"
CROSS_ARM64_PKGS="libc6-dev libgomp1 libstdc++6 libpng-dev libtiff-dev libjansson-dev libcairo2-dev
  nettle-dev libzip-dev liblapack-dev"

# apt-get and dpkg run as root: through sudo for another user
SUDO=
[[ $(id -u) == 0 ]] || SUDO=sudo

say() { printf '\033[1m[polarcam]\033[0m %s\n' "$*" >&2; }

install_pkgs() {
  local missing=()
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  ((${#missing[@]})) || return 0
  say "installing Debian packages: ${missing[*]}"
  if ! $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}" >/tmp/polarcam-apt.log 2>&1; then
    $SUDO apt-get update -q >>/tmp/polarcam-apt.log 2>&1 || true
    $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}" >>/tmp/polarcam-apt.log 2>&1 ||
      { tail -20 /tmp/polarcam-apt.log >&2; say "apt-get failed (log: /tmp/polarcam-apt.log)"; exit 1; }
  fi
}

build() { # build DIR [cmake options...]
  local dir=$1; shift
  # The Python module is built for Debian's interpreter, the one python3-numpy is installed for
  # (another python3 first on PATH, a pyenv or a venv, may lack NumPy).
  local py=()
  [[ -x /usr/bin/python3 ]] && py=(-DPython3_EXECUTABLE=/usr/bin/python3)
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo "${py[@]}" "$@" >"$dir.configure.log" 2>&1 ||
    { mkdir -p "$dir"; cat "$dir.configure.log" >&2; exit 1; }
  # show warnings and errors, not the progress lines; pipefail keeps cmake's exit status
  if ! cmake --build "$dir" -j "$JOBS" 2>&1 |
    { grep -vE '^\[ *[0-9]+%\]|^(Consolidate|Scanning|Built target)' || true; } >&2; then
    say "build failed in $dir"
    exit 1
  fi
}

# The libFuzzer build (tests/fuzz.cmake): clang with -fsanitize=fuzzer,address,undefined on
# everything, asserts on (-O1 -g, no NDEBUG), no optional backends (no hardware, no threads).
have_libfuzzer() {
  command -v clang >/dev/null 2>&1 &&
    [[ -n $(find "$(clang -print-resource-dir 2>/dev/null)" -name 'libclang_rt.fuzzer-*.a' 2>/dev/null) ]]
}
build_fuzz() {
  local dir=build-fuzz
  CC=clang CXX=clang++ cmake -S . -B $dir -DCMAKE_BUILD_TYPE=Fuzz -DCMAKE_C_FLAGS="-O1 -g" \
    -DCMAKE_CXX_FLAGS="-O1 -g" -DPC_FUZZ=ON -DPC_WERROR=OFF -DPC_WITH_ARAVIS=OFF \
    -DPC_WITH_OPENCV=OFF -DPC_WITH_LIBUSB=OFF -DPC_WITH_OPENMP=OFF -DPC_WITH_LIBCAMERA=OFF \
    >"$dir.configure.log" 2>&1 || { mkdir -p $dir; cat "$dir.configure.log" >&2; return 1; }
  cmake --build $dir -j "$JOBS" --target fuzz_all 2>&1 |
    { grep -vE '^\[ *[0-9]+%\]|^(Consolidate|Scanning|Built target)|warning|note:|^ |^In file' || true; } >&2
  [[ ${PIPESTATUS[0]} == 0 ]]
}

# The C, C++ and kernel-fragment sources of the project, as git knows them.
format_files() {
  git ls-files -- '*.c' '*.h' '*.cpp' '*.inc' '*.h.in'
}

# ctest -E regex of the tests that the clang build leaves to the sanitizers' build (see ./do
# test): the system-level ones (QEMU guest, GigE Vision peers, X window, device listing) and the
# long end-to-end runs (kills, the bad-input table, capture faults, Slurm), which exercise the
# same library code as there and take most of the suite's time. test_cli_conventions (files,
# exit statuses, JSON lines, help examples, batch bytes against single runs of the same binary)
# and python_cli (the module against the CLI, both calling the same library functions) compare
# a build with itself: the compiler does not enter.
CLANG_SKIP='^(v4l2_guest|devices_gige_.*|devices_bench_smoke|devices_view_xvfb|devices_list|test_interrupt|test_bad_input|test_capture_faults|dataset_slurm|test_cli_conventions|python_cli)$'
# The GCC suite runs once, under AddressSanitizer + UndefinedBehaviorSanitizer (build-asan),
# without what needs a binary without the sanitizers, which the clang build runs: the soak (RSS
# is judged only without ASan, whose quarantine grows), the Python package built by pip and the
# module's memory loop (leaks measured without ASan), and the installed library as users get it
# (install prefix, consumers, the docs' example).
PLAIN_ONLY='^(devices_soak|python_pip|python_memory|install_.*|api_doc_example)$'

# ctest -E regex of the tests ./do cross leaves out: those that install the library and build
# programs against it with the host's compiler (install_*, api_doc_example), the system-level
# ones (QEMU guest, cameras, Slurm, libcamera), whose backends the cross build does not have, and
# test_v4l2, whose device calls qemu-aarch64 does not pass on (it answers ENOSYS to V4L2 ioctls).
CROSS_SKIP='^(install_.*|api_doc_example|v4l2_guest|test_v4l2|devices_.*|dataset_slurm|test_libcamera.*)$'

# The files among them that clang-format would change.
format_differs() {
  format_files | xargs -d '\n' -P "$JOBS" -n 16 sh -c \
    'for f; do clang-format --dry-run --Werror "$f" >/dev/null 2>&1 || echo "$f"; done' sh | sort
}

cmd=${1:-help}
case $cmd in
  deps)
    install_pkgs $BUILD_PKGS
    if [[ ${2:-} == test ]]; then install_pkgs $TEST_PKGS; fi
    ;;
  build)
    install_pkgs $BUILD_PKGS
    build build
    say "built build/tools/polarcam"
    ;;
  demo)
    install_pkgs $BUILD_PKGS
    build build
    out=${2:-polarcam-demo}
    say "running: build/tools/polarcam demo -o $out"
    build/tools/polarcam demo -o "$out" --overwrite
    ;;
  cross)
    install_pkgs $CROSS_HOST_PKGS
    if ! dpkg --print-foreign-architectures | grep -qx arm64; then
      say "adding dpkg's arm64 architecture (multiarch) for the arm64 libraries"
      $SUDO dpkg --add-architecture arm64
      $SUDO apt-get update -q >/tmp/polarcam-apt.log 2>&1 ||
        { tail -20 /tmp/polarcam-apt.log >&2; say "apt-get update failed"; exit 1; }
    fi
    # shellcheck disable=SC2046
    install_pkgs $(printf '%s:arm64 ' $CROSS_ARM64_PKGS)
    build build-aarch64 -DCMAKE_TOOLCHAIN_FILE="$PWD/cmake/toolchain-aarch64.cmake" \
      -DPC_WITH_ARAVIS=OFF -DPC_WITH_LIBUSB=OFF -DPC_WITH_OPENCV=OFF -DPC_WITH_PYTHON=OFF \
      -DPC_WITH_LIBCAMERA=OFF -DPC_WERROR=ON
    say "running the tests under qemu-aarch64 (build-aarch64/)"
    ctest --test-dir build-aarch64 -j "$JOBS" -E "$CROSS_SKIP" --output-on-failure
    say "AArch64 build: all tests passed under qemu-aarch64"
    ;;
  format-check)
    install_pkgs $FORMAT_PKGS
    mapfile -t bad < <(format_differs)
    if ((${#bad[@]})); then
      printf '%s\n' "${bad[@]}"
      say "${#bad[@]} of $(format_files | wc -l) files differ from .clang-format (./do format fixes them)"
      exit 1
    fi
    say "all $(format_files | wc -l) files follow .clang-format"
    ;;
  format)
    install_pkgs $FORMAT_PKGS
    # clang-format 14 needs a second pass on a few files (aligned macros after a reflow)
    for pass in 1 2 3; do
      mapfile -t bad < <(format_differs)
      ((${#bad[@]})) || break
      say "pass $pass: formatting ${#bad[@]} files"
      printf '%s\n' "${bad[@]}" | xargs -d '\n' clang-format -i
    done
    mapfile -t bad < <(format_differs)
    ((${#bad[@]} == 0)) || { printf '%s\n' "${bad[@]}"; say "still not stable after 3 passes"; exit 1; }
    say "all $(format_files | wc -l) files follow .clang-format"
    ;;
  test)
    install_pkgs $BUILD_PKGS $TEST_PKGS $FORMAT_PKGS
    # formatting first: it takes seconds, and a file off .clang-format fails the run
    mapfile -t bad < <(format_differs)
    if ((${#bad[@]})); then
      printf '%s\n' "${bad[@]}"
      say "${#bad[@]} files differ from .clang-format (./do format fixes them)"
      exit 1
    fi
    say "format: all $(format_files | wc -l) files follow .clang-format"
    start=$SECONDS
    # the time of each step, with the load average when it ended (the machine may be shared)
    laps=() mark=$SECONDS
    lap() {
      laps+=("$1 $((SECONDS - mark)) s (load $(cut -d' ' -f1 /proc/loadavg))")
      mark=$SECONDS
    }
    # Two builds on two cores. clang in Release as users build it runs everything whose result
    # depends on the compiler and what needs a binary without sanitizers (the soak, the Python
    # module's memory loop, the installed library, and python_pip, which builds the library and
    # the module once more through pip with GCC in Release, here with -Werror); GCC with the
    # sanitizers runs the whole suite. (Until ci61 a third build, GCC in Release, ran only that
    # plain part: 110-136 s of build for what the pip build and the clang build cover.)
    # What waits on the network or on a clock runs beside a build, and that build is niced so
    # that the tests keep their share of the CPU and the compiler fills the rest.
    # The guest tests boot Debian's own kernel package: fetched now, beside the builds, so that
    # the tests themselves need no network (tests/qemu/kernel.sh caches it per build). Only
    # build-asan boots it.
    (tests/qemu/kernel.sh build-asan/qemu-cache vivid >/dev/null ||
      say "Debian's kernel package could not be fetched: the QEMU guest tests will be skipped") &
    kernel_pid=$!
    status=0
    # OpenMP threads sleep while they wait: with two tests side by side on two cores, spinning
    # threads burn the CPU the other test needs (tests/CMakeLists.txt sets it per test too)
    export OMP_WAIT_POLICY=PASSIVE
    # libcamera (CI builds its backend) loads lttng-ust, whose constructor reads the ELF headers
    # of every library in the process (some 14 000 read and lseek calls): 0.11 -> 0.08 s of the
    # plain CLI's start-up without it, 0.28 -> 0.24 s under the sanitizers, paid by every test
    # that runs the CLI (about a thousand runs). Nothing here traces: lttng-ust's switch is off.
    export LTTNG_UST_WITHOUT_BADDR_STATEDUMP=1
    # python_pip's build of the library with GCC in Release: warnings are errors there too
    export POLARCAM_CMAKE_ARGS="-DPC_WERROR=ON${POLARCAM_CMAKE_ARGS:+ $POLARCAM_CMAKE_ARGS}"
    ctest_in() { # ctest_in DIR ctest-options...: the suite in DIR with the sanitizers' settings
      local dir=$1; shift
      (cd "$dir" && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
        LSAN_OPTIONS=suppressions=$PWD/../tests/lsan.supp:print_suppressions=0 \
        ctest --output-on-failure -j "$JOBS" --timeout 900 "$@")
    }
    say "build 1/2: build-clang (clang, Release as users build it, -Wall -Wextra -Werror)"
    # libcamera is off by default; CI asks for it so that the backend is compiled and tested
    if (CC=clang CXX=clang++ build build-clang -DCMAKE_BUILD_TYPE=Release -DPC_WERROR=ON \
      -DPC_WITH_LIBCAMERA=AUTO); then
      lap "build build-clang"
      say "tests in build-clang, without $CLANG_SKIP (beside build 2/2; their output follows it)"
      ctest_in build-clang -E "$CLANG_SKIP" >build-clang.tests.log 2>&1 &
      clang_pid=$!
    else
      lap "build build-clang (failed)"
      status=1 clang_pid=
    fi
    say "build 2/2: build-asan (GCC, AddressSanitizer + UndefinedBehaviorSanitizer; niced)"
    # -g1: line tables only (the sanitizers' reports keep file:line), a third less compile time
    # than -g's full debug information
    asan_ok=1
    (renice -n 10 -p $BASHPID >/dev/null
      build build-asan -DPC_WERROR=ON -DPC_SANITIZE=ON -DPC_WITH_LIBCAMERA=AUTO \
        -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG") ||
      asan_ok=0
    lap "build build-asan$( ((asan_ok)) || echo ' (failed)')"
    if [[ -n $clang_pid ]]; then
      wait $clang_pid || status=1
      cat build-clang.tests.log
      lap "tests in build-clang (the rest of them)"
    fi
    wait $kernel_pid || true
    lap "QEMU kernel cache (the rest of it)"
    if ((asan_ok)); then
      say "tests in build-asan (the whole suite but what needs a binary without sanitizers)"
      ctest_in build-asan -E "$PLAIN_ONLY" || status=1
      lap "tests in build-asan"
    else
      status=1
    fi
    # every libFuzzer harness for POLARCAM_FUZZ_SECONDS seconds (the corpora also replay in the
    # builds above: ctest fuzz_replay_*)
    # Only when asked (POLARCAM_FUZZ_SECONDS): the fuzz build is a fourth full build, and CI
    # has 20 minutes; `./do fuzz` runs the campaigns.
    if [[ -z ${POLARCAM_FUZZ_SECONDS:-} ]]; then
      say "fuzzing: the corpora were replayed (fuzz_replay_*); POLARCAM_FUZZ_SECONDS=N fuzzes too"
    elif have_libfuzzer; then
      say "fuzzing: build-fuzz (clang, libFuzzer + ASan + UBSan)"
      if build_fuzz; then
        tests/fuzz/run.sh build-fuzz "${POLARCAM_FUZZ_SECONDS:-5}" build-fuzz/fuzz-ci || status=1
        lap "fuzzing in build-fuzz"
      else
        lap "build build-fuzz (failed)"
        status=1
      fi
    else
      say "clang with libFuzzer not found: the fuzz harnesses were only replayed (fuzz_replay_*)"
    fi
    for l in "${laps[@]}"; do say "  $l"; done
    say "tests finished in $((SECONDS - start)) s: $([[ $status == 0 ]] && echo PASSED || echo FAILED)"
    exit $status
    ;;
  fuzz)
    install_pkgs $BUILD_PKGS clang
    have_libfuzzer || { say "clang's libFuzzer runtime is missing (Debian: clang)"; exit 1; }
    build_fuzz || { say "the fuzz build failed"; exit 1; }
    secs=${2:-600}
    shift $(($# < 2 ? $# : 2))
    say "fuzzing each harness for $secs s (corpora kept in build-fuzz/fuzz-work)"
    tests/fuzz/run.sh build-fuzz "$secs" build-fuzz/fuzz-work "$@"
    ;;
  *)
    sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//'
    [[ $cmd == help || $cmd == -h || $cmd == --help ]] || exit 2
    ;;
esac
