// A team plugin for the runtime's team tests: each robot's dead reckoning from its own start
// pose, through the SDK's one SE(2) step, and a count of the ranges between robots it was given
// (diagnostics "ranges between robots" and "ranges from <robot> to <robot>"). Its paths must
// equal the shipped deadreckoning plugin's on each robot, so the team's routing is tested against
// the one-robot routing.
//
// Its key `heading_bias_rad` (default 0) turns robot r's published path by (-1)^r times that much
// more per step than its odometry does: an answer worse than dead reckoning, for the team
// self-check's tests (roam/self_check.hpp). Robots curl opposite ways, so the distances between
// them are wrong too (one curl shared by every robot of a team started side by side moves them
// together, and their ranges between robots barely see it).
#include <array>
#include <map>
#include <string>
#include <vector>

#include "roam/plugin_shim.hpp"
#include "roam/se2.hpp"

namespace {

class TeamDeadReckoning : public roam::Estimator {
 public:
  explicit TeamDeadReckoning(double heading_bias_rad) : heading_bias_rad_(heading_bias_rad) {}
  void setTeam(const std::vector<std::string>& robots) override {
    robots_ = robots;
    paths_.assign(robots.size(), {});
  }
  void setInitialPose(const roam::Pose& start) override {
    roam::Path& path = paths_.at(static_cast<size_t>(start.robot));
    if (!path.empty()) return;
    roam::Pose first = start;
    first.heading_rad = roam::wrapAngle(first.heading_rad);
    path.push_back(first);
    setState(roam::EstimatorState::kTracking);
  }
  void addOdometry(const roam::Odometry& odometry) override {
    roam::Path& path = paths_.at(static_cast<size_t>(odometry.robot));
    if (path.empty()) {
      rejectOdometry("before the start pose");
      return;
    }
    const roam::Pose& last = path.back();
    const double pose[3] = {last.x_m, last.y_m, last.heading_rad};
    const double increment[3] = {odometry.forward_m, odometry.lateral_m, odometry.delta_heading_rad +
                                 (odometry.robot % 2 == 0 ? heading_bias_rad_ : -heading_bias_rad_)};
    double next[3];
    roam::composeIncrement(pose, increment, next);
    roam::Pose out;
    out.utime = odometry.utime;
    out.x_m = next[0];
    out.y_m = next[1];
    out.heading_rad = roam::wrapAngle(next[2]);
    out.robot = odometry.robot;
    path.push_back(out);
    acceptOdometry();
    emitPose(out);
  }
  void addRange(const roam::Range& range) override {
    if (!range.toRobot()) return;
    acceptRange();
    setDiagnostic("ranges between robots", static_cast<double>(rangesAccepted()));
    const std::string key = "ranges from " + robots_.at(static_cast<size_t>(range.robot)) + " to " +
                            robots_.at(static_cast<size_t>(range.other_robot));
    setDiagnostic(key, diagnostics().count(key) ? diagnostics().at(key) + 1.0 : 1.0);
  }
  bool trajectory(bool /*force*/, roam::Path* path) override {
    path->clear();
    for (const roam::Path& robot_path : paths_) path->insert(path->end(), robot_path.begin(), robot_path.end());
    return !path->empty();
  }

 private:
  double heading_bias_rad_ = 0.0;
  std::vector<std::string> robots_;
  std::vector<roam::Path> paths_;
};

std::unique_ptr<roam::Estimator> makeTeamDeadReckoning(roam::Options& options) {
  double heading_bias_rad = 0.0;
  options.add("heading_bias_rad", &heading_bias_rad, "added to every step's heading change (a distorted answer)");
  options.parse();
  return std::make_unique<TeamDeadReckoning>(heading_bias_rad);
}

}  // namespace

ROAM_DEFINE_TEAM_PLUGIN("team_dr", "each robot's dead reckoning, as a team plugin (tests)", makeTeamDeadReckoning)
