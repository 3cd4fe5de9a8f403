// bench_spectral: CPU time of the batch solve on a Plaza-sized synthetic run (9,658 poses,
// 4 beacons, round-robin UWB-like ranges at 1.83 Hz) and of online mode per odometry step.
#include <benchmark/benchmark.h>

#include "sim.hpp"
#include "spectral_slam.hpp"

namespace {

const roam::sim::SimRun& plazaSized() {
  static const roam::sim::SimRun run = [] {
    roam::sim::SimConfig c;
    c.seed = 1;
    c.num_steps = 9657;
    c.path = roam::sim::PathKind::kLawnMower;
    c.area_width_m = 60.0;
    c.area_height_m = 50.0;
    c.num_beacons = 4;
    c.schedule = roam::sim::RangeSchedule::kRoundRobin;
    c.range_rate_hz = 1.83;
    c.range_sigma_m = 0.5;
    c.odo_distance_sigma_rel = 0.02;
    return roam::sim::simulate(c);
  }();
  return run;
}

roam::spectral::SpectralProblem problemOf(const roam::sim::SimRun& run, const roam::spectral::SpectralConfig& config) {
  roam::spectral::SpectralSlam slam(config);
  slam.setInitialPose(run.start);
  slam.setBeacons(run.beacons);
  for (const auto& odometry : run.odometry) slam.addOdometry(odometry);
  for (const auto& range : run.ranges) slam.addRange(range);
  return slam.problem();
}

// The whole batch solve: interpolation, Gram SVD, upgrade, bridging.
void BM_BatchSolve(benchmark::State& state) {
  roam::spectral::SpectralConfig config;
  config.rank = static_cast<int>(state.range(0));
  const roam::spectral::SpectralProblem problem = problemOf(plazaSized(), config);
  for (auto _ : state) benchmark::DoNotOptimize(roam::spectral::solveSpectral(problem, config));
}
BENCHMARK(BM_BatchSolve)->Arg(4)->Arg(7)->Unit(benchmark::kMillisecond);

// Baseline in the same run: the paper's plain least-squares window fits, no trimmed refit.
void BM_BatchSolvePlainLeastSquares(benchmark::State& state) {
  roam::spectral::SpectralConfig config;
  config.rank = static_cast<int>(state.range(0));
  config.robust_interpolation = false;
  const roam::spectral::SpectralProblem problem = problemOf(plazaSized(), config);
  for (auto _ : state) benchmark::DoNotOptimize(roam::spectral::solveSpectral(problem, config));
}
BENCHMARK(BM_BatchSolvePlainLeastSquares)->Arg(4)->Arg(7)->Unit(benchmark::kMillisecond);

// Online mode: one odometry step (with its ranges); the mean over the whole run.
void BM_OnlineStep(benchmark::State& state) {
  const auto& run = plazaSized();
  roam::spectral::SpectralConfig config;
  config.mode = roam::spectral::SpectralMode::kOnline;
  std::unique_ptr<roam::spectral::SpectralSlam> slam;
  size_t step = 0, r = 0;
  for (auto _ : state) {
    if (!slam || step == run.odometry.size()) {
      state.PauseTiming();
      slam = std::make_unique<roam::spectral::SpectralSlam>(config);
      slam->setInitialPose(run.start);
      slam->setBeacons(run.beacons);
      step = 0;
      r = 0;
      state.ResumeTiming();
    }
    slam->addOdometry(run.odometry[step]);
    while (r < run.ranges.size() && run.ranges[r].utime <= run.odometry[step].utime) slam->addRange(run.ranges[r++]);
    benchmark::DoNotOptimize(slam->takePoses());
    ++step;
  }
}
BENCHMARK(BM_OnlineStep)->Unit(benchmark::kMicrosecond)->Iterations(9657)->Repetitions(1);

}  // namespace

BENCHMARK_MAIN();
