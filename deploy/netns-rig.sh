#!/usr/bin/env bash
# A simulated rig network on one machine: one network namespace per camera node, one for the
# fusion host, one for the trigger master, joined by a Linux bridge (in its own "switch"
# namespace, so the host's network is untouched), with a multicast route for LCM in each.
#
#   deploy/netns-rig.sh create PREFIX NUM_CAMERAS   -> namespaces PREFIX-master, PREFIX-fusion,
#                                                      PREFIX-cam0 .. PREFIX-cam<N-1>, PREFIX-sw
#   deploy/netns-rig.sh destroy PREFIX
#   deploy/netns-rig.sh loss PREFIX NAMESPACE PORT [N]   drop 1 in N (default 10) UDP datagrams to
#                                                      PORT in and out of PREFIX-NAMESPACE (nftables;
#                                                      this kernel has no netem qdisc)
#   deploy/netns-rig.sh dropped PREFIX NAMESPACE       datagrams 'loss' dropped there so far: IN OUT
#
# Run a process inside with: ip netns exec PREFIX-cam3 <command>. LCM needs ttl=1 to cross the
# bridge: udpm://239.255.76.67:PORT?ttl=1. Needs root (CAP_NET_ADMIN) and iproute2, nftables.
# On a real LAN the switch floods multicast unless IGMP snooping with a querier is configured.
set -euo pipefail

die() { echo "netns-rig: $*" >&2; exit 1; }
[[ $# -ge 2 ]] || die "usage: $0 create PREFIX NUM_CAMERAS | destroy PREFIX | loss PREFIX NAMESPACE PORT [N] | dropped PREFIX NAMESPACE"
cmd=$1 prefix=$2
[[ $prefix =~ ^[a-z][a-z0-9]{0,7}$ ]] || die "PREFIX must be 1-8 lowercase letters/digits starting with a letter, got '$prefix'"
sw="$prefix-sw"

create() {
  local n=$1 i=1 names=("master" "fusion")
  [[ $n =~ ^[0-9]+$ && $n -ge 1 && $n -le 64 ]] || die "NUM_CAMERAS must be 1..64, got '$n'"
  for ((c = 0; c < n; c++)); do names+=("cam$c"); done
  ip netns add "$sw" || die "cannot create network namespaces (need root / CAP_NET_ADMIN)"
  ip -n "$sw" link add br0 type bridge
  # Flood multicast to every port: there is no IGMP querier on this bridge.
  ip -n "$sw" link set br0 type bridge mcast_snooping 0
  ip -n "$sw" link set br0 up
  ip -n "$sw" link set lo up
  for name in "${names[@]}"; do
    local ns="$prefix-$name"
    ip netns add "$ns"
    ip -n "$sw" link add "p$i" type veth peer name eth0 netns "$ns"
    ip -n "$sw" link set "p$i" master br0 up
    ip -n "$ns" link set lo up
    ip -n "$ns" addr add "10.77.0.$i/24" dev eth0
    ip -n "$ns" link set eth0 up multicast on
    ip -n "$ns" route add 224.0.0.0/4 dev eth0
    i=$((i + 1))
  done
  echo "netns-rig: created ${#names[@]} namespaces ($prefix-master, $prefix-fusion, $prefix-cam0..$((n - 1))) on bridge $sw/br0"
}

destroy() {
  local ns
  for ns in $(ip netns list | awk '{print $1}' | grep -E "^$prefix-(master|fusion|cam[0-9]+|sw)$" || true); do
    ip netns del "$ns" || true
  done
}

loss() {
  local ns="$prefix-$1" port=$2 every=${3:-10}
  [[ $port =~ ^[0-9]+$ && $every =~ ^[0-9]+$ && $every -ge 2 ]] || die "loss: PORT and N must be numbers (N >= 2)"
  ip netns exec "$ns" nft -f - <<NFT
table inet hullpose_loss {
  chain input { type filter hook input priority 0; udp dport $port numgen random mod $every 0 counter drop; }
  chain output { type filter hook output priority 0; udp dport $port numgen random mod $every 0 counter drop; }
}
NFT
}

dropped() {
  ip netns exec "$prefix-$1" nft list table inet hullpose_loss 2>/dev/null |
    awk '/chain input/ { c = "in" } /chain output/ { c = "out" }
         /counter packets/ { for (i = 1; i < NF; ++i) if ($i == "packets") n[c] += $(i + 1) }
         END { print n["in"] + 0, n["out"] + 0 }'
}

case $cmd in
  create) [[ $# -eq 3 ]] || die "usage: $0 create PREFIX NUM_CAMERAS"; create "$3" ;;
  destroy) destroy ;;
  loss) [[ $# -ge 4 ]] || die "usage: $0 loss PREFIX NAMESPACE PORT [N]"; loss "$3" "$4" "${5:-10}" ;;
  dropped) [[ $# -eq 3 ]] || die "usage: $0 dropped PREFIX NAMESPACE"; dropped "$3" ;;
  *) die "unknown command '$cmd'" ;;
esac
