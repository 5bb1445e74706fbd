# Network namespaces standing in for hosts (scripts/multihost.sh; COOPNAV_NETNS_PREFIX in
# scripts/scenario.sh). Every host is a namespace PREFIX-<host> with one NIC, eth0 (a veth), and a
# multicast route on it; the other end of each veth is a port of a bridge in a namespace of its
# own, PREFIX-sw (the switch). Nothing of these hosts touches the machine's own namespace: the
# LCM runs of other scripts and tests on this machine neither hear them nor are heard, whatever
# the port. Needs root (CAP_NET_ADMIN and CAP_SYS_ADMIN for `ip netns`). Sourced after lib.sh,
# not executed.
#
#   coopnav_netns_check PREFIX          0 when namespaces, a bridge and veth pairs can be made;
#                                       else prints why on stdout and returns 1
#   coopnav_netns_up PREFIX HOST...     the switch and one host per name (cleans up on failure)
#   coopnav_netns_down PREFIX           stops what still runs in them (processes of this run
#                                       only: they are in its namespaces) and deletes them;
#                                       idempotent, for traps
#   coopnav_netns_reap_stale            coopnav_netns_down for the namespaces of runs that were
#                                       killed before their trap ran (cnmh<pid>-*, pid gone)
#   coopnav_netns_cable PREFIX HOST up|down
#                                       plugs / unplugs a host's cable at the switch (the host's
#                                       own NIC stays up, as when a cable or a switch port fails)
#   coopnav_netns_netem PREFIX on "NETEM ARGS" [SPARE_HOST] | PREFIX off
#                                       netem on both ends of every link (the host's eth0 and its
#                                       switch port, so a message between two hosts crosses two
#                                       lossy, delayed links) except SPARE_HOST's; returns 1 (and
#                                       leaves nothing behind) when the kernel refuses netem

COOPNAV_NETNS_SUBNET="${COOPNAV_NETNS_SUBNET:-10.213.0}"

# The switch port of a host: its name in the switch namespace (interface names are at most 15
# characters; host names differ within their first 13).
coopnav_netns_port() { printf 'h-%.13s' "$1"; }

# The namespaces of PREFIX (exact prefix: cnmh12 does not match cnmh123-...).
_cn_netns_of() {
  ip netns list 2>/dev/null | awk -v p="$1-" 'index($1, p) == 1 { print $1 }'
}

coopnav_netns_check() {  # PREFIX
  local ns="$1-check" err
  if ! command -v ip >/dev/null; then
    echo "no ip command (iproute2)"
    return 1
  fi
  if ! err=$(ip netns add "$ns" 2>&1); then
    echo "cannot create a network namespace (ip netns add: ${err:-failed}; needs root)"
    return 1
  fi
  if ! err=$(ip -n "$ns" link add br0 type bridge 2>&1); then
    ip netns del "$ns" 2>/dev/null || true
    echo "no bridge support in this kernel (ip link add type bridge: $err)"
    return 1
  fi
  if ! err=$(ip -n "$ns" link add v0 type veth peer name v1 2>&1); then
    ip netns del "$ns" 2>/dev/null || true
    echo "no veth support in this kernel (ip link add type veth: $err)"
    return 1
  fi
  ip netns del "$ns"
}

coopnav_netns_up() {  # PREFIX HOST...
  local prefix="$1" sw="$1-sw" i=1 h ns port
  shift
  {
    ip netns add "$sw" &&
      ip -n "$sw" link set lo up &&
      # No IGMP snooping: the switch floods multicast to every port, as an unmanaged switch
      # does; with snooping and no querier, forwarding would hang on the timing of the hosts'
      # membership reports.
      ip -n "$sw" link add br0 type bridge mcast_snooping 0 &&
      ip -n "$sw" link set br0 up
  } || { coopnav_netns_down "$prefix"; return 1; }
  for h in "$@"; do
    ns="$prefix-$h"
    port="$(coopnav_netns_port "$h")"
    i=$((i + 1))
    {
      ip netns add "$ns" &&
        ip -n "$ns" link set lo up &&
        ip -n "$ns" link add eth0 type veth peer name "$port" netns "$sw" &&
        ip -n "$sw" link set "$port" master br0 &&
        ip -n "$sw" link set "$port" up &&
        ip -n "$ns" addr add "$COOPNAV_NETNS_SUBNET.$i/24" dev eth0 &&
        ip -n "$ns" link set eth0 up &&
        # LCM's udpm needs a multicast route (README "Network and hosts"): on the NIC, so that
        # ttl=1 traffic goes out on the wire.
        ip -n "$ns" route add 224.0.0.0/4 dev eth0
    } || { echo "netns: could not make host $h ($ns)" >&2; coopnav_netns_down "$prefix"; return 1; }
  done
}

coopnav_netns_down() {  # PREFIX
  local ns pids=() p i
  for ns in $(_cn_netns_of "$1"); do
    # shellcheck disable=SC2207  # pids are numbers
    pids+=($(ip netns pids "$ns" 2>/dev/null))
  done
  if [ "${#pids[@]}" -gt 0 ]; then
    for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
    # Daemons exit within 1 s of SIGTERM (README, lifecycle); then whatever is left is killed.
    for i in $(seq 1 30); do
      local alive=0
      for p in "${pids[@]}"; do kill -0 "$p" 2>/dev/null && alive=1; done
      [ "$alive" -eq 0 ] && break
      sleep 0.1
    done
    for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null || true; done
  fi
  # Deleting a host takes its veth (and so the switch port) with it; the switch takes the bridge.
  for ns in $(_cn_netns_of "$1"); do ip netns del "$ns" 2>/dev/null || true; done
}

coopnav_netns_reap_stale() {
  local p
  for p in $(ip netns list 2>/dev/null | awk '{ print $1 }' | sed -n 's/^cnmh\([0-9][0-9]*\)-.*/\1/p' |
    sort -u); do
    # (Not kill -0: for another user's process it fails as if the process were gone.)
    if [ ! -d "/proc/$p" ]; then
      echo "netns: removing namespaces cnmh$p-* left by a run that was killed" >&2
      coopnav_netns_down "cnmh$p"
    fi
  done
}

coopnav_netns_cable() {  # PREFIX HOST up|down
  ip -n "$1-sw" link set "$(coopnav_netns_port "$2")" "$3"
}

coopnav_netns_netem() {  # PREFIX on "ARGS" [SPARE_HOST] | PREFIX off
  local prefix="$1" what="$2" args="${3:-}" spare="${4:-}" ns h dev ns_of dev_of
  local netem=()
  read -r -a netem <<<"$args"
  for ns in $(_cn_netns_of "$prefix"); do
    h="${ns#"$prefix"-}"
    [ "$h" = sw ] && continue
    [ -n "$spare" ] && [ "$h" = "$spare" ] && continue
    for dev in "$ns eth0" "$prefix-sw $(coopnav_netns_port "$h")"; do
      read -r ns_of dev_of <<<"$dev"
      if [ "$what" = on ]; then
        if ! ip netns exec "$ns_of" tc qdisc add dev "$dev_of" root netem "${netem[@]}" 2>/dev/null
        then
          coopnav_netns_netem "$prefix" off
          return 1
        fi
      else
        ip netns exec "$ns_of" tc qdisc del dev "$dev_of" root 2>/dev/null || true
      fi
    done
  done
}
