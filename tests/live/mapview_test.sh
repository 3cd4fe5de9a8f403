#!/usr/bin/env bash
# lcm-spy's "roam map view" draws a live run where the data says it is.
#   mapview_test.sh BUILD_DIR SOURCE_DIR [SCREENSHOT.png]
# In a private network namespace, on a virtual display: roam-spy --map (lcm-spy, which must find
# the plugin on its class path, and the map view opened by it), roam-run live with two estimators
# (tests/live/mapview.ini), lcm-logplayer playing Plaza 1 at 20x. After SNAPSHOT_AFTER_S the
# view writes a PNG of itself and, beside it, the world-to-pixel transform of that same paint.
# roam-run is then stopped (its log closes) and MapViewCheck compares the PNG with that log:
# beacons, ground truth and both estimators' paths at their computed pixels, in roam-plot's
# colours. With xdotool installed, the view is also opened the way a person does, from lcm-spy's
# context menu on a channel row. The optional third argument receives a screenshot of the whole
# screen (spy and view).
# ROAM_TEST_KEEP=DIR keeps the snapshot, its sidecar, the run's log and the outputs there.
# Exit 77 (skipped) without Xvfb, java or network namespaces.
set -uo pipefail
build="$1"; source="$2"; screenshot="${3:-}"
bin="$build/bin"
SNAPSHOT_AFTER_S=14
for tool in Xvfb java ip; do
  command -v "$tool" >/dev/null || { echo "SKIPPED: $tool not installed"; exit 77; }
done
work="$(mktemp -d "$build/tests/mapview.XXXXXX")"
ns="roammap$$"
display=":$((500 + $$ % 400))"
cleanup() {
  ip netns pids "$ns" 2>/dev/null | xargs -r kill -9 2>/dev/null
  ip netns del "$ns" 2>/dev/null
  [ -n "${xvfb_pid:-}" ] && kill "$xvfb_pid" 2>/dev/null
  if [ -n "${ROAM_TEST_KEEP:-}" ]; then cp -r "$work/." "$ROAM_TEST_KEEP/"; fi  # for a look afterwards
  rm -rf "$work"
}
trap cleanup EXIT
ip netns add "$ns" 2>/dev/null || { echo "SKIPPED: cannot create network namespaces"; exit 77; }
ip -n "$ns" link set lo up && ip -n "$ns" link set lo multicast on &&
  ip -n "$ns" route add 224.0.0.0/4 dev lo || { echo "SKIPPED: cannot set up multicast in a namespace"; exit 77; }
url="udpm://239.255.76.67:7667?ttl=0"

Xvfb "$display" -screen 0 1600x900x24 -nolisten tcp >"$work/xvfb.txt" 2>&1 & xvfb_pid=$!
for _ in $(seq 50); do [ -e "/tmp/.X11-unix/X${display#:}" ] && break; sleep 0.2; done
kill -0 "$xvfb_pid" 2>/dev/null || { echo "SKIPPED: Xvfb does not start"; cat "$work/xvfb.txt"; exit 77; }

snapshot="$work/view.png"
DISPLAY="$display" ROAM_SPY_JAVA_OPTS="-Droam.spy.snapshot=$snapshot -Droam.spy.snapshot_after_s=$SNAPSHOT_AFTER_S \
-Droam.spy.geometry=1100x800+500+0 -Droam.spy.stats_s=5" \
  ip netns exec "$ns" "$bin/roam-spy" --map --lcm-url="$url" >"$work/spy.txt" 2>&1 &
disown $!  # killed at the end with the namespace: no job notice
for _ in $(seq 300); do grep -q "roam map view: listening" "$work/spy.txt" && break; sleep 0.2; done
if ! grep -q "roam.spy.MapSpyPlugin" "$work/spy.txt" || ! grep -q "roam map view: listening" "$work/spy.txt"; then
  echo "FAILED: lcm-spy did not load the roam map view plugin, or the view did not subscribe"; cat "$work/spy.txt"; exit 1
fi
ip netns exec "$ns" "$bin/roam-run" "$source/tests/live/mapview.ini" --input "$url" --output "$work/run.lcmlog" \
  >"$work/runtime.txt" 2>&1 & run_pid=$!
for _ in $(seq 100); do grep -q "live on" "$work/runtime.txt" && break; sleep 0.1; done
ip netns exec "$ns" lcm-logplayer --lcm-url="$url" -s 20 "$source/logs/plaza1.lcmlog" >/dev/null 2>&1 & player_pid=$!

for _ in $(seq $((SNAPSHOT_AFTER_S * 5 + 300))); do [ -f "$snapshot" ] && break; sleep 0.2; done
[ -f "$snapshot" ] || { echo "FAILED: the map view wrote no snapshot"; cat "$work/spy.txt"; exit 1; }
if [ -n "$screenshot" ] && command -v import >/dev/null; then
  DISPLAY="$display" import -window root "$screenshot"
fi
# The way a person opens it: lcm-spy's context menu on a roam channel offers the plugin's action.
# Right-click the table's first row (BEACONS: sorted by name, spy's window at the origin), then
# click the menu's second item ("Structure Viewer..." is the first); a second view must open.
menu_status=0
if command -v xdotool >/dev/null; then
  DISPLAY="$display" xdotool mousemove 60 25 click 3; sleep 1
  DISPLAY="$display" xdotool mousemove 100 56 click 1
  for _ in $(seq 50); do [ "$(grep -c 'roam map view: listening' "$work/spy.txt")" -ge 2 ] && break; sleep 0.2; done
  if [ "$(grep -c 'roam map view: listening' "$work/spy.txt")" -ge 2 ] &&
     DISPLAY="$display" xdotool search --name '^roam map view' >/dev/null; then
    echo "ok: lcm-spy's context menu opened a second map view"
  else
    echo "FAILED: lcm-spy's context menu did not open the map view"; menu_status=1
  fi
else
  echo "NOTE: xdotool is not installed: lcm-spy's context menu not exercised"
fi
kill "$player_pid" 2>/dev/null
kill -INT "$run_pid"
for _ in $(seq 300); do kill -0 "$run_pid" 2>/dev/null || break; sleep 0.1; done
wait "$run_pid"; run_status=$?
[ $run_status -eq 0 ] || { echo "FAILED: roam-run exited with $run_status"; cat "$work/runtime.txt"; exit 1; }
grep "roam map view" "$work/spy.txt"
cat "$snapshot.txt"

lcm_jar=/usr/share/java/lcm.jar
[ -f "$lcm_jar" ] || lcm_jar=/usr/local/share/java/lcm.jar
# Colours: roam-plot's palette in order of appearance (roam-run publishes in config order).
java -cp "$lcm_jar:$build/share/java/lcmtypes_roam.jar" "$source/tests/live/MapViewCheck.java" \
  "$snapshot" "$work/run.lcmlog" 'dr=#0072B2' 'ekf=#D55E00' || exit 1
exit $menu_status
