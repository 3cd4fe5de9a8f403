// ekf_plaza: runs the EKF core on the Plaza 1 CSVs (../shared/data/plaza1) and prints the
// full-path mean and RMS position error, the last-10 % mean error, the beacon error and the
// CPU time. Not a test (no ctest): a measuring tool until roam-run and its logs are the path.
//
//   ekf_plaza <data dir> odometry|drpath start_pose|beacons [key=value ...]
//
// "drpath" derives the odometry from dead_reckoning_path.csv (roam::loadCsvDataset, as
// roam-import does for logs/plaza1-drpath.lcmlog: the spectral paper's setting).
#include <cmath>
#include <cstdlib>

#include <Eigen/Geometry>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "csv_dataset.hpp"
#include "ekf_config.hpp"
#include "ekf_slam.hpp"
#include "feed.hpp"

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: ekf_plaza <data dir> odometry|drpath start_pose|beacons [key=value ...]\n");
    return 2;
  }
  const std::string dir = argv[1], odometry_kind = argv[2];
  roam::KeyValues values{{"anchor", argv[3]}};
  for (int i = 4; i < argc; ++i) {
    const std::string kv = argv[i];
    const auto eq = kv.find('=');
    values.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
  }
  roam::EkfConfig config;
  roam::Options options(values);
  roam::addEkfOptions(options, &config);
  options.parse();

  roam::CsvImportOptions import;
  if (odometry_kind == "drpath") import.odometry_from_path = dir + "/dead_reckoning_path.csv";
  const roam::Dataset data = roam::loadCsvDataset(dir, import);

  roam::EkfSlam ekf(config);
  const std::clock_t cpu_start = std::clock();
  {
    // roam::test::feed, sampling the filter's range bias every 250 steps.
    ekf.setInitialPose(data.start);
    ekf.setBeacons(data.beacons);
    size_t r = 0;
    const bool series = std::getenv("EKF_PLAZA_SERIES") != nullptr;
    for (size_t k = 0; k < data.odometry.size(); ++k) {
      while (r < data.ranges.size() && data.ranges[r].utime < data.odometry[k].utime) ekf.addRange(data.ranges[r++]);
      ekf.addOdometry(data.odometry[k]);
      if (series && k % 250 == 0 && ekf.filter().withBias()) {
        const auto& f = ekf.filter();
        std::printf("  step %5zu  scale %.4f +- %.4f  offset %.3f +- %.3f  heading error %.4f +- %.4f rad\n", k,
                    f.scale(), std::sqrt(f.covariance()(3, 3)), f.offset(), std::sqrt(f.covariance()(4, 4)),
                    roam::wrapAngle(f.mean()(2) - data.ground_truth[k + 1].heading_rad), std::sqrt(f.covariance()(2, 2)));
        if (f.withCalibration())
          std::printf("          odometry scale %.4f  heading-rate bias %.5f rad/s  beacons %zu\n", f.odometryScale(),
                      f.headingRateBias(), f.beacons().size());
      }
    }
    while (r < data.ranges.size()) ekf.addRange(data.ranges[r++]);
    ekf.finish();
  }
  const double cpu_s = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;

  const roam::Path& path = ekf.path();
  const size_t n = std::min(path.size(), data.ground_truth.size());
  double sum = 0.0, sum2 = 0.0, sum_last = 0.0, worst = 0.0;
  size_t last_count = 0;
  for (size_t k = 0; k < n; ++k) {
    const double e = std::hypot(path[k].x_m - data.ground_truth[k].x_m, path[k].y_m - data.ground_truth[k].y_m);
    sum += e;
    sum2 += e * e;
    worst = std::max(worst, e);
    if (k >= n - n / 10) {
      sum_last += e;
      ++last_count;
    }
  }
  // Best rigid 2-D fit (Umeyama without scale) of the path onto the ground truth.
  Eigen::MatrixXd src(2, n), dst(2, n);
  for (size_t k = 0; k < n; ++k) {
    src.col(k) << path[k].x_m, path[k].y_m;
    dst.col(k) << data.ground_truth[k].x_m, data.ground_truth[k].y_m;
  }
  const Eigen::Matrix3d T = Eigen::umeyama(src, dst, false);
  double sum_aligned = 0.0;
  for (size_t k = 0; k < n; ++k)
    sum_aligned += (T.topLeftCorner<2, 2>() * src.col(k) + T.topRightCorner<2, 1>() - dst.col(k)).norm();
  if (std::getenv("EKF_PLAZA_SERIES")) {
    for (size_t k = 0; k < n; k += 250)
      std::printf("  t %7.1f s  error %.2f m  sigma %.2f m\n", (path[k].utime - path[0].utime) * 1e-6,
                  std::hypot(path[k].x_m - data.ground_truth[k].x_m, path[k].y_m - data.ground_truth[k].y_m),
                  std::sqrt(path[k].covariance[0] + path[k].covariance[4]));
  }
  for (const auto& init : ekf.initialisations()) {
    for (const auto& t : data.beacons) {
      if (t.id != init.id) continue;
      std::printf("  beacon %d: entered at %.1f s, solved at %.1f s from %d ranges, batch error %.2f m "
                  "(sigma %.2f %.2f m, chi2 %.1f, rival %.1f)\n", init.id,
                  (init.first_utime - path[0].utime) * 1e-6, (init.utime - path[0].utime) * 1e-6, init.num_ranges,
                  std::hypot(init.solve.world_m.x() - t.x_m, init.solve.world_m.y() - t.y_m),
                  std::sqrt(init.solve.cov_m2(0, 0)), std::sqrt(init.solve.cov_m2(1, 1)), init.solve.chi2,
                  init.solve.rival_chi2);
    }
  }
  std::printf("aligned mean %.3f m (rotation %.4f rad)\n", sum_aligned / n, std::atan2(T(1, 0), T(0, 0)));
  double beacon_error = 0.0;
  const roam::Map map = ekf.currentMap();
  for (const auto& b : map)
    for (const auto& t : data.beacons)
      if (b.id == t.id) beacon_error += std::hypot(b.x_m - t.x_m, b.y_m - t.y_m) / map.size();
  std::printf("%s %s: mean %.3f m  rmse %.3f m  last10%% %.3f m  max %.2f m  beacons(%zu) %.3f m  "
              "scale %.4f offset %.3f  gated %lld/%lld  replays %.0f  cpu %.3f s (%.1f us/step)\n",
              odometry_kind.c_str(), config.anchor.c_str(), sum / n, std::sqrt(sum2 / n), sum_last / last_count,
              worst, map.size(), beacon_error, ekf.filter().scale(), ekf.filter().offset(),
              static_cast<long long>(ekf.rangesRejected()),
              static_cast<long long>(ekf.rangesRejected() + ekf.rangesAccepted()),
              ekf.diagnostics().at("replays"), cpu_s, 1e6 * cpu_s / n);
  for (const auto& [key, value] : ekf.diagnostics()) std::printf("  %s = %g\n", key.c_str(), value);
  return 0;
}
