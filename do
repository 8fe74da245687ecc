#!/usr/bin/env bash
# polarcam set-up and entry points. On a fresh Debian 12 machine as root:
#   ./do demo [DIR]   install build packages, build, render the default scene and run the pipeline
#   ./do test         install build and test packages, build twice (plain and ASan+UBSan,
#                     -Wall -Wextra -Werror) and run the whole test suite in both builds
#   ./do build        install build packages and build (build/)
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
  libcamera-dev"

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
    build/tools/polarcam demo -o "$out" --overwrite
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
    say "tests finished in $((SECONDS - start)) s: $([[ $status == 0 ]] && echo PASSED || echo FAILED)"
    exit $status
    ;;
  *)
    sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'
    [[ $cmd == help || $cmd == -h || $cmd == --help ]] || exit 2
    ;;
esac
