#!/usr/bin/env bash
# bench/ab_render.sh OLD NEW [ROUNDS] - the sensor chain's frame rate of two polarcam builds,
# measured alternately in one run (A B A B ...), so that both see the same machine load.
#
# OLD and NEW are polarcam executables (for example a build of an earlier commit and the
# current one). Each round runs `polarcam bench render --sets default` (the default scene at
# 2448x2048 with every sensor effect: the chain the sim: source runs per frame) in both and
# keeps, per build, the fastest wall time per frame and the least CPU time per frame over the
# rounds: the wall time with all threads, the CPU time with one thread (with several, threads
# that wait for a descheduled peer spin, which a loaded machine turns into CPU time). Prints
# frames/s from both and their ratio, and the load average.
set -euo pipefail
[[ $# -ge 2 ]] || { sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
old=$1 new=$2 rounds=${3:-3}
for b in "$old" "$new"; do [[ -x $b ]] || { echo "ab_render: $b is not executable" >&2; exit 2; }; done
field() { # JSON text, key of the "default" set
  python3 -c 'import json,sys; d=json.loads(sys.argv[1]); s=[x for x in d["sets"] if x["set"]=="default"][0]; print(s[sys.argv[2]])' "$1" "$2"
}
best_old=inf best_new=inf cpu_old=inf cpu_new=inf
min() { python3 -c 'import sys; print(min(float(a) for a in sys.argv[1:]))' "$@"; }
for ((r = 1; r <= rounds; r++)); do
  for which in old new; do
    bin=$old; [[ $which == new ]] && bin=$new
    j=$("$bin" bench render --sets default --frames 5 --repeat 1 --json 2>/dev/null | tail -1)
    f=$(field "$j" frame_s)
    j=$("$bin" bench render --sets default --frames 5 --repeat 1 --json -t 1 2>/dev/null | tail -1)
    c=$(field "$j" frame_cpu_s)
    if [[ $which == old ]]; then best_old=$(min "$best_old" "$f"); cpu_old=$(min "$cpu_old" "$c")
    else best_new=$(min "$best_new" "$f"); cpu_new=$(min "$cpu_new" "$c"); fi
  done
done
python3 - "$best_old" "$best_new" "$cpu_old" "$cpu_new" "$(cut -d' ' -f1-3 /proc/loadavg)" "$(nproc)" <<'PY'
import sys
fo, fn, co, cn = map(float, sys.argv[1:5])
load, ncpu = sys.argv[5], int(sys.argv[6])
print("sensor chain, default scene 2448x2048, every sensor effect (fastest of the rounds):")
print(f"  old: {1/fo:6.1f} frames/s wall, {co*1e3:6.1f} ms CPU per frame on one thread (= {ncpu/co:5.1f} frames/s on {ncpu} idle cores)")
print(f"  new: {1/fn:6.1f} frames/s wall, {cn*1e3:6.1f} ms CPU per frame on one thread (= {ncpu/cn:5.1f} frames/s on {ncpu} idle cores)")
print(f"  new/old: {fo/fn:.2f}x wall, {co/cn:.2f}x CPU; load average {load}")
PY
