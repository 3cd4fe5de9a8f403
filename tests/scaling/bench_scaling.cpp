// bench_scaling: how the batch solvers grow with the length of the run T (odometry steps) and
// the number of beacons N, on synthetic runs built in memory by roam::sim::simulate.
//
// World: a lawn-mower path at 1 m/s, 5 Hz odometry (0.2 s steps), over a 60 m x 50 m area with
// 5 m lanes (the robot sweeps it back and forth as long as the run lasts); N beacons uniform in
// the area plus a 10 m margin; odometry noise 2 % of distance and 0.002 rad per step; UWB-like
// round-robin ranges with 0.5 m noise. The range rate grows with N: 0.5 N ranges per second,
// so every beacon is ranged at 0.5 Hz whatever N is, and the spectral interpolation window
// (16 ranges of the least-ranged beacon) stays at 32 s. At a fixed total rate the window would
// grow with N (8 beacons at 2 Hz: 64 s) and then hit its cap, which measures the window rule,
// not the solver.
//
//   BM_Spectral/T:<steps>/N:<beacons>  roam::spectral::solveSpectral, rank 7, the plugin's default config
//                                      (robust window fits, anchor = surveyed beacons); the
//                                      problem is built before timing. Expected O(N^2 T).
//   BM_Batch/T:<steps>/N:<beacons>     spectral_batch with its default config (spectral seed,
//                                      Ceres, range scale and offset) but anchor = surveyed
//                                      beacons: a whole estimator run, fed and finished, as
//                                      bench_spectral_batch times it.
//
// Counters: per_step (CPU per odometry step), peak_rss_MB (peak resident memory while solving:
// the peak is reset after the input is built, so it holds the input plus the solver's own
// memory), input_rss_MB (resident memory before the first solve), mean_error_m (against ground
// truth: the solve is a real one), window_s (spectral), sys_share (the kernel's part of the CPU
// time: first touches of the pages of freshly allocated matrices). Times are process CPU time
// (user + kernel).
//
// Options before Google Benchmark's own: --quick (T up to 3e4 only, for a smoke run);
// --batch-max-steps=T (largest T for the batch solver, default 100000).
// utilities/scaling runs every configuration in a fresh process (peak memory per configuration).
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "feed.hpp"
#include "sim.hpp"
#include "spectral_batch_slam.hpp"
#include "spectral_slam.hpp"

namespace {

roam::sim::SimConfig worldConfig(int steps, int beacons) {
  roam::sim::SimConfig c;
  c.seed = 7;
  c.num_steps = steps;
  c.dt_s = 0.2;
  c.speed_mps = 1.0;
  c.path = roam::sim::PathKind::kLawnMower;
  c.area_width_m = 60.0;
  c.area_height_m = 50.0;
  c.lane_spacing_m = 5.0;
  c.num_beacons = beacons;
  c.beacon_margin_m = 10.0;
  c.odo_distance_sigma_rel = 0.02;
  c.odo_heading_sigma_rad = 0.002;
  c.schedule = roam::sim::RangeSchedule::kRoundRobin;
  c.range_rate_hz = 0.5 * beacons;  // 0.5 Hz per beacon
  c.range_sigma_m = 0.5;
  return c;
}

// /proc/self/status field in kB (VmRSS, VmHWM), or -1.
double statusKb(const char* field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  const size_t n = std::strlen(field);
  while (std::getline(status, line)) {
    if (line.compare(0, n, field) == 0 && line.size() > n && line[n] == ':') return std::atof(line.c_str() + n + 1);
  }
  return -1.0;
}

// Resets the peak resident size (Linux >= 4.0); false where that is not allowed.
bool resetPeakRss() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.flush();
  return static_cast<bool>(clear);
}

double peakRssMb() {
  const double hwm_kb = statusKb("VmHWM");
  if (hwm_kb >= 0.0) return hwm_kb / 1024.0;
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

// The run of the current configuration, built once per process and kept (Google Benchmark calls
// a benchmark function several times: iteration estimate, repetitions).
const roam::Dataset& world(int steps, int beacons) {
  static std::map<std::pair<int, int>, std::unique_ptr<roam::Dataset>> cache;
  auto& slot = cache[{steps, beacons}];
  if (!slot) slot = std::make_unique<roam::Dataset>(roam::sim::simulate(worldConfig(steps, beacons)));
  return *slot;
}

double meanError_m(const roam::Path& path, const roam::Path& truth) {
  return path.size() == truth.size() ? roam::test::meanError_m(path, truth) : -1.0;
}

double seconds(const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); }

// User and kernel CPU of the process so far.
struct CpuSplit {
  double user_s = 0.0, sys_s = 0.0;
  static CpuSplit now() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return {seconds(usage.ru_utime), seconds(usage.ru_stime)};
  }
};

// sys_share: the kernel's part of the timed CPU (page faults of freshly allocated matrices).
void setCommonCounters(benchmark::State& state, const roam::Dataset& data, double input_rss_mb,
                       const CpuSplit& before) {
  const CpuSplit after = CpuSplit::now();
  const double user_s = after.user_s - before.user_s, sys_s = after.sys_s - before.sys_s;
  state.counters["sys_share"] = user_s + sys_s > 0.0 ? sys_s / (user_s + sys_s) : 0.0;
  const double steps = static_cast<double>(data.odometry.size());
  state.counters["per_step"] =
      benchmark::Counter(steps, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["ranges"] = static_cast<double>(data.ranges.size());
  state.counters["input_rss_MB"] = input_rss_mb;
  state.counters["peak_rss_MB"] = peakRssMb();
}

void BM_Spectral(benchmark::State& state) {
  const int steps = static_cast<int>(state.range(0)), beacons = static_cast<int>(state.range(1));
  static std::map<std::pair<int, int>, std::unique_ptr<roam::spectral::SpectralProblem>> problems;
  roam::spectral::SpectralConfig config;  // rank 7, robust fits, anchor = beacons: the plugin's defaults
  auto& problem = problems[{steps, beacons}];
  if (!problem) {
    const roam::Dataset& data = world(steps, beacons);
    roam::spectral::SpectralSlam slam(config);
    slam.setInitialPose(data.start);
    slam.setBeacons(data.beacons);
    for (const auto& odometry : data.odometry) slam.addOdometry(odometry);
    for (const auto& range : data.ranges) slam.addRange(range);
    problem = std::make_unique<roam::spectral::SpectralProblem>(slam.problem());
  }
  const roam::Dataset& data = world(steps, beacons);
  const double input_rss_mb = statusKb("VmRSS") / 1024.0;
  resetPeakRss();
  roam::spectral::SpectralSolution solution;
  const CpuSplit before = CpuSplit::now();
  for (auto _ : state) {
    solution = roam::spectral::solveSpectral(*problem, config);
    benchmark::DoNotOptimize(solution.trajectory.data());
  }
  setCommonCounters(state, data, input_rss_mb, before);
  state.counters["mean_error_m"] = meanError_m(solution.trajectory, data.ground_truth);
  state.counters["window_s"] = solution.window_s;
}

void BM_Batch(benchmark::State& state) {
  const int steps = static_cast<int>(state.range(0)), beacons = static_cast<int>(state.range(1));
  const roam::Dataset& data = world(steps, beacons);
  roam::spectral_batch::SpectralBatchConfig config;  // spectral seed, Ceres, range scale and offset: defaults,
  config.anchor = roam::spectral_batch::SpectralBatchConfig::Anchor::kBeacons;  // but surveyed beacons fix the frame, as in BM_Spectral
  const double input_rss_mb = statusKb("VmRSS") / 1024.0;
  resetPeakRss();
  roam::Path path;
  double iterations = 0.0;
  const CpuSplit before = CpuSplit::now();
  for (auto _ : state) {
    roam::spectral_batch::SpectralBatchSlam slam(config);
    roam::test::feed(data, slam);
    slam.trajectory(true, &path);
    iterations = slam.diagnostics().at("solver_iterations");
  }
  setCommonCounters(state, data, input_rss_mb, before);
  state.counters["mean_error_m"] = meanError_m(path, data.ground_truth);
  state.counters["solver_iterations"] = iterations;
}

// Removes "--name" or "--name=value" from argv; returns whether it was there (and its value).
bool takeFlag(int* argc, char** argv, const char* name, std::string* value) {
  const size_t n = std::strlen(name);
  for (int i = 1; i < *argc; ++i) {
    if (std::strncmp(argv[i], name, n) == 0 && (argv[i][n] == '\0' || argv[i][n] == '=')) {
      if (value != nullptr && argv[i][n] == '=') *value = argv[i] + n + 1;
      for (int j = i; j + 1 < *argc; ++j) argv[j] = argv[j + 1];
      --*argc;
      return true;
    }
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = takeFlag(&argc, argv, "--quick", nullptr);
  std::string batch_max = "100000";
  takeFlag(&argc, argv, "--batch-max-steps", &batch_max);
  const long batch_max_steps = std::atol(batch_max.c_str());

  const std::vector<int> all_steps = {10000, 30000, 100000, 300000, 1000000};
  for (const int steps : all_steps) {
    if (quick && steps > 30000) break;
    for (const int beacons : {4, 16, 64}) {
      benchmark::RegisterBenchmark("BM_Spectral", BM_Spectral)
          ->Args({steps, beacons})
          ->ArgNames({"T", "N"})
          ->Unit(benchmark::kMillisecond)
          ->MeasureProcessCPUTime();
    }
  }
  for (const int steps : all_steps) {
    if ((quick && steps > 30000) || steps > batch_max_steps) break;
    for (const int beacons : {4, 16}) {
      benchmark::RegisterBenchmark("BM_Batch", BM_Batch)
          ->Args({steps, beacons})
          ->ArgNames({"T", "N"})
          ->Unit(benchmark::kMillisecond)
          ->MeasureProcessCPUTime();
    }
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
