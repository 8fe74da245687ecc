#!/usr/bin/env bash
# Runs the libFuzzer harnesses of a PC_FUZZ build (tests/fuzz/README.md).
#   tests/fuzz/run.sh BUILD_DIR SECONDS [WORK_DIR] [HARNESS...]
# Each harness fuzzes for SECONDS from its checked-in seeds (tests/fuzz/corpus/NAME) plus the
# corpus it grew in WORK_DIR/corpus/NAME earlier (kept between runs, never written back to the
# tree), one harness after the other on one core. Findings (crashes, broken properties, leaks,
# timeouts) go to WORK_DIR/findings/NAME-*. Prints one line per harness: executions, seconds
# of wall clock and of CPU (user + system: on a shared machine at nice 19 the two differ a lot),
# coverage (edges "cov", features "ft"), corpus size, findings; exits 1 when any harness found
# something.
set -uo pipefail
src=$(cd "$(dirname "$0")" && pwd)
build=${1:?usage: run.sh BUILD_DIR SECONDS [WORK_DIR] [HARNESS...]}
secs=${2:?usage: run.sh BUILD_DIR SECONDS [WORK_DIR] [HARNESS...]}
work=${3:-$build/fuzz-work}
shift $(($# < 3 ? $# : 3))
harnesses=("$@")
if ((${#harnesses[@]} == 0)); then
  for f in "$src"/fuzz_*.c; do h=${f##*/fuzz_}; harnesses+=("${h%.c}"); done
fi
mkdir -p "$work/findings"
status=0
printf '%-16s %12s %8s %8s %7s %7s %9s %s\n' harness executions seconds cpu_s cov ft corpus findings
total=0
for h in "${harnesses[@]}"; do
  bin=$build/tests/fuzz_$h
  [[ -x $bin ]] || { echo "$h: $bin not built (cmake --build $build --target fuzz_all)" >&2; status=1; continue; }
  mkdir -p "$work/corpus/$h"
  log=$work/$h.log
  dict=()
  [[ -f $src/$h.dict ]] && dict=(-dict="$src/$h.dict")
  # findings: crash-, leak-, timeout-, oom- artifacts (slow-unit- only marks an input that took
  # more than 10 s of wall clock, which a starved process at nice 19 produces in plenty)
  before=$(ls "$work/findings" | grep -E "^$h-(crash|leak|timeout|oom)-" -c || true)
  start=$SECONDS
  # -timeout: one input may take 20 s (FUZZ_TIMEOUT) at most, wall clock (a hang is a finding;
  # raise it on a loaded machine, where nice 19 starves the process); -rss_limit_mb: memory per
  # input; leaks are findings too (LeakSanitizer, on by default)
  TIMEFORMAT='%U %S'
  { time "$bin" -max_total_time="$secs" -timeout="${FUZZ_TIMEOUT:-20}" -rss_limit_mb=2560 \
    -print_final_stats=1 -artifact_prefix="$work/findings/$h-" "${dict[@]}" "$work/corpus/$h" \
    "$src/corpus/$h" >"$log" 2>&1; } 2>"$work/$h.cpu"
  rc=$?
  cpu=$(awk '{ printf "%.0f", $1 + $2 }' "$work/$h.cpu" 2>/dev/null)
  took=$((SECONDS - start))
  after=$(ls "$work/findings" | grep -E "^$h-(crash|leak|timeout|oom)-" -c || true)
  execs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*$')
  line=$(grep -E '^#[0-9]+' "$log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' <<<"$line" | grep -o '[0-9]*$')
  ft=$(grep -o 'ft: [0-9]*' <<<"$line" | grep -o '[0-9]*$')
  corp=$(grep -o 'corp: [0-9]*' <<<"$line" | grep -o '[0-9]*$')
  new=$((after - before))
  if ((rc != 0 || new > 0)); then
    status=1
    grep -E 'property failed|ERROR: |runtime error|SUMMARY' "$log" | head -5 >&2
  fi
  total=$((total + ${execs:-0}))
  printf '%-16s %12s %8s %8s %7s %7s %9s %s\n' "$h" "${execs:-?}" "$took" "${cpu:-?}" "${cov:-?}" "${ft:-?}" \
    "${corp:-?}" "$new$( ((rc != 0)) && echo " (exit $rc, log $log)")"
done
echo "total executions: $total"
exit $status
