// bench_ekf: CPU per filter update with 4 surveyed beacons (state of 19: pose 3, odometry
// calibration 2, range scale and offset 2, beacons 4 x 2, each beacon's own range offset 4).
// One iteration = one odometry step carrying one range (the Plaza pattern: ~2 ranges/s at 5 Hz
// odometry, so a step holds at most one or two ranges). Target: median < 20 us.
#include <benchmark/benchmark.h>

#include <random>

#include "ekf_joint_bias.hpp"
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

// The start-pose EKF's joint solve of its pending beacons (ekf_joint_bias.hpp): K beacons with 20
// sightings each, 10 % of them 8 m long, the buffers a 64-beacon run at 10 Hz ranges holds about
// 130 s in. It runs at each range while two or more beacons are pending, so its cost is per
// range, on runs with many beacons and many outliers.
void BM_JointHeadingBias(benchmark::State& state) {
  const int beacons = static_cast<int>(state.range(0));
  std::map<int, std::vector<roam::estimation::Sighting>> sightings;
  std::map<int, roam::estimation::MultilaterationResult> start;
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI), slope(-60.0, 60.0);
  for (int k = 0; k < beacons; ++k) {
    const Eigen::Vector2d m(30.0 * std::cos(2.0 * M_PI * k / beacons), 30.0 * std::sin(2.0 * M_PI * k / beacons));
    for (int i = 0; i < 20; ++i) {
      const double b = angle(rng);
      const Eigen::Vector2d p(10.0 * std::cos(b), 10.0 * std::sin(b));
      roam::estimation::Sighting s;
      s.sigma_m = 0.3;
      s.dx_db = slope(rng);
      s.dy_db = slope(rng);
      s.x_m = p.x() - s.dx_db * 0.004;
      s.y_m = p.y() - s.dy_db * 0.004;
      s.range_m = (m - p).norm() + (i % 10 == 9 ? 8.0 : 0.0);
      sightings[k].push_back(s);
    }
    roam::estimation::MultilaterationResult own;
    own.status = roam::estimation::MultilaterationResult::Status::kReady;
    own.world_m = m + Eigen::Vector2d(0.6, -0.8);
    start[k] = own;
  }
  roam::estimation::RangeBiasPrior bias;
  bias.scale_sigma = 0.1;
  bias.offset_sigma_m = 1.0;
  bias.heading_rate_bias_sigma_rad_s = 0.01;
  for (auto _ : state) benchmark::DoNotOptimize(roam::ekf::solveJointHeadingBias(sightings, start, bias, 3.0, 6));
}
BENCHMARK(BM_JointHeadingBias)->Arg(4)->Arg(16)->Arg(64)->Repetitions(5)->ReportAggregatesOnly(true);

}  // namespace

BENCHMARK_MAIN();
