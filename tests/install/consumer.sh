#!/usr/bin/env bash
# tests/install/consumer.sh STATE pkg-config|cmake VERSION CC CXX [FLAGS]: builds, out of tree
# and against the installed polarcam only, the two consumer programs (stokes_raw.c, the example
# of docs/api.md, and consumer/stokes_pipeline.cpp), linked with the shared library and again
# with the static one, and checks that their stokes.npy, dolp.npy and aolp.npy equal those of
# `polarcam process` byte for byte, on a frame that the installed `polarcam render` made.
#   pkg-config: cc ... $(pkg-config --cflags --libs polarcam), and --static for libpolarcam.a
#   cmake:      find_package(polarcam) with polarcam::polarcam / polarcam::polarcam_static
# FLAGS: compiler flags the library was built with that a program must share (the sanitizers).
set -euo pipefail
state=$1 how=$2 version=$3 cc=$4 cxx=$5 flags=${6:-}
here=$(cd "$(dirname "$0")" && pwd)
prefix=$(cat "$state")
fail() { echo "FAIL: $*" >&2; exit 1; }
tmp=$(mktemp -d "${TMPDIR:-/tmp}/polarcam-consumer.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
polarcam=$prefix/bin/polarcam
# nothing from the build tree: only the prefix
unset POLARCAM PC_SOURCE_DIR LD_LIBRARY_PATH

# A raw frame of the built-in scene (12-bit, 320x240 at an even offset: layout 90,45,135,0)
# and the command line's results for two methods: the fused bilinear pass and EARI's row bands.
"$polarcam" render -o "$tmp/rec" --roi 1000,800,320,240 --no-truth >/dev/null 2>&1 ||
  fail "polarcam render"
raw=$tmp/rec/raw_000000.png
layout=90,45,135,0
methods="bilinear eari"
for m in $methods; do
  "$polarcam" process "$raw" --layout $layout --method $m -o "$tmp/cli-$m" >/dev/null ||
    fail "polarcam process --method $m"
done

# Builds the two programs into $tmp/$1 (shared or static).
build() {
  local kind=$1 out=$tmp/$1
  mkdir -p "$out"
  case $how in
    pkg-config)
      export PKG_CONFIG_PATH=$(dirname "$(find "$prefix" -name polarcam.pc | head -1)")
      local cflags libs
      cflags=$(pkg-config --cflags polarcam) || fail "pkg-config --cflags polarcam"
      if [[ $kind == shared ]]; then
        libs=$(pkg-config --libs polarcam) || fail "pkg-config --libs polarcam"
        libs="-Wl,-rpath,$(pkg-config --variable=libdir polarcam) $libs"
      else
        # --static adds Requires.private and Libs.private; -l:libpolarcam.a picks the archive
        libs=$(pkg-config --static --libs polarcam) || fail "pkg-config --static --libs polarcam"
        libs=$(echo "$libs" | sed -E 's/(^| )-lpolarcam( |$)/\1-l:libpolarcam.a\2/')
      fi
      echo "$kind: $cc -std=c11 $cflags stokes_raw.c $libs"
      # the public headers must be clean for users' warnings
      $cc -std=c11 -Wall -Wextra -Werror $flags $cflags "$here/stokes_raw.c" -o "$out/stokes_raw" $libs ||
        fail "$kind build of stokes_raw.c with pkg-config"
      $cxx -std=c++17 -Wall -Wextra -Werror $flags $cflags "$here/consumer/stokes_pipeline.cpp" \
        -o "$out/stokes_pipeline" $libs || fail "$kind build of stokes_pipeline.cpp with pkg-config"
      ;;
    cmake)
      local static=OFF
      [[ $kind == static ]] && static=ON
      cmake -S "$here/consumer" -B "$out/build" -DCMAKE_PREFIX_PATH="$prefix" \
        -DCMAKE_C_COMPILER="$cc" -DCMAKE_CXX_COMPILER="$cxx" -DSTATIC=$static \
        -DEXPECTED_VERSION="$version" -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_C_FLAGS="-Wall -Wextra -Werror $flags" -DCMAKE_CXX_FLAGS="-Wall -Wextra -Werror $flags" \
        -DCMAKE_EXE_LINKER_FLAGS="$flags" >"$out/configure.log" 2>&1 ||
        { cat "$out/configure.log" >&2; fail "$kind: cmake configure with find_package(polarcam)"; }
      grep -F -- "-- polarcam $version from $prefix/" "$out/configure.log" ||
        fail "$kind: find_package did not find polarcam $version in $prefix"
      cmake --build "$out/build" >"$out/build.log" 2>&1 ||
        { cat "$out/build.log" >&2; fail "$kind: cmake --build"; }
      cp "$out/build/stokes_raw" "$out/build/stokes_pipeline" "$out/"
      echo "$kind: built with find_package(polarcam) and polarcam::polarcam$([[ $kind == static ]] && echo _static)"
      ;;
    *) fail "unknown consumer kind $how" ;;
  esac
  # shared: the installed libpolarcam.so; static: no libpolarcam.so at all
  local deps
  deps=$(ldd "$out/stokes_raw" | grep libpolarcam || true)
  if [[ $kind == shared ]]; then
    [[ $(readlink -f "$(echo "$deps" | awk '{print $3}')") == "$(readlink -f "$prefix")"/* ]] ||
      fail "$kind stokes_raw does not use the installed library: $deps"
  else
    [[ -z $deps ]] || fail "static stokes_raw still needs $deps"
  fi
}

status=0
for kind in shared static; do
  build $kind
  for prog in stokes_raw stokes_pipeline; do
    for m in $methods; do
      o=$tmp/$kind-$prog-$m
      "$tmp/$kind/$prog" "$raw" $layout $m "$o" || fail "$kind $prog $m exited $?"
      for f in stokes.npy dolp.npy aolp.npy; do
        if cmp -s "$tmp/cli-$m/$f" "$o/$f"; then
          echo "ok   $kind $prog $m $f: equal to polarcam process ($(stat -c %s "$o/$f") bytes)"
        else
          echo "FAIL $kind $prog $m $f differs from polarcam process: $(cmp "$tmp/cli-$m/$f" "$o/$f" 2>&1 | head -1)" >&2
          status=1
        fi
      done
    done
  done
done
exit $status
