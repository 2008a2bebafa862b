#!/usr/bin/env bash
# Runs a command on a small internet of the test's own: two offices, each behind a router that
# translates addresses (NAT, as an ordinary office or home router does) and forwards nothing in,
# and a public side where a server runs. All of it in namespaces made here (a mount namespace of
# its own holds their names), so nothing can leave them and nothing is left behind.
#   office A 192.168.1.2 -- 192.168.1.1 router A 100.64.0.2 --+
#                                                              +-- 100.64.0.1 the public side
#   office B 192.168.2.2 -- 192.168.2.1 router B 100.64.0.3 --+
# The command runs on the public side, with RT_TEST_PUBLIC_ADDRESS (100.64.0.1), and runs a
# program in an office with `ip netns exec office_a|office_b PROGRAM`. The offices cannot reach
# each other: their networks are private and no router forwards in what is not an answer. Each
# router counts the UDP it forwards out and the UDP answers it lets in
# (`ip netns exec router_a nft list chain ip filter forward`). The public side is one segment (a
# bridge), as a server with one address sees the internet. Exits 77 where namespaces, ip or nft
# are missing.
#   behind_routers.sh COMMAND [ARGS...]
set -uo pipefail
if ! command -v ip > /dev/null || ! command -v nft > /dev/null || ! unshare -mn true 2> /dev/null; then
  echo "SKIPPED: behind_routers.sh needs unshare -mn (root), iproute2 and nftables"
  exit 77
fi
exec unshare -mn bash -c '
  set -e
  mkdir -p /run/netns
  mount -t tmpfs rt-netns /run/netns
  ip link set lo up
  ip link add public type bridge
  ip addr add 100.64.0.1/24 dev public
  ip link set public up
  for i in 1 2; do
    site=$([ $i = 1 ] && echo a || echo b)
    ip netns add router_$site
    ip netns add office_$site
    ip link add public_$site type veth peer name wan netns router_$site
    ip link set public_$site master public
    ip link set public_$site up
    ip -n router_$site link set lo up
    ip -n router_$site addr add 100.64.0.$((i + 1))/24 dev wan
    ip -n router_$site link set wan up
    ip -n router_$site route add default via 100.64.0.1
    ip -n router_$site link add lan type veth peer name eth0 netns office_$site
    ip -n router_$site addr add 192.168.$i.1/24 dev lan
    ip -n router_$site link set lan up
    ip -n office_$site link set lo up
    ip -n office_$site addr add 192.168.$i.2/24 dev eth0
    ip -n office_$site link set eth0 up
    ip -n office_$site route add default via 192.168.$i.1
    ip netns exec router_$site sysctl -qw net.ipv4.ip_forward=1
    ip netns exec router_$site nft -f - <<NFT
table ip nat {
  chain postrouting { type nat hook postrouting priority srcnat; oifname "wan" masquerade; }
}
table ip filter {
  chain forward {
    type filter hook forward priority filter; policy drop;
    iifname "lan" oifname "wan" meta l4proto udp counter accept
    iifname "lan" oifname "wan" accept
    iifname "wan" oifname "lan" ct state established,related meta l4proto udp counter accept
    iifname "wan" oifname "lan" ct state established,related accept
  }
}
NFT
  done
  export RT_TEST_PUBLIC_ADDRESS=100.64.0.1
  exec "$@"' behind_routers "$@"
