#!/usr/bin/env bash
# Runs a command in a network namespace of its own: loopback up and a veth pair whose first end has
# the address the command finds in RT_TEST_NAMESPACE_ADDRESS (a pair: both ends up, so the link has
# a carrier, which ICE agents ask of an interface). What it sends cannot leave the namespace,
# and servers that will not use loopback for media (Janus) have an address to use. Where no
# namespace can be made (no CAP_SYS_ADMIN), the command runs without one and without the variable,
# and says so itself. RT_TEST_START_JANUS names tests/cli/start_janus.sh for the tests that start a Janus.
#   in_network_namespace.sh COMMAND [ARGS...]
set -uo pipefail
address=10.77.0.1
RT_TEST_START_JANUS="$(cd "$(dirname "$0")" && pwd)/start_janus.sh"
export RT_TEST_START_JANUS
if unshare -n true 2>/dev/null && command -v ip >/dev/null; then
  exec unshare -n bash -c '
    set -e
    ip link set lo up
    ip link add rt0 type veth peer name rt1
    ip addr add '"$address"'/24 dev rt0
    ip link set rt0 up
    ip link set rt1 up
    export RT_TEST_NAMESPACE_ADDRESS='"$address"'
    exec "$@"' in_network_namespace "$@"
fi
echo "in_network_namespace.sh: cannot make a network namespace here (unshare -n or ip missing, or not allowed)" >&2
exec "$@"
