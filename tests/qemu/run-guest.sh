#!/bin/bash
# tests/qemu/run-guest.sh [options] PROGRAM [ARG...]
#
# Boots Debian's own kernel (tests/qemu/kernel.sh) under QEMU software emulation (TCG) with a
# busybox initramfs that holds the kernel modules, PROGRAM (static, or dynamic with the shared
# libraries it needs copied in) and an init that loads the modules, runs PROGRAM ARG... once and
# powers off. The guest's serial console is the test output: PROGRAM prints PASS/FAIL/SKIP
# lines, init prints "GUEST-EXIT <status>".
#
# Options:
#   --cache DIR            kernel cache (default: $PC_QEMU_CACHE or ./qemu-cache)
#   --module "NAME [PARAM=VALUE...]"   load NAME (and its dependencies) with parameters; repeatable
#   --log FILE             console log (default: DIR/console.log)
#   --timeout SECONDS      kill the guest after this long (default 300)
#   --min-pass N           fail unless at least N PASS lines appear (default 1)
#   --env NAME             pass the host's NAME=value into the guest (repeatable)
#   --file SRC:DEST        copy the host file or directory SRC to DEST in the guest (repeatable)
#   --exe SRC:DEST         copy the host executable SRC to DEST with its shared libraries
#
# Exit status: 0 when the guest ran to the end, PROGRAM exited 0, no FAIL line and enough PASS
# lines; 77 when QEMU, busybox-static or the kernel package are missing (reason on stderr) or
# PROGRAM itself exited 77; 1 otherwise. Nothing here opens a network socket: QEMU gets no NIC.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)

skip() { echo "SKIP: $*" >&2; exit 77; }
die() { echo "run-guest.sh: error: $*" >&2; exit 1; }

cache=${PC_QEMU_CACHE:-$PWD/qemu-cache}
log=
timeout_s=300
min_pass=1
modules=()
envs=()
files=()
exes=()
while (($#)); do
	case $1 in
	--cache) cache=$2; shift 2 ;;
	--module) modules+=("$2"); shift 2 ;;
	--log) log=$2; shift 2 ;;
	--timeout) timeout_s=$2; shift 2 ;;
	--min-pass) min_pass=$2; shift 2 ;;
	--env) envs+=("$2"); shift 2 ;;
	--file) files+=("$2"); shift 2 ;;
	--exe) exes+=("$2"); shift 2 ;;
	--) shift; break ;;
	-*) die "unknown option $1" ;;
	*) break ;;
	esac
done
(($# >= 1)) || die "usage: run-guest.sh [options] PROGRAM [ARG...]"
program=$1
shift
[[ -x $program ]] || die "$program: not an executable"

qemu=$(command -v qemu-system-x86_64 || true)
[[ -n $qemu ]] || skip "qemu-system-x86_64 not found (Debian package qemu-system-x86)"
busybox=/bin/busybox
[[ -x $busybox ]] || skip "$busybox not found (Debian package busybox-static)"
command -v cpio >/dev/null || skip "cpio not found"

names=()
for m in "${modules[@]}"; do names+=("${m%% *}"); done
kdir=$("$here/kernel.sh" "$cache" "${names[@]}") # exits 77 itself when the kernel cannot be had
[[ -f $kdir/vmlinuz ]] || die "kernel.sh gave no kernel"
kver=$(cat "$kdir/kernel-version")

work=$(mktemp -d "${TMPDIR:-/tmp}/pc-guest.XXXXXX")
trap 'rm -rf "$work"' EXIT
[[ -n $log ]] || log=$cache/console.log
root=$work/root
mkdir -p "$root"/{bin,dev,proc,sys,tmp,run,lib/modules/"$kver"}
cp -a "$kdir/modules/." "$root/lib/modules/$kver/"

# Executables with their shared libraries (the dynamic loader included) when not static.
add_exe() { # add_exe HOSTPATH GUESTPATH
	cp "$1" "$root$2"
	chmod 755 "$root$2"
	local lib
	if ldd "$1" >/dev/null 2>&1; then
		for lib in $(ldd "$1" | grep -o '/[^ ]*'); do
			[[ -e $root$lib ]] && continue
			mkdir -p "$root$(dirname "$lib")"
			cp -L "$lib" "$root$lib"
		done
	fi
}
add_exe "$busybox" /bin/busybox
for f in "${exes[@]}"; do
	[[ -x ${f%%:*} && ${f#*:} == /* ]] || die "--exe $f: expected an executable SRC and an absolute DEST"
	mkdir -p "$root$(dirname "${f#*:}")"
	add_exe "${f%%:*}" "${f#*:}"
done
for f in "${files[@]}"; do
	src=${f%%:*}
	dst=${f#*:}
	[[ -e $src && $dst == /* ]] || die "--file $f: expected an existing SRC and an absolute DEST"
	mkdir -p "$root$(dirname "$dst")"
	cp -a "$src" "$root$dst"
done
add_exe "$program" /bin/pc-guest-test

# init: PID 1 of the guest.
{
	echo '#!/bin/busybox sh'
	echo '/bin/busybox --install -s /bin'
	echo 'mount -t proc proc /proc; mount -t sysfs sys /sys; mount -t devtmpfs dev /dev'
	# /tmp stays the initramfs's own (writable RAM): shared libraries are copied in at their
	# host paths, and a build under /tmp would vanish beneath a tmpfs mounted there
	echo 'mount -t tmpfs run /run'
	echo 'echo "GUEST-BOOT uptime=$(cut -d" " -f1 /proc/uptime)"'
	while IFS= read -r p; do
		base=${p##*/}
		name=${base%%.ko*}
		params=
		for m in "${modules[@]}"; do
			mn=${m%% *}
			if [[ ${mn//-/_} == "${name//-/_}" && $m == *" "* ]]; then params=${m#* }; fi
		done
		echo "insmod /lib/modules/$kver/$p $params || echo 'FAIL insmod $name'"
	done <"$kdir/load-order"
	echo 'echo "GUEST-MODULES uptime=$(cut -d" " -f1 /proc/uptime)"'
	for e in "${envs[@]}"; do
		[[ -n ${!e:-} ]] && printf 'export %s=%q\n' "$e" "${!e}"
	done
	printf '/bin/pc-guest-test'
	for a in "$@"; do printf ' %q' "$a"; done
	echo
	echo 'echo "GUEST-EXIT $? uptime=$(cut -d" " -f1 /proc/uptime)"'
	echo 'poweroff -f'
} >"$root/init"
chmod 755 "$root/init"
# Uncompressed: decompressing tens of MB under software emulation costs the guest seconds,
# copying them costs nothing.
(cd "$root" && find . | cpio -o -H newc --quiet) >"$work/initramfs.cpio"

# No KVM (nested virtualisation failed here, see docs): TCG. No NIC, no display.
netns=()
if [[ $(id -u) == 0 ]] && command -v unshare >/dev/null && unshare -n true 2>/dev/null; then
	netns=(unshare -n)
fi
t0=$SECONDS
set +e
"${netns[@]}" timeout -k 5 "$timeout_s" "$qemu" -accel tcg -cpu max -smp "${PC_QEMU_SMP:-2}" \
	-m "${PC_QEMU_MEM:-1536}" -nodefaults -no-reboot -display none -nic none \
	-serial "file:$work/console.raw" -kernel "$kdir/vmlinuz" -initrd "$work/initramfs.cpio" \
	-append "console=ttyS0 rdinit=/init panic=-1 oops=panic quiet loglevel=3" </dev/null
qrc=$?
set -e
tr -d '\r' <"$work/console.raw" | sed 's/\x1b\[[0-9;?]*[a-zA-Z]//g' >"$log"
secs=$((SECONDS - t0))
cat "$log"

npass=$(grep -c '^PASS' "$log" || true)
nfail=$(grep -c '^FAIL' "$log" || true)
nskip=$(grep -c '^SKIP' "$log" || true)
gexit=$(sed -n 's/^GUEST-EXIT \([0-9]*\).*/\1/p' "$log" | tail -1)
echo "run-guest.sh: qemu ran ${secs} s (exit $qrc), PASS $npass, FAIL $nfail, SKIP $nskip, guest program exit ${gexit:-none}"
if [[ -z $gexit ]]; then
	((qrc == 124)) && echo "run-guest.sh: FAIL: the guest did not finish within $timeout_s s"
	echo "run-guest.sh: FAIL: the guest program never reported its exit status"
	exit 1
fi
if [[ $gexit == 77 && $nfail == 0 ]]; then
	echo "run-guest.sh: the guest program skipped: $(grep '^SKIP' "$log" | head -3 | tr '\n' ' ')"
	exit 77
fi
if [[ $gexit != 0 || $nfail != 0 || $npass -lt $min_pass ]]; then
	echo "run-guest.sh: FAIL (guest exit $gexit, $nfail FAIL lines, $npass PASS lines, at least $min_pass expected)"
	exit 1
fi
echo "run-guest.sh: OK"
