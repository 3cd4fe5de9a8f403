// spectral_plaza: runs the spectral core on a run in the Plaza CSV layout and prints the
// full-path mean / RMS position error against ground truth (matched by pose index), for
// both anchors and both ranks. Usage: spectral_plaza DIR [--drpath] [key=value ...]
// A measuring tool for the report: parameters are never chosen from its output.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>

#include "csv_dataset.hpp"
#include "metric_upgrade.hpp"
#include "spectral_slam.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s DIR [--drpath]\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  roam::CsvImportOptions import;
  for (int i = 2; i < argc; ++i)
    if (std::string(argv[i]) == "--drpath") import.odometry_from_path = dir + "/dead_reckoning_path.csv";
  const roam::Dataset data = roam::loadCsvDataset(dir, import);
  for (roam::SpectralAnchor anchor : {roam::SpectralAnchor::kBeacons, roam::SpectralAnchor::kStartPose}) {
    for (int rank : {4, 7}) {
      roam::SpectralConfig config;
      config.anchor = anchor;
      config.rank = rank;
      roam::SpectralSlam slam(config);
      slam.setInitialPose(data.start);
      slam.setBeacons(data.beacons);
      size_t r = 0;
      const std::clock_t cpu0 = std::clock();
      for (const roam::Odometry& odo : data.odometry) {
        while (r < data.ranges.size() && data.ranges[r].utime <= odo.utime) slam.addRange(data.ranges[r++]);
        slam.addOdometry(odo);
      }
      while (r < data.ranges.size()) slam.addRange(data.ranges[r++]);
      const std::clock_t cpu1 = std::clock();
      std::string error;
      try {
        slam.finish();
      } catch (const std::exception& e) {
        error = e.what();
      }
      const std::clock_t cpu2 = std::clock();
      double sum = 0.0, sum_sq = 0.0, heading_sum = 0.0;
      size_t n = 0;
      roam::Path path;
      if (error.empty() && slam.trajectory(true, &path)) {
        for (size_t k = 0; k < path.size() && k < data.ground_truth.size(); ++k) {
          const double e = std::hypot(path[k].x_m - data.ground_truth[k].x_m, path[k].y_m - data.ground_truth[k].y_m);
          sum += e;
          sum_sq += e * e;
          heading_sum += std::abs(roam::wrapAngle(path[k].heading_rad - data.ground_truth[k].heading_rad));
          ++n;
        }
      }
      double aligned = NAN;
      if (n > 10) {
        Eigen::Matrix2Xd est(2, n), gt(2, n);
        for (size_t k = 0; k < n; ++k) {
          est.col(k) << path[k].x_m, path[k].y_m;
          gt.col(k) << data.ground_truth[k].x_m, data.ground_truth[k].y_m;
        }
        const roam::Similarity sim = roam::fitSimilarity(est, gt);
        aligned = (sim.apply(est) - gt).colwise().norm().mean();
        std::printf("   similarity to GT: det %.4f scale %.4f angle %.4f t (%.2f, %.2f)\n", sim.linear.determinant(),
                    std::sqrt(std::abs(sim.linear.determinant())), std::atan2(sim.linear(1, 0), sim.linear(0, 0)),
                    sim.translation.x(), sim.translation.y());
      }
      std::printf("aligned %.3f  ", aligned);
      std::printf("anchor=%-10s rank=%d  mean %.3f m  rmse %.3f m  heading mean %.2f deg  solved %g  scale %.4f  cpu feed %.1f ms solve %.1f ms %s\n",
                  anchor == roam::SpectralAnchor::kBeacons ? "beacons" : "start_pose", rank,
                  n ? sum / n : NAN, n ? std::sqrt(sum_sq / n) : NAN, n ? heading_sum / n * 180 / M_PI : NAN,
                  slam.diagnostics().count("solved_poses") ? slam.diagnostics().at("solved_poses") : 0.0,
                  slam.diagnostics().count("state_scale") ? slam.diagnostics().at("state_scale") : 0.0,
                  1e3 * (cpu1 - cpu0) / CLOCKS_PER_SEC, 1e3 * (cpu2 - cpu1) / CLOCKS_PER_SEC, error.c_str());
    }
  }
  return 0;
}
