#!/usr/bin/env bash
# tests/install/install.sh BUILD STATE VERSION: `cmake --install BUILD` into a new prefix under
# $TMPDIR, checks what was installed, and records the prefix in the file STATE for the tests
# that use it (install_exports, install_consumer_*; ctest fixture "installed"). cleanup.sh
# removes it.
set -euo pipefail
build=$1 state=$2 version=$3
src=$(cd "$(dirname "$0")/../.." && pwd)
prefix=$(mktemp -d "${TMPDIR:-/tmp}/polarcam-install.XXXXXX")
echo "$prefix" >"$state"
fail() { echo "FAIL: $*" >&2; exit 1; }

cmake --install "$build" --prefix "$prefix" >"$prefix.log" 2>&1 || { cat "$prefix.log" >&2; fail "cmake --install"; }
rm -f "$prefix.log"
echo "installed into $prefix"

# Headers: exactly the layers' public headers plus the generated version.h and polarcam.h
# (nothing from beside the sources: internal headers stay internal).
inc=$prefix/include/polarcam
[[ -d $inc ]] || fail "no $inc"
expected=$( (cd "$src" && ls core/include/polarcam/*.h io/include/polarcam/*.h sim/include/polarcam/*.h \
  devices/include/polarcam/*.h calib/include/polarcam/*.h 2>/dev/null | xargs -n1 basename
  echo version.h; echo polarcam.h) | sort)
got=$(ls "$inc" | sort)
[[ $got == "$expected" ]] || fail "installed headers differ from the public ones: $(diff <(echo "$expected") <(echo "$got") | tr '\n' ' ')"
echo "headers: $(echo "$got" | wc -l) public headers, no internal ones"
grep -q "#define PC_VERSION_STRING \"$version\"" "$inc/version.h" || fail "version.h does not say $version"

# Libraries: the shared one with its SONAME links, the static one, the CMake package and .pc.
lib=$(dirname "$(find "$prefix" -name 'libpolarcam.so' | head -1)")
[[ -n $lib && -d $lib ]] || fail "no libpolarcam.so"
real=$(readlink -f "$lib/libpolarcam.so")
[[ $(basename "$real") == "libpolarcam.so.$version" ]] || fail "libpolarcam.so points to $real, not libpolarcam.so.$version"
soname=$(objdump -p "$real" | awk '$1 == "SONAME" {print $2}')
[[ -e $lib/$soname ]] || fail "SONAME $soname is not installed"
[[ -f $lib/libpolarcam.a ]] || fail "no libpolarcam.a"
[[ -f $lib/pkgconfig/polarcam.pc ]] || fail "no polarcam.pc"
grep -qx "prefix=$prefix" "$lib/pkgconfig/polarcam.pc" || fail "polarcam.pc does not name the install prefix"
for f in polarcamConfig.cmake polarcamConfigVersion.cmake polarcamTargets.cmake; do
  [[ -f $lib/cmake/polarcam/$f ]] || fail "no $lib/cmake/polarcam/$f"
done
echo "library: $(basename "$real"), SONAME $soname, libpolarcam.a, polarcam.pc, polarcamConfig.cmake"

# The command, run from the prefix (it finds its library through its RUNPATH, $ORIGIN-relative).
out=$(env -u LD_LIBRARY_PATH "$prefix/bin/polarcam" --version) || fail "installed polarcam --version"
[[ $out == "polarcam $version (library built by "*")" ]] || fail "polarcam --version says '$out', expected 'polarcam $version (library built by ...)'"
used=$(ldd "$prefix/bin/polarcam" | awk '$1 ~ /^libpolarcam\.so/ {print $3}')
[[ -n $used && $(readlink -f "$used") == "$real" ]] ||
  fail "installed polarcam does not use $real: $(ldd "$prefix/bin/polarcam" | grep polarcam)"
echo "command: $out, linked with $lib/$soname"
