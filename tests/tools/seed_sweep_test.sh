#!/usr/bin/env bash
# utilities/seed-sweep: its table holds what roam-eval measures on the runs it says it made, and
# bad arguments are refused with the key named.
#   seed_sweep_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$1"
source="$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
sweep="$source/utilities/seed-sweep"
export ROAM_BUILD_DIR="$build"
fail() { echo "seed_sweep_test: FAIL: $*" >&2; exit 1; }

# Bad arguments: exit 2 and the offending value named.
status=0; "$sweep" --kinds nlos30,foo --results "$work/r" 2>"$work/err" >/dev/null || status=$?
[ "$status" -eq 2 ] || fail "unknown kind: exit $status, expected 2"
grep -q "unknown kind 'foo'" "$work/err" || fail "unknown kind not named: $(cat "$work/err")"
status=0; "$sweep" --config "$work/missing.ini" --results "$work/r" 2>"$work/err" >/dev/null || status=$?
[ "$status" -eq 2 ] && grep -q "missing.ini" "$work/err" || fail "missing config: exit $status, $(cat "$work/err")"

# Two seeds of one kind through dead reckoning and the EKF with beacons.
cat >"$work/sweep.ini" <<'INI'
[runtime]
input = unused.lcmlog
[estimator.deadreckoning]
plugin = deadreckoning
[estimator.ekf_beacons]
plugin = ekf
anchor = beacons
INI
status=0; "$sweep" --summary ekf_start --config "$work/sweep.ini" --results "$work/r" 2>"$work/err" >/dev/null || status=$?
[ "$status" -eq 2 ] && grep -q "summary names 'ekf_start'.*its estimators: deadreckoning, ekf_beacons" "$work/err" ||
  fail "unknown --summary column: exit $status, $(cat "$work/err")"
"$sweep" --seeds 2 --first-seed 7 --kinds nlos30 --config "$work/sweep.ini" --jobs 1 --results "$work/r" >"$work/table.md"

# The same runs made by hand (the options --list prints) and scored by roam-eval.
options="$("$sweep" --list | awk '/^nlos30:/ { getline; sub(/^  roam-sim /, ""); sub(/ --seed SEED$/, ""); print }')"
[ -n "$options" ] || fail "--list has no nlos30 options"
declare -A expected
for seed in 7 8; do
  # shellcheck disable=SC2086  # the options are split on purpose
  "$build/bin/roam-sim" -o "$work/in-$seed.lcmlog" --seed "$seed" $options >/dev/null
  "$build/bin/roam-run" "$work/sweep.ini" --input "$work/in-$seed.lcmlog" --output "$work/out-$seed.lcmlog" --no-progress >/dev/null 2>&1
  for estimator in deadreckoning ekf_beacons; do
    expected[$estimator-$seed]="$("$build/bin/roam-eval" "$work/out-$seed.lcmlog" --format csv |
      awk -F, -v e="$estimator" '$2 == e { printf "%.6f", $5 }')"
  done
done
for estimator in deadreckoning ekf_beacons; do
  a="${expected[$estimator-7]}"; b="${expected[$estimator-8]}"
  [ -n "$a" ] && [ -n "$b" ] || fail "roam-eval scored no $estimator"
  row="$(python3 -c "
a, b = $a, $b
dr = {7: ${expected[deadreckoning-7]}, 8: ${expected[deadreckoning-8]}}
worst, seed = (a, 7) if a >= b else (b, 8)
ratio, ratio_seed = (b / dr[8], 8) if b / dr[8] > a / dr[7] else (a / dr[7], 7)
print('| $estimator | %.2f | %.2f | %.2f (%d) | %.2f (%d) |  |' % ((a + b) / 2, (a + b) / 2, worst, seed, ratio, ratio_seed))")"
  grep -qxF "$row" "$work/table.md" || fail "expected row '$row' in:
$(cat "$work/table.md")"
done
# The summary matrix: median (the mean of two seeds) and worst of each default column the config has.
median_worst() { python3 -c "a, b = $1, $2; print('%.2f (%.2f)' % ((a + b) / 2, max(a, b)))"; }
row="| nlos30 | $(median_worst "${expected[deadreckoning-7]}" "${expected[deadreckoning-8]}") | $(median_worst "${expected[ekf_beacons-7]}" "${expected[ekf_beacons-8]}") |"
[ "$(head -1 "$work/r/seed-sweep-summary.md")" = "| kind | dead reckoning | EKF, beacons |" ] ||
  fail "summary header: $(head -1 "$work/r/seed-sweep-summary.md")"
grep -qxF "$row" "$work/r/seed-sweep-summary.md" || fail "expected summary row '$row' in:
$(cat "$work/r/seed-sweep-summary.md")"
grep -qxF "$row" "$work/table.md" || fail "the printed output lacks the summary row '$row'"
# The EKF with surveyed beacons holds on this kind (30 % NLOS): well under dead reckoning.
python3 -c "import sys; sys.exit(0 if ${expected[ekf_beacons-7]} < 0.5 and ${expected[ekf_beacons-8]} < 0.5 else 1)" ||
  fail "ekf_beacons ${expected[ekf_beacons-7]} / ${expected[ekf_beacons-8]} m on nlos30"
[ "$(grep -c '^nlos30,' "$work/r/seed-sweep.csv")" -eq 6 ] || fail "seed-sweep.csv: expected 6 nlos30 rows"
grep -q "ekf_beacons" "$work/r/seed-sweep/nlos30-7.txt" || fail "no roam-run summary kept"
echo "seed_sweep_test: ok"
