#!/usr/bin/env bash
# tests/install/doc_example.sh SRC: the example program printed in docs/api.md is
# tests/install/stokes_raw.c, the one the install_consumer_* tests compile and run.
set -euo pipefail
src=$1
# the lines between "<!-- begin ... -->" + "```c" and "```" + "<!-- end ... -->"
awk '/^<!-- begin tests\/install\/stokes_raw.c -->$/ {on = 1; getline; next}
     /^<!-- end tests\/install\/stokes_raw.c -->$/ {on = 0}
     on' "$src/docs/api.md" | sed '$d' >"${TMPDIR:-/tmp}/pc_doc_example.$$"
trap 'rm -f "${TMPDIR:-/tmp}/pc_doc_example.$$"' EXIT
[[ -s ${TMPDIR:-/tmp}/pc_doc_example.$$ ]] || { echo "FAIL: no example block in docs/api.md" >&2; exit 1; }
if ! diff -u "$src/tests/install/stokes_raw.c" "${TMPDIR:-/tmp}/pc_doc_example.$$"; then
  echo "FAIL: the example in docs/api.md differs from tests/install/stokes_raw.c" >&2
  exit 1
fi
echo "docs/api.md's example = tests/install/stokes_raw.c ($(wc -l <"$src/tests/install/stokes_raw.c") lines)"
