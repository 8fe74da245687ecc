#!/bin/bash
# tests/qemu/v4l2-guest.sh CACHE SIMFRAMES GUEST POLARCAM [run-guest.sh options...]
#
# The v4l2_guest test: renders simulated raw frames on the host with SIMFRAMES (the project's
# simulator; cached in CACHE/simframes until SIMFRAMES is rebuilt), then boots the guest
# (run-guest.sh) with vivid and GUEST, which gets the frames under /sim and the polarcam command
# line (POLARCAM, copied with its shared libraries) as /bin/polarcam. Exit 77 when QEMU or the
# kernel package are unavailable (checked before spending time on rendering).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
(($# >= 4)) || { echo "usage: v4l2-guest.sh CACHE SIMFRAMES GUEST POLARCAM [options]" >&2; exit 2; }
cache=$1 simframes=$2 guest=$3 cli=$4
shift 4

command -v qemu-system-x86_64 >/dev/null || { echo "SKIP: qemu-system-x86_64 not found (Debian package qemu-system-x86)" >&2; exit 77; }
"$here/kernel.sh" "$cache" vivid >/dev/null # exits 77 with the reason when the kernel cannot be had

frames=$cache/simframes
if [[ ! -f $frames/sim.txt || $simframes -nt $frames/sim.txt ]]; then
	rm -rf "$frames"
	t0=$SECONDS
	"$simframes" "$frames" 3 7
	echo "v4l2-guest.sh: simulator frames rendered in $((SECONDS - t0)) s"
fi
exec "$here/run-guest.sh" --cache "$cache" --file "$frames:/sim" --exe "$cli:/bin/polarcam" "$@" \
	"$guest" --sim /sim --cli /bin/polarcam
