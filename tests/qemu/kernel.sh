#!/bin/bash
# tests/qemu/kernel.sh CACHE_DIR MODULE...
#
# Makes CACHE_DIR/<kernel version>/ hold Debian's own kernel - the linux-image-<version> package
# that linux-image-amd64 depends on, fetched with `apt-get download` - reduced to what a test guest
# needs: vmlinuz, the named modules and every module they depend on (resolved from the
# modules.dep that depmod writes for the unpacked package), and `load-order`, one module path per
# line with dependencies first. Prints that directory on stdout.
#
# A second run with the same kernel version and module list reuses the cache and touches no
# network. Exit status 77 (with the reason on stderr) when the kernel package cannot be had.
set -euo pipefail

skip() { echo "SKIP: $*" >&2; exit 77; }
die() { echo "kernel.sh: error: $*" >&2; exit 1; }

(($# >= 2)) || die "usage: kernel.sh CACHE_DIR MODULE..."
cache=$1
shift
mods=("$@")

command -v apt-cache >/dev/null || skip "apt-cache not found: the guest kernel comes from Debian's packages"
command -v dpkg-deb >/dev/null || skip "dpkg-deb not found"
depmod=$(command -v depmod || echo /sbin/depmod)
[[ -x $depmod ]] || skip "depmod not found (Debian package kmod)"

kpkg=$(apt-cache depends linux-image-amd64 2>/dev/null | awk '/Depends: linux-image-[0-9]/ { print $2; exit }')
[[ -n $kpkg ]] || skip "apt-cache does not know which kernel linux-image-amd64 depends on (apt-get update needed?)"
kver=${kpkg#linux-image-}
dir=$cache/$kver
key="$kpkg ${mods[*]}"

if [[ -f $dir/stamp && $(cat "$dir/stamp") == "$key" ]]; then
	echo "$dir"
	exit 0
fi

mkdir -p "$cache"
tmp=$(mktemp -d "$cache/.kernel.XXXXXX")
trap 'rm -rf "$tmp"' EXIT

if ! (cd "$tmp" && apt-get download "$kpkg") >"$tmp/download.log" 2>&1; then
	skip "apt-get download $kpkg failed (no network or no package index?): $(grep -E '^(E|Err):' "$tmp/download.log" | head -2 | tr '\n' ' ')"
fi
deb=$(ls "$tmp"/linux-image-*.deb 2>/dev/null | head -1)
[[ -n $deb ]] || skip "apt-get download $kpkg produced no .deb"

# The package unpacks to ~400 MB; only vmlinuz and a few modules are kept.
mkdir -p "$tmp/k"
dpkg-deb -x "$deb" "$tmp/k"
rm -f "$deb"
kmods=$tmp/k/lib/modules/$kver
[[ -f $tmp/k/boot/vmlinuz-$kver && -d $kmods ]] || die "$kpkg does not hold boot/vmlinuz-$kver and lib/modules/$kver"
"$depmod" -b "$tmp/k" "$kver" || die "depmod failed on $kpkg"

# modules.dep: "kernel/path/name.ko: dep1.ko dep2.ko ..." (paths relative to lib/modules/KVER).
declare -A dep_line=()
while IFS= read -r line; do
	path=${line%%:*}
	base=${path##*/}
	name=${base%%.ko*}
	dep_line[$name]=$line
done <"$kmods/modules.dep"

declare -A done_mod=() visiting=()
order=()
resolve() {
	local name=${1//-/_} line path dep d
	# modules.dep uses file names; module names treat '-' and '_' alike
	[[ -n ${dep_line[$name]:-} ]] || name=${1//_/-}
	[[ -n ${dep_line[$name]:-} ]] || die "module $1 is not in $kpkg"
	[[ -n ${done_mod[$name]:-} ]] && return 0
	[[ -n ${visiting[$name]:-} ]] && die "dependency cycle at module $name"
	visiting[$name]=1
	line=${dep_line[$name]}
	path=${line%%:*}
	for dep in ${line#*:}; do
		d=${dep##*/}
		resolve "${d%%.ko*}"
	done
	done_mod[$name]=1
	order+=("$path")
}
for m in "${mods[@]}"; do resolve "$m"; done

out=$tmp/out
mkdir -p "$out/modules"
cp "$tmp/k/boot/vmlinuz-$kver" "$out/vmlinuz"
: >"$out/load-order"
for p in "${order[@]}"; do
	mkdir -p "$out/modules/$(dirname "$p")"
	cp "$kmods/$p" "$out/modules/$p"
	echo "$p" >>"$out/load-order"
done
echo "$kver" >"$out/kernel-version"
echo "$key" >"$out/stamp"

rm -rf "$dir"
mv "$out" "$dir"
echo "kernel.sh: cached $kpkg ($(wc -l <"$dir/load-order") modules: $(tr '\n' ' ' <"$dir/load-order" | sed 's#[^ ]*/##g')) in $dir" >&2
echo "$dir"
