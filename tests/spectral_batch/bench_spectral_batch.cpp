// Benchmark (not in ctest): the Plaza-sized batch solve - 9,658 poses at 5 Hz, 4 beacons,
// ~3,500 round-robin ranges (1.83 Hz), ranges 7 % long, UWB-like noise - from dead reckoning
// and, when the spectral core is built in, from the spectral seed (its time included).
#include <benchmark/benchmark.h>

#include "feed.hpp"
#include "sim.hpp"
#include "spectral_batch_slam.hpp"
#include "spectral_seed.hpp"

namespace {

const roam::Dataset& plazaSized() {
  static const roam::Dataset data = [] {
    roam::sim::SimConfig config;
    config.seed = 1;
    config.num_steps = 9657;
    config.dt_s = 0.2;
    config.area_width_m = 50.0;
    config.area_height_m = 40.0;
    config.lane_spacing_m = 4.0;
    config.schedule = roam::sim::RangeSchedule::kRoundRobin;
    config.range_rate_hz = 1.83;
    config.odo_distance_sigma_rel = 0.02;
    config.odo_heading_sigma_rad = 0.002;
    config.range_sigma_m = 0.5;
    config.range_scale = 1.07;
    return roam::sim::simulate(config);
  }();
  return data;
}

void solve(benchmark::State& state, const char* init) {
  const roam::Dataset& data = plazaSized();
  roam::spectral_batch::SpectralBatchConfig config;
  roam::setOptions(&config, roam::spectral_batch::addSpectralBatchOptions, {{"init", init}});
  double error_m = 0.0;
  for (auto _ : state) {
    roam::spectral_batch::SpectralBatchSlam slam(config);
    roam::test::feed(data, slam);
    roam::Path path;
    slam.trajectory(true, &path);
    error_m = roam::test::meanError_m(path, data.ground_truth);
    state.counters["iterations"] = slam.diagnostics().at("solver_iterations");
    state.counters["scale"] = slam.rangeScale();
  }
  state.counters["mean_error_m"] = error_m;
  state.counters["poses"] = static_cast<double>(data.odometry.size() + 1);
  state.counters["ranges"] = static_cast<double>(data.ranges.size());
}

void BM_BatchFromDeadReckoning(benchmark::State& state) { solve(state, "deadreckoning"); }
BENCHMARK(BM_BatchFromDeadReckoning)->Unit(benchmark::kMillisecond);

void BM_SpectralPlusBatch(benchmark::State& state) {
  if (!roam::spectral_batch::spectralSeedAvailable()) {
    state.SkipWithError("built without the spectral core");
    for (auto _ : state) {
    }
    return;
  }
  solve(state, "spectral");
}
BENCHMARK(BM_SpectralPlusBatch)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
