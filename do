#!/usr/bin/env bash
# polarcam set-up and entry points. On a fresh Debian 12 machine as root:
#   ./do demo [DIR]   install build packages, build, render the default scene and run the pipeline
#   ./do test         install build and test packages, build twice (plain and ASan+UBSan,
#                     -Wall -Wextra -Werror) and run the whole test suite in both builds
#   ./do build        install build packages and build (build/)
#   ./do fuzz [SECONDS] [HARNESS...]  build the libFuzzer harnesses (clang) and fuzz each for
#                     SECONDS (default 600) from its corpus (tests/fuzz/README.md)
#   ./do deps [test]  only install the Debian packages
set -euo pipefail
cd "$(dirname "$0")"
JOBS=${JOBS:-$(nproc)}
export DEBIAN_FRONTEND=noninteractive

# Debian 12 packages. Build: compiler, CMake, libraries. Optional backends are auto-detected and
# installed here so that a fresh machine builds everything.
BUILD_PKGS="build-essential cmake pkg-config libpng-dev libtiff-dev libjansson-dev libcairo2-dev
  fonts-dejavu-core
  libaravis-dev aravis-tools-cli libusb-1.0-0-dev libopencv-core-dev libopencv-imgproc-dev
  libopencv-highgui-dev libzip-dev liblapack-dev"
# Tests: network namespaces, the QEMU guest with Debian's kernel and vivid, Xvfb for the window.
TEST_PKGS="iproute2 util-linux qemu-system-x86 busybox-static cpio kmod v4l-utils xvfb xauth x11-apps
  libcamera-dev clang"

say() { printf '\033[1m[polarcam]\033[0m %s\n' "$*" >&2; }

install_pkgs() {
  local missing=()
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  ((${#missing[@]})) || return 0
  local sudo=
  [[ $(id -u) == 0 ]] || sudo=sudo
  say "installing Debian packages: ${missing[*]}"
  if ! $sudo apt-get install -y -q --no-install-recommends "${missing[@]}" >/tmp/polarcam-apt.log 2>&1; then
    $sudo apt-get update -q >>/tmp/polarcam-apt.log 2>&1 || true
    $sudo apt-get install -y -q --no-install-recommends "${missing[@]}" >>/tmp/polarcam-apt.log 2>&1 ||
      { tail -20 /tmp/polarcam-apt.log >&2; say "apt-get failed (log: /tmp/polarcam-apt.log)"; exit 1; }
  fi
}

build() { # build DIR [cmake options...]
  local dir=$1; shift
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@" >"$dir.configure.log" 2>&1 ||
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

cmd=${1:-help}
case $cmd in
  deps)
    install_pkgs $BUILD_PKGS
    [[ ${2:-} == test ]] && install_pkgs $TEST_PKGS
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
    build/tools/polarcam demo -o "$out"
    ;;
  test)
    install_pkgs $BUILD_PKGS $TEST_PKGS
    start=$SECONDS
    say "build 1/2: build-ci (-Wall -Wextra -Werror)"
    # libcamera is off by default; CI asks for it so that the backend is compiled and tested
    build build-ci -DPC_WERROR=ON -DPC_WITH_LIBCAMERA=AUTO
    say "build 2/2: build-asan (AddressSanitizer + UndefinedBehaviorSanitizer)"
    build build-asan -DPC_WERROR=ON -DPC_SANITIZE=ON -DPC_WITH_LIBCAMERA=AUTO
    # The QEMU guest tests boot Debian's own kernel package: fetch it here, with the packages,
    # so that the tests themselves need no network (tests/qemu/kernel.sh caches it per build).
    for dir in build-ci build-asan; do
      tests/qemu/kernel.sh "$dir/qemu-cache" vivid >/dev/null ||
        say "Debian's kernel package could not be fetched: the QEMU guest tests will be skipped"
    done
    status=0
    for dir in build-ci build-asan; do
      say "tests in $dir"
      (cd "$dir" && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
        LSAN_OPTIONS=suppressions=$PWD/../tests/lsan.supp:print_suppressions=0 \
        ctest --output-on-failure -j "$JOBS" --timeout 900) || status=1
    done
    # every libFuzzer harness for a few seconds (the corpora also replay in both builds above:
    # ctest fuzz_replay_*); POLARCAM_FUZZ_SECONDS changes the time per harness
    if have_libfuzzer; then
      say "fuzzing: build-fuzz (clang, libFuzzer + ASan + UBSan)"
      if build_fuzz; then
        tests/fuzz/run.sh build-fuzz "${POLARCAM_FUZZ_SECONDS:-5}" build-fuzz/fuzz-ci || status=1
      else
        say "the fuzz build failed"
        status=1
      fi
    else
      say "clang with libFuzzer not found: the fuzz harnesses were only replayed (fuzz_replay_*)"
    fi
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
    sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'
    [[ $cmd == help || $cmd == -h || $cmd == --help ]] || exit 2
    ;;
esac
