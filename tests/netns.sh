#!/bin/sh
# Runs a command in a private network namespace with only loopback up (GigE Vision discovery
# and streams never leave this machine). Exit 77 (skipped) when namespaces are not permitted.
if ! command -v unshare >/dev/null 2>&1 || ! command -v ip >/dev/null 2>&1; then
  echo "SKIP: unshare/ip not installed (Debian: util-linux, iproute2)" >&2
  exit 77
fi
if ! unshare -n true 2>/dev/null; then
  echo "SKIP: cannot create a network namespace (unshare -n needs root or user namespaces)" >&2
  exit 77
fi
exec unshare -n sh -c 'ip link set lo up && exec "$@"' netns "$@"
