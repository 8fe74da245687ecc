#!/usr/bin/env bash
# tests/install/exports.sh STATE: the installed libpolarcam.so exports exactly the functions that
# the installed headers declare (PC_API), all named pc_*, and nothing else: no internal helper
# leaks out, and no declared function is missing.
#
# The declarations come from the compiler, not from cmake/pc_api.py's parse: GCC's -aux-info
# lists every function prototype that <polarcam/polarcam.h> brings in, with the file it is in.
set -euo pipefail
state=$1
prefix=$(cat "$state")
fail() { echo "FAIL: $*" >&2; exit 1; }
gcc=$(command -v gcc || true)
[[ -n $gcc ]] || { echo "SKIP: needs gcc for -aux-info"; exit 77; }
command -v nm >/dev/null || { echo "SKIP: needs nm (binutils)"; exit 77; }
tmp=$(mktemp -d "${TMPDIR:-/tmp}/polarcam-exports.XXXXXX")
trap 'rm -rf "$tmp"' EXIT

so=$(find "$prefix" -name 'libpolarcam.so' | head -1)
[[ -n $so ]] || fail "no libpolarcam.so under $prefix"
inc=$prefix/include

printf '#include <polarcam/polarcam.h>\n' >"$tmp/all.c"
"$gcc" -std=c11 -fsyntax-only -aux-info "$tmp/aux.txt" -I"$inc" "$tmp/all.c"
# lines: /* FILE:LINE:NC */ extern TYPE NAME (ARGS);   (NC: a declaration; NF: a definition,
# i.e. the static inline helpers, which are not exported)
grep -F "/* $inc/polarcam/" "$tmp/aux.txt" | grep -E ':NC \*/ extern ' |
  sed -E 's/^.*\*\/ extern [^(]*[ *]([A-Za-z_][A-Za-z0-9_]*) \(.*$/\1/' | sort -u >"$tmp/declared"
# defined dynamic symbols: T (text), D/B/R (data), W/V (weak), u (unique), i (ifunc)
nm -D --defined-only "$so" | awk 'NF == 3 {print $3}' | sort -u >"$tmp/exported"

nd=$(wc -l <"$tmp/declared") ne=$(wc -l <"$tmp/exported")
echo "declared in $inc/polarcam: $nd functions; exported by $(basename "$so"): $ne symbols"
(( nd > 100 )) || fail "only $nd declarations found: the header parse is broken"
status=0
if grep -v '^pc_' "$tmp/exported" >"$tmp/foreign"; then
  echo "FAIL: exported symbols without the pc_ prefix:" >&2; sed 's/^/  /' "$tmp/foreign" >&2; status=1
fi
if comm -13 "$tmp/declared" "$tmp/exported" | grep '^pc_' >"$tmp/undeclared"; then
  echo "FAIL: exported but declared in no installed header (internal: drop PC_API / hide it):" >&2
  sed 's/^/  /' "$tmp/undeclared" >&2; status=1
fi
if comm -23 "$tmp/declared" "$tmp/exported" >"$tmp/missing" && [[ -s $tmp/missing ]]; then
  echo "FAIL: declared in an installed header but not exported (missing PC_API: run cmake/pc_api.py; or not implemented):" >&2
  sed 's/^/  /' "$tmp/missing" >&2; status=1
fi
((status == 0)) && echo "exports = declarations: $ne pc_ functions"
exit $status
