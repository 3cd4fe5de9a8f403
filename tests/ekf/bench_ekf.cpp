// bench_ekf: CPU per filter update with 4 surveyed beacons (state of 19: pose 3, odometry
// calibration 2, range scale and offset 2, beacons 4 x 2, each beacon's own range offset 4).
// One iteration = one odometry step carrying one range (the Plaza pattern: ~2 ranges/s at 5 Hz
// odometry, so a step holds at most one or two ranges). Target: median < 20 us.
#include <benchmark/benchmark.h>

#include "ekf_slam.hpp"
#include "sim.hpp"

namespace {

roam::sim::SimRun benchRun() {
  roam::sim::SimConfig c;
  c.seed = 42;
  c.num_steps = 20000;
  c.path = roam::sim::PathKind::kRandomWalk;
  c.area_width_m = 40.0;
  c.area_height_m = 40.0;
  c.num_beacons = 4;
  c.schedule = roam::sim::RangeSchedule::kRoundRobin;
  c.range_rate_hz = 5.0;  // one range per 0.2 s step
  c.odo_distance_sigma_rel = 0.02;
  c.odo_heading_sigma_rad = 0.002;
  c.range_sigma_m = 0.3;
  return roam::sim::simulate(c);
}

void BM_EkfStepWithRange(benchmark::State& state) {
  static const roam::sim::SimRun run = benchRun();
  roam::ekf::EkfConfig config;
  config.anchor = roam::ekf::EkfConfig::Anchor::kBeacons;  // all 4 beacons in the state from the start
  auto ekf = std::make_unique<roam::ekf::EkfSlam>(config);
  ekf->setInitialPose(run.start);
  ekf->setBeacons(run.beacons);
  size_t k = 0, r = 0;
  for (auto _ : state) {
    if (k == run.odometry.size()) {
      state.PauseTiming();
      ekf = std::make_unique<roam::ekf::EkfSlam>(config);
      ekf->setInitialPose(run.start);
      ekf->setBeacons(run.beacons);
      k = r = 0;
      state.ResumeTiming();
    }
    while (r < run.ranges.size() && run.ranges[r].utime < run.odometry[k].utime) ekf->addRange(run.ranges[r++]);
    ekf->addOdometry(run.odometry[k++]);
    benchmark::DoNotOptimize(ekf->takePoses());
  }
}
BENCHMARK(BM_EkfStepWithRange)->Repetitions(10)->ReportAggregatesOnly(true);

}  // namespace

BENCHMARK_MAIN();
