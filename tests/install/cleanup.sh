#!/usr/bin/env bash
# tests/install/cleanup.sh STATE: removes the prefix that install.sh made.
set -euo pipefail
state=$1
[[ -f $state ]] || exit 0
prefix=$(cat "$state")
case $prefix in
  */polarcam-install.*) rm -rf -- "$prefix" ;;
  *) echo "cleanup.sh: refusing to remove '$prefix'" >&2; exit 1 ;;
esac
rm -f -- "$state"
