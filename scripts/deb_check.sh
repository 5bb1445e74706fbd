#!/usr/bin/env bash
# The Debian package on a fresh Debian 12 (README "Install"): builds coopnav_<version>_amd64.deb
# (cpack in the build folder), installs it with apt into a minimal bookworm chroot of its own
# (apt pulls the dependencies the package declares, nothing else is there), then starts the
# installed daemons (/usr/bin/coopnav_<daemon>) with the installed admin configs
# (/etc/coopnav/<daemon>.yaml, unedited: their maps resolve through the package's links) on an
# LCM port of their own, checks that `coopnav_ctl wait-ready` hears all of them, and runs
# narrow_minimal from the installed scenarios to its end with the installed world_sim, recorded
# by the installed coopnav_record: its summary (the installed `coopnav_ctl summarize`) must say
# GOAL_REACHED without a contact.
#
#   scripts/deb_check.sh [--deb FILE] [--keep]
#   --deb: check this package instead of building one.   --keep: leave the chroot for a look.
# Root (chroot, mounts) and the Debian mirror (apt). The chroot starts from the pristine minbase
# tar that ../shared/tools/fresh-debian.sh keeps, ${TMPDIR:-/tmp}/fresh-debian/root.base.tar
# (debootstrapped here, once, if missing: a few minutes); each check extracts it afresh into
# ${TMPDIR:-/tmp}/coopnav-deb-check/root. About 1-2 min with the base present.
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

deb="" keep=0
while [ $# -gt 0 ]; do
  case "$1" in
    --deb) deb="$2"; shift 2 ;;
    --keep) keep=1; shift ;;
    -h|--help) sed -n '2,/^[^#]/p' "$0" | grep '^#' | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "deb_check.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
[ "$(id -u)" -eq 0 ] || { echo "deb_check.sh: needs root (chroot, mounts)" >&2; exit 2; }

if [ -z "$deb" ]; then
  cmake --build "$COOPNAV_BUILD_DIR" -j"$(nproc)"
  rm -f "$COOPNAV_BUILD_DIR"/coopnav_*.deb
  (cd "$COOPNAV_BUILD_DIR" && cpack -G DEB) >"$COOPNAV_BUILD_DIR/cpack.log" 2>&1 ||
    { cat "$COOPNAV_BUILD_DIR/cpack.log"; echo "deb_check.sh: cpack failed" >&2; exit 1; }
  deb="$(ls "$COOPNAV_BUILD_DIR"/coopnav_*_amd64.deb)"
fi
[ -f "$deb" ] || { echo "deb_check.sh: no package '$deb'" >&2; exit 2; }
echo "package: $deb"
dpkg-deb -f "$deb" Depends

work="${TMPDIR:-/tmp}/coopnav-deb-check"
root="$work/root"
base="${TMPDIR:-/tmp}/fresh-debian/root.base.tar"
mirror="$(awk '/^URIs:/{print $2; exit}' /etc/apt/sources.list.d/debian.sources 2>/dev/null || true)"
mirror="${mirror:-http://deb.debian.org/debian}"
mkdir -p "$work" "$(dirname "$base")"
if [ ! -f "$base" ]; then
  command -v debootstrap >/dev/null ||
    env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq debootstrap >/dev/null
  echo "debootstrapping the pristine base (once): $base"
  rm -rf --one-file-system "$work/base"
  debootstrap --variant=minbase bookworm "$work/base" "$mirror" >"$work/debootstrap.log" 2>&1 ||
    { tail "$work/debootstrap.log"; echo "deb_check.sh: debootstrap failed" >&2; exit 1; }
  tar -C "$work/base" -cf "$base.tmp.$$" . && mv "$base.tmp.$$" "$base"
  rm -rf --one-file-system "$work/base"
fi

unmount() { local m; for m in dev/pts dev sys proc; do umount -l "$root/$m" 2>/dev/null || true; done; }
cleanup() {
  coopnav_stop_all
  unmount
  if [ "$keep" = 0 ]; then rm -rf --one-file-system "$root"; fi
}
unmount
rm -rf --one-file-system "$root" && mkdir -p "$root" && tar -C "$root" -xf "$base"
coopnav_trap cleanup EXIT
cp /etc/resolv.conf "$root/etc/resolv.conf" 2>/dev/null || true
for m in proc sys dev dev/pts; do mount --bind "/$m" "$root/$m"; done
cp "$deb" "$root/tmp/"

# In the chroot with a clean environment (a command, not a function: the daemons' pids are the
# ones coopnav_stop_all signals).
url=""
in_root() {
  chroot "$root" /usr/bin/env -i HOME=/root PATH=/usr/sbin:/usr/bin:/sbin:/bin LANG=C.UTF-8 \
    DEBIAN_FRONTEND=noninteractive LCM_DEFAULT_URL="$url" "$@"
}
SECONDS=0
in_root apt-get update -qq >"$work/apt.log" 2>&1 &&
  in_root apt-get install -y -qq --no-install-recommends "/tmp/$(basename "$deb")" >>"$work/apt.log" 2>&1 ||
  { tail -30 "$work/apt.log"; echo "FAIL: apt-get install of the package" >&2; exit 1; }
echo "installed with its dependencies in ${SECONDS} s ($(in_root dpkg-query -W -f='${binary:Package}\n' | wc -l) packages in the chroot)"

# What the package put where, as the units and the admin's copies expect it.
for f in /usr/bin/coopnav_band_source /usr/bin/coopnav_ctl /usr/share/coopnav/band_source.yaml \
  /usr/share/coopnav/maps/open.yaml /usr/share/coopnav/scenarios/narrow_minimal.yaml \
  /etc/coopnav/coopnav.env /etc/coopnav/band_source.yaml /etc/coopnav/maps/open.pgm \
  /usr/lib/systemd/system/coopnav@.service /usr/lib/systemd/system/coopnav.target; do
  [ -e "$root$f" ] || { echo "FAIL: the package has no $f" >&2; exit 1; }
done
grep -q '^ExecStart=/usr/bin/coopnav_%i --config /etc/coopnav/%i.yaml' \
  "$root/usr/lib/systemd/system/coopnav@.service" ||
  { echo "FAIL: coopnav@.service does not start /usr/bin/coopnav_%i" >&2; exit 1; }

# The daemons, as the units start them (installed binary, /etc/coopnav config), on a port of
# this check's own (the chroot shares this machine's network: ttl=0 keeps it on the host).
coopnav_ensure_multicast
port=$((7900 + RANDOM % 90))
url="udpm://239.255.76.67:$port?ttl=0&recv_buf_size=4194304"
mapfile -t daemons < <("$COOPNAV_ROOT/scripts/coopnav" system daemons)  # config/system.yaml
mkdir -p "$root/var/log/coopnav-check"
for d in "${daemons[@]}"; do
  coopnav_spawn "$root/var/log/coopnav-check/$d.log" chroot "$root" /usr/bin/env -i \
    PATH=/usr/bin:/bin LCM_DEFAULT_URL="$url" "/usr/bin/coopnav_$d" --config "/etc/coopnav/$d.yaml"
done
if ! in_root /usr/bin/coopnav_ctl wait-ready "${daemons[@]}" --timeout-s 60; then
  tail -n 5 "$root"/var/log/coopnav-check/*.log
  echo "FAIL: the installed daemons did not all answer wait-ready" >&2
  exit 1
fi
echo "wait-ready: ${daemons[*]} answer from /usr/bin with /etc/coopnav configs"

# A whole run from the installed scenario (its map is the configs' map, maps/open.yaml), recorded
# with the installed recorder; its outcome is read from the installed `coopnav_ctl summarize`.
logs=/var/log/coopnav-check
coopnav_spawn "$root$logs/record.log" chroot "$root" /usr/bin/env -i PATH=/usr/bin:/bin \
  /usr/bin/coopnav_record -f -c 'COOPNAV_.*' --lcm-url "$url" "$logs/narrow_minimal.lcm"
for _ in $(seq 1 100); do [ -s "$root$logs/narrow_minimal.lcm" ] && break; sleep 0.1; done
rc=0
in_root /usr/bin/coopnav_world_sim --config /etc/coopnav/world_sim.yaml \
  --set scenario=/etc/coopnav/scenarios/narrow_minimal.yaml >"$root$logs/world_sim.log" 2>&1 || rc=$?
coopnav_wait_recorded "$root$logs/narrow_minimal.lcm"
in_root /usr/bin/coopnav_ctl summarize "$logs/narrow_minimal.lcm" --out "$logs/summary.json" \
  >"$root$logs/summarize.log" 2>&1 || true
# scripts/coopnav outcome: the final state, and exit 1 unless every goal was reached without a
# contact (run.py outcome_failure).
ok=0
outcome="$("$COOPNAV_ROOT/scripts/coopnav" outcome "$root$logs/summary.json" 2>&1)" || ok=$?
echo "world_sim narrow_minimal: exit $rc, outcome $outcome"
if [ "$rc" != 0 ] || [ "$ok" != 0 ]; then
  tail -n 20 "$root$logs/world_sim.log" "$root$logs/summarize.log"
  echo "FAIL: the installed narrow_minimal run did not reach the goal" >&2
  exit 1
fi
echo "deb check: coopnav installs on a fresh Debian 12 and runs from its installed paths (${SECONDS} s)"
