#!/usr/bin/env bash
# roam-spy under Xvfb decodes every roam channel by type name.
#   spy_test.sh BUILD_DIR SOURCE_DIR [SCREENSHOT.png]
# In a private network namespace: roam-spy (lcm-spy with lcmtypes_roam.jar) on a virtual
# display, roam-run live, lcm-logplayer playing Plaza 1 at 20x. A screenshot of spy's channel
# table is read back with OCR: each roam channel must show its roam type (no "??" = unknown).
# Exit 77 (skipped) without network namespaces, Xvfb or tesseract.
set -uo pipefail
build="$1"; source="$2"; screenshot="${3:-}"
bin="$build/bin"
for tool in Xvfb tesseract import java; do
  command -v "$tool" >/dev/null || { echo "SKIPPED: $tool not installed"; exit 77; }
done
work="$(mktemp -d "$build/tests/spy.XXXXXX")"
ns="roamspy$$"
display=":$((100 + $$ % 400))"
cleanup() {
  ip netns pids "$ns" 2>/dev/null | xargs -r kill -9 2>/dev/null
  ip netns del "$ns" 2>/dev/null
  [ -n "${xvfb_pid:-}" ] && kill "$xvfb_pid" 2>/dev/null
  rm -rf "$work"
}
trap cleanup EXIT
ip netns add "$ns" 2>/dev/null || { echo "SKIPPED: cannot create network namespaces"; exit 77; }
ip -n "$ns" link set lo up; ip -n "$ns" link set lo multicast on
ip -n "$ns" route add 224.0.0.0/4 dev lo
url="udpm://239.255.76.67:7667?ttl=0"

Xvfb "$display" -screen 0 1280x800x24 >/dev/null 2>&1 & xvfb_pid=$!
for _ in $(seq 50); do [ -e "/tmp/.X11-unix/X${display#:}" ] && break; sleep 0.2; done
DISPLAY="$display" ip netns exec "$ns" "$bin/roam-spy" --lcm-url="$url" >"$work/spy.txt" 2>&1 &
for _ in $(seq 300); do grep -q "LCM types" "$work/spy.txt" && break; sleep 0.2; done
grep -q "Found 9 LCM types" "$work/spy.txt" || { echo "FAILED: spy did not find the 9 roam types (8 messages and the older odometry layout)"; cat "$work/spy.txt"; exit 1; }
# BEACONS and INITIAL_POSE are sent once, at the log's start: play only once spy's LCM socket is
# bound to the bus port. lcm.spy.Spy prints "Found N LCM types", then builds and shows its window,
# then opens LCM and subscribes; on a loaded host that took longer than the 2 s this test used to
# wait, and spy never saw BEACONS.
port="${url##*:}"; port="${port%%\?*}"
bound_to_bus() { ip netns exec "$ns" ss -Hulpn "sport = :$port" 2>/dev/null | grep -c "(\"$1\""; }
for _ in $(seq 300); do [ "$(bound_to_bus java)" -ge 1 ] && break; sleep 0.2; done
[ "$(bound_to_bus java)" -ge 1 ] || { echo "FAILED: spy did not open LCM on port $port within 60 s"; cat "$work/spy.txt"; exit 1; }
ip netns exec "$ns" "$bin/roam-run" "$source/tests/live/live.ini" --input "$url" --output "" \
  >"$work/runtime.txt" 2>&1 &
for _ in $(seq 300); do grep -q "live on" "$work/runtime.txt" && break; sleep 0.2; done
grep -q "live on" "$work/runtime.txt" || { echo "FAILED: roam-run did not go live within 60 s"; cat "$work/runtime.txt"; exit 1; }
ip netns exec "$ns" lcm-logplayer --lcm-url="$url" -s 20 "$source/logs/plaza1.lcmlog" >/dev/null 2>&1 &
sleep 6
DISPLAY="$display" import -window root "$work/screen.png"
[ -n "$screenshot" ] && cp "$work/screen.png" "$screenshot"
convert "$work/screen.png" -crop 800x200+0+0 -resize 200% "$work/table.png"
tesseract "$work/table.png" - 2>/dev/null >"$work/ocr.txt"
cat "$work/ocr.txt"
status=0
# OCR reads '_' as ' ' now and then: compare with spaces and underscores removed.
squash() { tr -d ' _' | tr 'a-z' 'A-Z'; }
for pair in ODOMETRY:odometry_t RANGE:range_t BEACONS:map_t INITIAL_POSE:pose_t GROUND_TRUTH:pose_t POSE_DR:pose_t STATUS_DR:estimator_status_t TRAJECTORY_DR:trajectory_t; do
  channel="${pair%%:*}"; type="${pair##*:}"
  line="$(squash <"$work/ocr.txt" | grep "^$(echo "$channel" | squash)" | head -1)"
  if [ -z "$line" ] || ! echo "$line" | grep -q "$(echo "$type" | squash)" || echo "$line" | grep -q '??'; then
    echo "FAILED: spy does not show $channel decoded as $type"; status=1
  fi
done
[ $status -eq 0 ] && echo "PASSED: lcm-spy decodes every roam channel by type name"
exit $status
