// Measuring tool (not a test): spectral_batch on a run in the Plaza 1 CSV layout, every
// init x anchor x calibration, with the full-path mean and RMS position error and CPU time.
//   spectral_batch_plaza DIR [--drpath]
// --drpath: odometry derived from DIR/dead_reckoning_path.csv (the spectral paper's setting).
#include <cmath>
#include <cstdio>
#include <ctime>
#include <exception>
#include <string>

#include "csv_dataset.hpp"
#include "spectral_batch_slam.hpp"
#include "spectral_seed.hpp"

namespace {

void feed(const roam::Dataset& data, roam::Estimator& estimator) {
  estimator.setInitialPose(data.start);
  estimator.setBeacons(data.beacons);
  size_t r = 0;
  for (const roam::Odometry& odometry : data.odometry) {
    while (r < data.ranges.size() && data.ranges[r].utime < odometry.utime) estimator.addRange(data.ranges[r++]);
    estimator.addOdometry(odometry);
  }
  while (r < data.ranges.size()) estimator.addRange(data.ranges[r++]);
  estimator.finish();
}

// Ground truth linearly interpolated at time t (clamped to its span).
void truthAt(const roam::Path& truth, int64_t utime, double* x_m, double* y_m) {
  size_t k = 1;
  while (k + 1 < truth.size() && truth[k].utime < utime) ++k;
  const roam::Pose& a = truth[k - 1];
  const roam::Pose& b = truth[k];
  double alpha = b.utime > a.utime ? static_cast<double>(utime - a.utime) / static_cast<double>(b.utime - a.utime) : 0.0;
  alpha = std::min(1.0, std::max(0.0, alpha));
  *x_m = a.x_m + alpha * (b.x_m - a.x_m);
  *y_m = a.y_m + alpha * (b.y_m - a.y_m);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s DIR [--drpath]\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  roam::CsvImportOptions options;
  if (argc > 2 && std::string(argv[2]) == "--drpath") options.odometry_from_path = dir + "/dead_reckoning_path.csv";
  const roam::Dataset data = roam::loadCsvDataset(dir, options);
  std::printf("%-14s %-11s %-6s %8s %8s %8s %7s %8s\n", "init", "anchor", "calib", "mean_m", "rmse_m",
              "cpu_s", "scale", "offset_m");
  for (const char* init : {"deadreckoning", "spectral"}) {
    if (std::string(init) == "spectral" && !roam::batch::spectralSeedAvailable()) continue;
    for (const char* anchor : {"start_pose", "beacons"}) {
      for (bool calibrate : {true, false}) {
        roam::SpectralBatchConfig config;
        config.init = init;
        config.anchor = anchor;
        config.estimate_range_scale = config.estimate_range_offset = calibrate;
        try {
          const std::clock_t start = std::clock();
          roam::SpectralBatchSlam slam(config);
          feed(data, slam);
          roam::Path path;
          slam.trajectory(true, &path);
          const double cpu_s = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
          double sum_m = 0.0, sum2_m2 = 0.0;
          for (const roam::Pose& pose : path) {
            double x_m = 0.0, y_m = 0.0;
            truthAt(data.ground_truth, pose.utime, &x_m, &y_m);
            const double error_m = std::hypot(pose.x_m - x_m, pose.y_m - y_m);
            sum_m += error_m;
            sum2_m2 += error_m * error_m;
          }
          const double n = static_cast<double>(path.size());
          std::printf("%-14s %-11s %-6s %8.3f %8.3f %8.2f %7.4f %8.3f  (init_spectral %g, %g iterations)\n", init,
                      anchor, calibrate ? "on" : "off", sum_m / n, std::sqrt(sum2_m2 / n), cpu_s,
                      slam.rangeScale(), slam.rangeOffset_m(),
                      slam.diagnostics().count("init_spectral") ? slam.diagnostics().at("init_spectral") : -1.0,
                      slam.diagnostics().at("solver_iterations"));
        } catch (const std::exception& error) {
          std::printf("%-14s %-11s %-6s failed: %s\n", init, anchor, calibrate ? "on" : "off", error.what());
        }
        std::fflush(stdout);
      }
    }
  }
  return 0;
}
