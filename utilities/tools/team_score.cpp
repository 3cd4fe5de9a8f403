#include "team_score.hpp"

#include <algorithm>

namespace roam {
namespace {

double maxError(const std::vector<double>& errors_m) {
  return errors_m.empty() ? kNaN : *std::max_element(errors_m.begin(), errors_m.end());
}

}  // namespace

double RobotScore::coverage() const {
  return ground_truth == 0 ? 0.0 : static_cast<double>(score.matched) / static_cast<double>(ground_truth);
}

double TeamScore::coverage() const {
  return ground_truth == 0 ? 0.0 : static_cast<double>(matched) / static_cast<double>(ground_truth);
}

size_t TeamScore::robotsWithoutPath() const {
  return static_cast<size_t>(std::count_if(robots.begin(), robots.end(), [](const RobotScore& r) { return !r.published(); }));
}

TeamScore scoreTeam(const EstimatorOutputs& estimator, const std::map<std::string, Path>& team_ground_truth,
                    bool aligned_robots, const std::optional<Map>& true_map) {
  TeamScore team;
  std::vector<std::vector<MatchedPosition>> matched;  // per robot with a path
  for (const auto& [robot, truth] : team_ground_truth) {
    RobotScore r;
    r.robot = robot;
    r.ground_truth = truth.size();
    team.ground_truth += truth.size();
    const auto it = estimator.robots.find(robot);
    if (it != estimator.robots.end()) {
      r.scored = it->second.trajectory ? "trajectory" : "poses";
      r.score = scorePath(it->second.scoredPath(), truth, aligned_robots);
      matched.push_back(matchToGroundTruth(it->second.scoredPath(), truth));
      team.matched += matched.back().size();
    }
    team.robots.push_back(r);
  }
  std::vector<double> unaligned_m, aligned_m;
  for (const auto& path : matched)
    for (const MatchedPosition& m : path) unaligned_m.push_back(m.error_m());
  if (team.matched > 0) {
    team.alignment = fitRigid2D(matched);
    for (auto& path : matched) {
      for (MatchedPosition& m : path) {
        team.alignment->apply(&m.estimate_x_m, &m.estimate_y_m);
        aligned_m.push_back(m.error_m());
      }
    }
  }
  team.unaligned = errorStats(unaligned_m, 0, unaligned_m.size());
  team.aligned = errorStats(aligned_m, 0, aligned_m.size());
  team.unaligned_max_m = maxError(unaligned_m);
  team.aligned_max_m = maxError(aligned_m);
  if (estimator.map && true_map) {
    team.beacon_error_m = beaconError(*estimator.map, *true_map, std::nullopt);
    if (team.alignment) team.aligned_beacon_error_m = beaconError(*estimator.map, *true_map, team.alignment);
  }
  return team;
}

}  // namespace roam
