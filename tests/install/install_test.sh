#!/usr/bin/env bash
# Installs roam into a fresh prefix, builds examples/constant_velocity against that install alone
# (find_package(roam CONFIG), roam_add_plugin), and replays a synthetic run with it beside a
# shipped plugin using the installed roam-run. Asserts: the plugin loads from the out-of-tree
# folder, both estimators publish a pose for every odometry step, and the constant-velocity
# filter (surveyed beacons) beats dead reckoning's error bound stated below.
#   install_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$1"; source="$2"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"
cmake --install "$build" --prefix "$prefix" >/dev/null
test -f "$prefix/lib/cmake/roam/roamConfig.cmake" || { echo "no roamConfig.cmake in lib/cmake/roam"; exit 1; }
test -f "$prefix/lib/libroam_sdk.a" || { echo "no SDK library in lib/"; exit 1; }
# Ceres hidden from the example's configure: the SDK's package needs only what the SDK needs.
cmake -S "$source/examples/constant_velocity" -B "$work/cv" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_DISABLE_FIND_PACKAGE_Ceres=TRUE >/dev/null
cmake --build "$work/cv" >/dev/null
test -f "$work/cv/libroam_constant_velocity.so" || { echo "the example did not build a plugin"; exit 1; }
cat > "$work/run.ini" <<INI
[runtime]
input = $prefix/share/roam/logs/synthetic/lawnmower-4beacons.lcmlog
output = $work/out.lcmlog
plugin_path = $work/cv

[estimator.cv]
plugin = constant_velocity

[estimator.dr]
plugin = deadreckoning
INI
"$prefix/bin/roam-run" "$work/run.ini" > "$work/run.txt" 2>&1 || { cat "$work/run.txt"; exit 1; }
"$prefix/bin/roam-eval" "$work/out.lcmlog" --format csv > "$work/eval.csv"
cat "$work/eval.csv"
# run,estimator,scored,matched,full_mean_m,...: every ground-truth pose matched (3001), and the
# filter's mean error under 1 m on this 4-beacon lawn mower (range sigma 0.4 m at 2 Hz).
awk -F, '$2=="cv" { found=1; if ($4 != 3001) { print "cv matched " $4 " of 3001"; exit 1 }
                    if ($5 >= 1.0) { print "cv mean error " $5 " m, expected < 1 m"; exit 1 } }
         END { if (!found) { print "no cv row"; exit 1 } }' "$work/eval.csv"
awk -F, '$2=="dr" && $4 != 3001 { print "dr matched " $4; exit 1 }' "$work/eval.csv"
echo "install test: ok"
