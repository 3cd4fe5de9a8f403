#!/usr/bin/env bash
# A team live on a bus spread over several hosts, inside private network namespaces (no packet
# can leave the machine). Exit 77 (ctest: skipped) where namespaces cannot be created.
#
#   live_team_test.sh BUILD_DIR SOURCE_DIR RECORDER
#
# roam-sim writes a short team of three robots (A, B, C). Each robot's host (its own namespace)
# plays only that robot's channels (ODOMETRY_R, RANGE_R, ROBOT_RANGE_R, INITIAL_POSE_R,
# GROUND_TRUTH_R; robot A's host also BEACONS) with lcm-logplayer's channel filter, all three at
# once at ROAM_LIVE_SPEED (default 20x). A base station's namespace runs roam-run with the
# [team] config tests/live/team.ini and the recorder (bus_recorder.cpp). The hosts are joined by
# a bridge in a fourth namespace (multicast routed over veth, ttl=1), as in live_bus_test.sh's
# three-hosts mode. Every robot's odometry and ranges must reach roam-run, and its live output
# must score as the deterministic replay of the whole team log does (roam-eval's team and
# per-robot rows).
set -uo pipefail
build="$1"; source="$2"; recorder="${3:-}"
speed="${ROAM_LIVE_SPEED:-20}"
tolerance_m=0.001
bin="$build/bin"
config="$source/tests/live/team.ini"
robots=(A B C)
work="$(mktemp -d "$build/tests/live-team.XXXXXX")"
prefix="roamteam$$"
namespaces=()

cleanup() {
  for ns in "${namespaces[@]}"; do
    ip netns pids "$ns" 2>/dev/null | xargs -r kill -9 2>/dev/null
    ip netns del "$ns" 2>/dev/null
  done
  rm -rf "$work"
}
trap cleanup EXIT

skip() { echo "SKIPPED: $*"; exit 77; }
fail() { echo "FAILED: $*"; for f in "$work"/*.txt; do echo "--- $f"; tail -20 "$f"; done; exit 1; }
[ -x "$recorder" ] || fail "no recorder: give the path of bus_recorder as the third argument"

make_ns() {  # name: a namespace with multicast on lo
  ip netns add "$1" 2>/dev/null || skip "cannot create network namespaces here (needs root and iproute2)"
  namespaces+=("$1")
  ip -n "$1" link set lo up
  ip -n "$1" link set lo multicast on
}

url="udpm://239.255.76.67:7667?ttl=1"
recv_buf="recv_buf_size=4194304"

# The team: 3 robots, 400 steps of 0.2 s (80 s of data, 4 s at 20x).
log="$work/team.lcmlog"
"$bin/roam-sim" -o "$log" --robots 3 --steps 400 --odo-distance-sigma-rel 0.03 --odo-heading-sigma 0.01 \
  --range-sigma 0.1 >"$work/sim.txt" 2>&1 || fail "roam-sim failed"

switch="${prefix}sw"; make_ns "$switch"
ip -n "$switch" link add br0 type bridge
ip -n "$switch" link set br0 type bridge mcast_snooping 0
ip -n "$switch" link set br0 up
i=1
for role in base "${robots[@]}"; do
  ns="${prefix}$role"; make_ns "$ns"
  ip -n "$switch" link add "v$role" type veth peer name eth0 netns "$ns"
  ip -n "$switch" link set "v$role" master br0 up
  ip -n "$ns" addr add "10.213.1.$i/24" dev eth0
  ip -n "$ns" link set eth0 up
  ip -n "$ns" link set eth0 multicast on
  ip -n "$ns" route add 224.0.0.0/4 dev eth0
  i=$((i + 1))
done
ns_base="${prefix}base"

# Reference: the deterministic replay of the whole team log.
"$bin/roam-run" "$config" --no-progress --input "$log" --output "$work/replay.lcmlog" >"$work/replay.txt" 2>&1 \
  || fail "the reference replay failed"

ip netns exec "$ns_base" "$recorder" "$url&$recv_buf" "$work/recorded.lcmlog" >"$work/logger.txt" 2>&1 &
logger_pid=$!
ip netns exec "$ns_base" "$bin/roam-run" "$config" --input "$url" --output "$work/live.lcmlog" \
  >"$work/runtime.txt" 2>&1 &
runtime_pid=$!
for _ in $(seq 600); do grep -q "live on" "$work/runtime.txt" && grep -q "recording" "$work/logger.txt" && break; sleep 0.1; done
grep -q "live on" "$work/runtime.txt" || fail "roam-run did not go live within 60 s"
grep -q "recording" "$work/logger.txt" || fail "the recorder did not start within 60 s"
sleep 0.5

start=$(date +%s.%N)
player_pids=()
for robot in "${robots[@]}"; do
  channels="(ODOMETRY|RANGE|ROBOT_RANGE|INITIAL_POSE|GROUND_TRUTH)_$robot"
  [ "$robot" = "${robots[0]}" ] && channels="$channels|BEACONS"
  ip netns exec "${prefix}$robot" lcm-logplayer --lcm-url="$url" -s "$speed" -e "^($channels)\$" "$log" \
    >"$work/player-$robot.txt" 2>&1 &
  player_pids+=($!)
done
for pid in "${player_pids[@]}"; do wait "$pid" || fail "an lcm-logplayer failed"; done
played=$(python3 -c "import sys; print(round(float(sys.argv[2]) - float(sys.argv[1]), 1))" "$start" "$(date +%s.%N)")
sleep 1
kill -INT "$runtime_pid"; wait "$runtime_pid"; status=$?
sleep 0.5
kill -INT "$logger_pid"; wait "$logger_pid" 2>/dev/null
[ "$status" -eq 0 ] || fail "roam-run exited $status"
cat "$work/runtime.txt"

# No input lost: every robot's odometry, ranges and ranges between robots reached roam-run.
expected=$("$bin/roam-logcheck" "$log" | awk '$1~/^(ODOMETRY|RANGE|ROBOT_RANGE)_/{n+=$2} END{print n}')
received=$(grep -o "input: [0-9]* events, [0-9]* odometry, [0-9]* ranges, [0-9]* ranges between robots" \
  "$work/runtime.txt" | awk '{print $4+$6+$8}')
[ "$expected" = "$received" ] || fail "roam-run received $received odometry+range messages, the log has $expected"

"$bin/roam-eval" "$work/replay.lcmlog" --format csv >"$work/replay-score.txt" 2>&1 || fail "roam-eval (replay)"
grep -q ",team_batch,team," "$work/replay-score.txt" || fail "no team row of team_batch in the replay's scores"
"$bin/roam-eval" "$work/live.lcmlog" --format csv >"$work/live-score.txt" 2>&1 || fail "roam-eval (live)"
python3 "$source/tests/live/compare_scores.py" "$work/replay-score.txt" "$work/live-score.txt" 1e-9 \
  || fail "roam-run's live output log differs from the replay"
"$bin/roam-eval" "$work/recorded.lcmlog" --format csv >"$work/recorded-score.txt" 2>&1 || fail "roam-eval (recorded)"
python3 "$source/tests/live/compare_scores.py" "$work/replay-score.txt" "$work/recorded-score.txt" "$tolerance_m" \
  || fail "live estimates recorded on the bus differ from the replay"
echo "PASSED (team): ${#robots[@]} robots from ${#robots[@]} hosts, $received messages at ${speed}x in ${played}s," \
  "estimates match the replay"
