#!/usr/bin/env bash
# The browser viewer (daemons/viewer) end to end, with a real browser (headless Chromium):
#  1. live: narrow_minimal in real time (world_sim mode=real_time) with every daemon and the
#     viewer on the run's bus; a Chromium keeps the page open until the page reports
#     (/drawn.json, from its acks) that it drew the robot, human 1, the robot band, human 1's band,
#     the crossing and the round-1 utterance's bubble; then --dump-dom and --screenshot of the
#     page (the drawn summary in <pre id="drawn"> checked);
#  2. replay: the run's recorded log (coopnav_viewer --log, no bus), scrubbed with ?t= to a time
#     within the round-1 bubble: the same drawing, checked in the dumped DOM and screenshotted;
#  3. the replaying viewer under a slowloris, 300 idle connections and a header flood at once:
#     /scene.json within 1 s, SIGTERM within 1 s;
#  4. --log /dev/zero and --log FIFO: exit 3 at once with "not a regular file".
# Screenshots and logs go to $COOPNAV_VIEWER_TEST_OUT (default $COOPNAV_BUILD_DIR/e2e_viewer).
# Ports (COOPNAV_TEST_PORT_BASE from ctest, else 9300): LCM udpm at the base, HTTP (TCP) at
# base + 1 (live) and base + 2 (replay).
# Without Chromium the test fails, unless COOPNAV_ALLOW_SKIP=1 (then it exits 77, a skip).
set -euo pipefail
src="${COOPNAV_SOURCE_DIR:-$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)}"
export COOPNAV_BUILD_DIR="${COOPNAV_BUILD_DIR:?}"
chromium="${COOPNAV_CHROMIUM:-/usr/bin/chromium}"
if [ ! -x "$chromium" ]; then
  if [ "${COOPNAV_ALLOW_SKIP:-0}" = 1 ]; then
    echo "SKIP: no Chromium at $chromium (COOPNAV_ALLOW_SKIP=1)"
    exit 77
  fi
  echo "FAIL: no Chromium at $chromium: the viewer test needs a browser (apt-get install chromium;" \
    "COOPNAV_ALLOW_SKIP=1 skips)"
  exit 1
fi
viewer="$COOPNAV_BUILD_DIR/daemons/viewer/coopnav_viewer"
[ -x "$viewer" ] || { echo "FAIL: $viewer is not built"; exit 1; }

source "$src/scripts/lib.sh"
source "$src/scripts/scenario.sh"
if [ -n "${COOPNAV_VIEWER_TEST_OUT:-}" ]; then
  out="$COOPNAV_VIEWER_TEST_OUT"
else
  out="$COOPNAV_BUILD_DIR/e2e_viewer"
  rm -rf "$out"  # this test's own folder: the previous run's
fi
mkdir -p "$out"
scenario="$src/config/scenarios/narrow_minimal.yaml"
base="${COOPNAV_TEST_PORT_BASE:-9300}"  # ctest gives each e2e test its ports
lcm_port=$base
live_http=$((base + 1))   # TCP
replay_http=$((base + 2))
live_url="udpm://239.255.76.67:$lcm_port?ttl=0&recv_buf_size=4194304"

pids=()
cleanup() {
  local p
  for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
  coopnav_stop_all
}
coopnav_trap cleanup EXIT
fail() {
  echo "FAIL: $*"
  echo "--- viewer logs:"
  tail -n 20 "$out"/viewer_*.log 2>/dev/null || true
  exit 1
}

# get URL: the body, or nothing (python: no curl needed)
get() {
  python3 - "$1" <<'PY' 2>/dev/null || true
import sys, urllib.request
try:
    print(urllib.request.urlopen(sys.argv[1], timeout=5).read().decode())
except Exception:
    pass
PY
}
wait_http() {  # PORT: the viewer answers
  local start=$SECONDS
  while [ $((SECONDS - start)) -lt 30 ]; do
    [ -n "$(get "http://127.0.0.1:$1/scene.json")" ] && return 0
    sleep 0.2
  done
  return 1
}
chrome_flags=(--headless --no-sandbox --disable-gpu --disable-dev-shm-usage --hide-scrollbars)
# browser ARGS...: one headless Chromium run (own profile), bounded in time
browser() {
  local profile
  profile="$(mktemp -d "$out/chrome.XXXX")"
  timeout 120 "$chromium" "${chrome_flags[@]}" --user-data-dir="$profile" "$@" \
    2>>"$out/chromium.log"
}
# check_drawn HTML_FILE WHAT: the page's <pre id="drawn"> holds the map, the robot, human 1, both
# bands, daemon statuses, and (WHAT = bubble) the crossing and the round-1 bubble
check_drawn() {
  python3 - "$1" "$2" <<'PY'
import html, json, re, sys
dom = open(sys.argv[1]).read()
m = re.search(r'<pre id="drawn"[^>]*>(.*?)</pre>', dom, re.S)
if not m or not m.group(1).strip():
    sys.exit(f"no drawn summary in {sys.argv[1]}")
d = json.loads(html.unescape(m.group(1)))
bad = []
if not d.get("robot"): bad.append("no robot")
if 1 not in d.get("humans", []): bad.append("no human 1")
if not d.get("robot_band"): bad.append("no robot band")
if 1 not in d.get("human_bands", []): bad.append("no band of human 1")
if not d.get("map"): bad.append("no map")
# Live, the crossing was seen drawn in the acks; at the moment of the dump it may be unknown.
if sys.argv[2] == "bubble" and not any(c["human_id"] == 1 for c in d.get("crossings", [])):
    bad.append("no crossing")
# Dir as an arrow wherever it is left or right.
if any(c.get("dir") in ("left", "right") and not c.get("dir_arrow") for c in d.get("crossings", [])):
    bad.append("a Dir without its arrow")
if not d.get("statuses"): bad.append("no daemon status")
if sys.argv[2] == "bubble" and not any(b["round"] == 1 for b in d.get("bubbles", [])):
    bad.append("no round-1 bubble")
print(f"  drawn at t={d.get('t')}: robot {d.get('robot')}, humans {d.get('humans')}, "
      f"robot band {d.get('robot_band')} poses, human bands {d.get('human_bands')}, "
      f"mode {d.get('mode')}, bubbles {[b['text'] for b in d.get('bubbles', [])]}, "
      f"segments {d.get('segments')}, crossings {d.get('crossings')}, "
      f"statuses {len(d.get('statuses', []))}")
if bad:
    sys.exit("drawn summary lacks: " + ", ".join(bad))
PY
}

coopnav_ensure_multicast

# ---- 1. live
echo "== live: narrow_minimal in real time, viewer on :$live_http"
"$viewer" -c "$src/config/viewer.yaml" --lcm-url "$live_url" --set "http_port=$live_http" \
  --set "map_file=$scenario" --set bubble_hold_s=8 >"$out/viewer_live.log" 2>&1 &
pids+=($!)
wait_http "$live_http" || fail "the live viewer does not answer on :$live_http"
grep -q "open http://127.0.0.1:$live_http/" "$out/viewer_live.log" || fail "no 'open http://' line"
# The page kept open while the run goes (a simple command: $! is timeout's pid, and timeout
# passes the TERM of the cleanup on to Chromium).
timeout 300 "$chromium" "${chrome_flags[@]}" --user-data-dir="$(mktemp -d "$out/chrome.XXXX")" \
  --window-size=1280,800 "http://127.0.0.1:$live_http/" >/dev/null 2>>"$out/chromium.log" &
pids+=($!)

live_ok=0
coopnav_scenario_hook() {
  # Until the page has drawn every part of the round-1 scene at least once (its acks).
  local want=(robot human:1 robot_band human_band:1 crossing:1 seg_d_h:1 bubble:1:r1 plot:1) k
  local start=$SECONDS
  while [ $((SECONDS - start)) -lt 120 ]; do
    local drawn
    drawn="$(get "http://127.0.0.1:$live_http/drawn.json")"
    local missing=()
    for k in "${want[@]}"; do
      grep -q "\"$k\"" <<<"$drawn" || missing+=("$k")
    done
    if [ "${#missing[@]}" -eq 0 ]; then
      echo "  the page drew ${want[*]} ($((SECONDS - start)) s into the run)"
      live_ok=1
      # Soon after round 1: a screenshot and the DOM of the live page.
      browser --window-size=1280,800 --virtual-time-budget=4000 \
        --screenshot="$out/viewer_live.png" "http://127.0.0.1:$live_http/?once=1&ack=0" \
        >/dev/null || true
      browser --window-size=1280,800 --virtual-time-budget=4000 --dump-dom \
        "http://127.0.0.1:$live_http/?once=1&ack=0" >"$out/live_dom.html" || true
      return 0
    fi
    sleep 0.2
  done
  echo "  still missing after 120 s: ${missing[*]}"
}
export COOPNAV_DAEMON_ARGS_world_sim="--set mode=real_time"
rc=0
coopnav_run_scenario "$scenario" "$out/narrow_minimal" "$lcm_port" || rc=$?
[ "$rc" -eq 0 ] || fail "the run failed (world_sim exit $rc; see $out/narrow_minimal/*.log)"
[ "$live_ok" = 1 ] || fail "the live page never drew the round-1 scene (see $out)"
[ -s "$out/live_dom.html" ] || fail "no DOM of the live page"
check_drawn "$out/live_dom.html" any || fail "live page: the drawn summary is incomplete"
[ -s "$out/viewer_live.png" ] || fail "no screenshot of the live page"
stats="$(get "http://127.0.0.1:$live_http/stats.json")"
echo "  live stats: $stats"
skipped="$(get "http://127.0.0.1:$live_http/scene.json" | python3 -c \
  'import json,sys; print(json.load(sys.stdin)["viewer"]["skipped_total"])')"
[ "$skipped" = 0 ] || fail "the live viewer skipped $skipped messages of a clean run"
for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
pids=()

# ---- 2. replay of the recorded log
log="$out/narrow_minimal/narrow_minimal.lcm"
[ -s "$log" ] || fail "no recorded log $log"
echo "== replay: $log on :$replay_http"
"$viewer" -c "$src/config/viewer.yaml" --log "$log" --set "http_port=$replay_http" \
  --set replay_autoplay=false >"$out/viewer_replay.log" 2>&1 &
replay_pid=$!
pids+=($replay_pid)
wait_http "$replay_http" || fail "the replaying viewer does not answer on :$replay_http"
# The round-1 utterance's time, from the replayed scene at the end of the log.
python3 - "$replay_http" >"$out/t_round1" <<'PY' || fail "no round-1 utterance in the replayed log"
import json, sys, time, urllib.request
base = f"http://127.0.0.1:{sys.argv[1]}"
req = urllib.request.Request(base + "/control", data=b'{"command":"seek","value":1e9}',
                             headers={"Content-Type": "application/json"}, method="POST")
urllib.request.urlopen(req, timeout=5)
for _ in range(50):
    time.sleep(0.2)
    s = json.load(urllib.request.urlopen(base + "/scene.json", timeout=5))
    if s["replay"]["t"] >= s["replay"]["end"]:
        break
r1 = [u for u in s["utterances"] if u["round"] == 1 and u["human_id"] == 1]
if not r1:
    sys.exit(1)
print(f"{r1[0]['t'] + r1[0]['speech_start_s'] + 1.0:.2f}")
PY
t1="$(cat "$out/t_round1")"
echo "  round 1 + 1 s: t = $t1 s"
browser --window-size=1280,800 --virtual-time-budget=5000 --dump-dom \
  "http://127.0.0.1:$replay_http/?once=1&ack=0&t=$t1" >"$out/replay_dom.html" ||
  fail "Chromium could not dump the replay page"
check_drawn "$out/replay_dom.html" bubble || fail "replay page at t=$t1: the drawn summary is incomplete"
browser --window-size=1280,800 --virtual-time-budget=5000 --screenshot="$out/viewer_replay.png" \
  "http://127.0.0.1:$replay_http/?once=1&ack=0&t=$t1" >/dev/null ||
  fail "Chromium could not screenshot the replay page"
[ -s "$out/viewer_replay.png" ] || fail "no screenshot of the replay page"

# 3. The replaying viewer under a slowloris (40 connections trickling headers), 300 idle
#    connections and a header flood, all at once: /scene.json answered within 1 s, then SIGTERM
#    ends it within 1 s (the attack goes on meanwhile).
echo "== the replaying viewer under a slowloris, idle connections and a header flood"
python3 - "$replay_http" "$out/attack_ready" >"$out/attack.log" 2>&1 <<'PY' &
import socket, sys, threading, time
port, ready = int(sys.argv[1]), sys.argv[2]
def conn():
    s = socket.socket()
    s.settimeout(2)
    s.connect(("127.0.0.1", port))
    return s
idle = [conn() for _ in range(300)]
def slowloris():
    socks = []
    while True:
        while len(socks) < 40:
            try:
                s = conn(); s.sendall(b"GET /scene.json HTTP/1.1\r\nHost: x\r\n"); socks.append(s)
            except OSError:
                time.sleep(0.05)
        for s in list(socks):
            try:
                s.sendall(b"X-a: b\r\n")
            except OSError:
                socks.remove(s); s.close()
        time.sleep(0.1)
def flood():
    chunk = b"X: y\r\n" * 1000
    while True:
        try:
            s = conn(); s.sendall(b"GET / HTTP/1.1\r\n")
            for _ in range(1000):  # a million headers, until refused
                s.sendall(chunk)
        except OSError:
            pass
        finally:
            s.close()
for f in (slowloris, flood):
    threading.Thread(target=f, daemon=True).start()
time.sleep(0.5)
open(ready, "w").close()
time.sleep(20)
PY
attack_pid=$!
pids+=($attack_pid)
for _ in $(seq 100); do [ -e "$out/attack_ready" ] && break; sleep 0.1; done
[ -e "$out/attack_ready" ] || fail "the attack did not start ($(cat "$out/attack.log"))"
python3 - "$replay_http" <<'PY' || fail "/scene.json under the attack"
import sys, time, urllib.request
for _ in range(3):
    t0 = time.monotonic()
    body = urllib.request.urlopen(f"http://127.0.0.1:{sys.argv[1]}/scene.json", timeout=5).read()
    took = time.monotonic() - t0
    print(f"  /scene.json under the attack: {len(body)} bytes in {took:.3f} s")
    if took >= 1.0:
        sys.exit(1)
    time.sleep(0.2)
PY
t0=$(date +%s%N)
kill -TERM "$replay_pid"
rc=0
wait "$replay_pid" || rc=$?
stop_ms=$((($(date +%s%N) - t0) / 1000000))
echo "  SIGTERM under the attack: exit $rc in $stop_ms ms"
[ "$rc" = 0 ] || fail "the viewer exited $rc on SIGTERM under the attack"
[ "$stop_ms" -lt 1000 ] || fail "the viewer took $stop_ms ms to end under the attack"
kill "$attack_pid" 2>/dev/null || true

# 4. --log naming what is not a regular file (read for ever before): exit 3 at once, saying so.
for bad in /dev/zero "$out/fifo"; do
  [ "$bad" = /dev/zero ] || mkfifo "$bad"
  rc=0
  timeout 5 "$viewer" --log "$bad" --set http_port=0 >"$out/viewer_bad_log.log" 2>&1 || rc=$?
  [ "$rc" = 3 ] || fail "--log $bad: exit $rc, not 3 at once"
  grep -q "not a regular file" "$out/viewer_bad_log.log" || fail "--log $bad: no clear error"
done
echo "ok: live and replayed scenes drawn; screenshots $out/viewer_live.png $out/viewer_replay.png;" \
  "/scene.json and SIGTERM within 1 s under attack; --log /dev/zero and a FIFO refused at once"
