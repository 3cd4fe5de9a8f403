// bench_online_em: a Plaza-sized replay through the online EM core (9,658 poses = 9,657
// odometry steps at 5 Hz, round-robin ranges to 4 beacons at 1.83 Hz, 100 particles).
// Target: < 5 s CPU for the whole replay (1,933 s of data: >= 400x real time).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "feed.hpp"
#include "online_em_slam.hpp"
#include "roam/estimation/multilateration.hpp"
#include "sim.hpp"

namespace {

roam::Dataset plazaSized() {
  roam::sim::SimConfig c;
  c.seed = 1;
  c.num_steps = 9657;
  c.path = roam::sim::PathKind::kLawnMower;
  c.area_width_m = 40.0;
  c.area_height_m = 40.0;
  c.schedule = roam::sim::RangeSchedule::kRoundRobin;
  c.range_rate_hz = 1.83;
  c.odo_distance_sigma_rel = 0.02;
  c.odo_heading_sigma_rad = 0.005;
  c.range_sigma_m = 0.5;
  c.range_scale = 1.07;
  c.beacons = {{0, -10.0, -8.0, {}}, {1, 50.0, -6.0, {}}, {5, 48.0, 50.0, {}}, {6, -8.0, 47.0, {}}};
  return roam::sim::simulate(c);
}

void BM_PlazaSizedReplay(benchmark::State& state) {
  const roam::Dataset data = plazaSized();
  roam::online_em::OnlineEmConfig config;
  config.num_particles = static_cast<int>(state.range(0));
  for (auto _ : state) {
    roam::online_em::OnlineEmSlam slam(config);
    roam::online_em_test::feed(data, slam);
    benchmark::DoNotOptimize(slam.filteredPath().back().x_m);
    state.counters["error_m"] = roam::online_em_test::meanError(slam.filteredPath(), data.ground_truth);
  }
  // The same counters in every benchmark of this file: Google Benchmark's CSV report (what
  // utilities/benchmarks reads) refuses a counter one run lacks. n: steps here, ranges below.
  state.counters["n"] = static_cast<double>(data.odometry.size());
}
BENCHMARK(BM_PlazaSizedReplay)->Arg(100)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->Iterations(1);

// A landmark's initialisation by the consensus of triples (estimation::multilaterateTriples):
// n ranges along a lane and its turn, 40 % of them 2-40 m long; range(1) = max_triples (0: the
// default, 20,000; 1: every triple). At 50 Hz odometry and 10 Hz ranges a landmark first tried
// after a 60 m lane holds ~170 ranges.
void BM_LandmarkTriples(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  std::vector<std::array<double, 2>> positions;
  std::vector<double> ranges;
  for (int k = 0; k < n; ++k) {
    const double s_m = 60.0 * k / n;
    positions.push_back({std::min(s_m, 50.0), std::max(0.0, s_m - 50.0)});
    ranges.push_back(std::hypot(30.0 - positions.back()[0], 12.0 - positions.back()[1]) + (k % 5 < 2 ? 2.0 + 0.23 * k : 0.0));
  }
  std::array<double, 2> beacon_m{};
  for (auto _ : state) {
    const bool solved = state.range(1) == 1 ? roam::estimation::multilaterateTriples(positions, ranges, 1.0, &beacon_m, 1 << 30)
                                            : roam::estimation::multilaterateTriples(positions, ranges, 1.0, &beacon_m);
    benchmark::DoNotOptimize(solved);
  }
  state.counters["error_m"] = std::hypot(beacon_m[0] - 30.0, beacon_m[1] - 12.0);  // the beacon's
  state.counters["n"] = n;
}
BENCHMARK(BM_LandmarkTriples)->Args({19, 0})->Args({100, 0})->Args({100, 1})->Args({170, 0})->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
