#!/bin/sh
# tests/netns.sh [--pid-only] COMMAND [ARG...]
#
# Runs COMMAND in a private network namespace with only loopback up (GigE Vision discovery and
# streams never leave this machine) and, where permitted, in a private PID namespace, so that
# nothing COMMAND starts can outlive the test:
#   - this script dies with its parent (ctest), by PR_SET_PDEATHSIG (setpriv --pdeathsig);
#   - SIGTERM, SIGINT and SIGHUP to this script kill the namespace at once (unshare --fork
#     blocks those signals in itself, so they are not left to it);
#   - unshare dies with this script (--pdeathsig again), its child - a shell that is PID 1 of
#     the namespace - dies with unshare (--kill-child), and when PID 1 exits the kernel kills
#     every process left in the namespace: a crashed or killed test leaves no server behind.
# The test runs under a shell that is PID 1 (PID 1 ignores signals it has no handler for; the
# test keeps the usual behaviour).
#
# Exit 77 (skipped) when network namespaces are not permitted. --pid-only: no network
# namespace (for tests that open no sockets but start long-lived children, and may need the
# network to fetch what they need), only the clean-up; COMMAND runs without a PID namespace
# where that is not permitted.
pidonly=
if [ "${1:-}" = --pid-only ]; then
	pidonly=1
	shift
fi
if [ -z "${PC_NETNS_INNER:-}" ] && command -v setpriv >/dev/null 2>&1 &&
	setpriv --pdeathsig KILL true 2>/dev/null; then
	PC_NETNS_INNER=1 exec setpriv --pdeathsig KILL /bin/sh "$0" ${pidonly:+--pid-only} "$@"
fi
unset PC_NETNS_INNER
pdeath=
if command -v setpriv >/dev/null 2>&1 && setpriv --pdeathsig KILL true 2>/dev/null; then
	pdeath="setpriv --pdeathsig KILL"
fi

net=-n
if [ -n "$pidonly" ]; then
	net=
	if ! command -v unshare >/dev/null 2>&1 ||
		! unshare -p -f --kill-child --mount-proc true 2>/dev/null; then
		exec $pdeath "$@"
	fi
elif ! command -v unshare >/dev/null 2>&1 || ! command -v ip >/dev/null 2>&1 ||
	! unshare -n true 2>/dev/null; then
	if ! command -v unshare >/dev/null 2>&1 || ! command -v ip >/dev/null 2>&1; then
		echo "SKIP: unshare/ip not installed (Debian: util-linux, iproute2)" >&2
	else
		echo "SKIP: cannot create a network namespace (unshare -n needs root or user namespaces)" >&2
	fi
	exit 77
fi
pidns=
if unshare $net -p -f --kill-child --mount-proc true 2>/dev/null; then
	pidns="-p -f --kill-child --mount-proc"
fi

# In the background so that this shell can act on signals while it waits. Asynchronous commands
# of a non-interactive shell start with SIGINT ignored; SIGINT here kills the namespace.
# shellcheck disable=SC2086 # word splitting of $pdeath and $pidns is intended
if [ -n "$net" ]; then
	$pdeath unshare $net $pidns sh -c 'ip link set lo up && "$@"' netns "$@" <&0 &
else
	$pdeath unshare $pidns sh -c '"$@"' pidns "$@" <&0 &
fi
child=$!
trap 'kill -KILL $child 2>/dev/null' TERM INT HUP
while :; do
	wait $child
	rc=$?
	# wait returns early (status > 128) when a trapped signal arrives
	kill -0 $child 2>/dev/null || break
done
exit $rc
