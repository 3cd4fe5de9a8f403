// online_em_plaza: runs the online EM core on a run in the Plaza 1 CSV layout and prints the
// full-path mean error, RMSE, last-10 % mean error, beacon error, range scale/offset and CPU time.
// A measuring tool (not a test): parameters are never searched with it.
//
//   online_em_plaza <data dir> odometry|drpath start_pose|beacons [key=value ...]
#include <cstdio>
#include <ctime>
#include <string>

#include "csv_dataset.hpp"
#include "feed.hpp"
#include "online_em_slam.hpp"

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: online_em_plaza <data dir> odometry|drpath start_pose|beacons [key=value ...]\n");
    return 2;
  }
  const std::string dir = argv[1], odometry_kind = argv[2];
  roam::KeyValues values{{"anchor", argv[3]}};
  for (int i = 4; i < argc; ++i) {
    const std::string kv = argv[i];
    const auto eq = kv.find('=');
    values.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
  }
  roam::OnlineEmConfig config;
  roam::Options options(values);
  roam::addOnlineEmOptions(options, &config);
  options.parse();
  roam::CsvImportOptions import;
  if (odometry_kind == "drpath") import.odometry_from_path = dir + "/dead_reckoning_path.csv";
  const roam::Dataset data = roam::loadCsvDataset(dir, import);

  const std::clock_t begin = std::clock();
  roam::OnlineEmSlam slam(config);
  roam::online_em_test::feed(data, slam);
  const double cpu_s = static_cast<double>(std::clock() - begin) / CLOCKS_PER_SEC;
  double rmse = 0.0, last10 = 0.0;
  const double mean = roam::online_em_test::meanError(slam.filteredPath(), data.ground_truth, &rmse, &last10);
  const auto& d = slam.diagnostics();
  std::printf("mean %.3f m  rmse %.3f m  last10%% %.3f m  beacons %.3f m  scale %.4f  offset %.3f m  "
              "ess_min %.1f  eff_pred %.2f  cpu %.2f s\n",
              mean, rmse, last10, roam::online_em_test::mapError(slam.currentMap(), data.beacons),
              slam.rangeScale(), slam.rangeOffset(), d.count("ess_min") ? d.at("ess_min") : 0.0,
              d.count("smoothing_effective_predecessors") ? d.at("smoothing_effective_predecessors") : 0.0, cpu_s);
  for (const roam::Beacon& b : slam.currentMap()) std::printf("  beacon %d: %.2f %.2f\n", b.id, b.x_m, b.y_m);
  return 0;
}
