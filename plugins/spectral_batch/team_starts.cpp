#include "team_starts.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "roam/estimation/motion_model.hpp"
#include "roam/estimation/start_registration.hpp"

namespace roam {
namespace spectral_batch {

bool locate(const std::vector<int64_t>& times, int64_t t, StepLocation* out) {
  if (times.size() < 2 || t < times.front() || t > times.back()) return false;
  const int n = static_cast<int>(times.size());
  int k = static_cast<int>(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
  k = std::min(k, n - 2);  // t at the last pose: alpha = 1 on the last step
  out->step = k;
  out->alpha = static_cast<double>(t - times[k]) / static_cast<double>(times[k + 1] - times[k]);
  return true;
}

namespace {

using Chain = std::vector<std::array<double, 3>>;

Eigen::Vector2d positionAt(const Chain& poses, const StepLocation& at) {
  const auto& a = poses[static_cast<size_t>(at.step)];
  const auto& b = poses[static_cast<size_t>(at.step) + 1];
  return {a[0] + at.alpha * (b[0] - a[0]), a[1] + at.alpha * (b[1] - a[1])};
}

// The dead-reckoned position's variance (mean of its two) at each pose, from the start's zero.
std::vector<double> deadReckoningVariance(const TeamRobot& robot, const TeamSolveOptions& options,
                                          const std::vector<double>& dt_s, const Chain& poses) {
  std::vector<double> out{0.0};
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (size_t k = 0; k < robot.odometry.size(); ++k) {
    const Odometry& o = robot.odometry[k];
    const Eigen::Vector3d pose(poses[k][0], poses[k][1], poses[k][2]);
    const estimation::StepJacobians j = estimation::stepJacobians(pose, o, dt_s[k]);
    const Eigen::Matrix3d q = options.increment_covariance ? options.increment_covariance(o, dt_s[k])
                                                           : estimation::incrementCovariance(o, dt_s[k], options.motion_noise);
    covariance = j.wrt_pose * covariance * j.wrt_pose.transpose() + j.wrt_increment * q * j.wrt_increment.transpose();
    out.push_back(0.5 * (covariance(0, 0) + covariance(1, 1)));
  }
  return out;
}

void moveToWorld(const Eigen::Vector3d& start, Chain* poses) {
  const double c = std::cos(start.z()), s = std::sin(start.z());
  for (auto& p : *poses) {
    const double x = p[0], y = p[1];
    p = {start.x() + c * x - s * y, start.y() + s * x + c * y, p[2] + start.z()};
  }
}

}  // namespace

std::vector<TeamStart> findUnknownStarts(const TeamInput& input, const TeamSolveOptions& options,
                                         const std::vector<std::vector<int64_t>>& times,
                                         const std::vector<std::vector<double>>& dt_s,
                                         const std::vector<bool>& start_known,
                                         std::vector<std::vector<std::array<double, 3>>>* poses) {
  const int num_robots = static_cast<int>(input.robots.size());
  std::vector<TeamStart> starts(static_cast<size_t>(num_robots));
  std::vector<bool> placed(static_cast<size_t>(num_robots), false);
  std::vector<std::vector<double>> variance(static_cast<size_t>(num_robots));
  for (int r = 0; r < num_robots; ++r) {
    placed[r] = start_known[r];
    if (!placed[r]) starts[r].source = TeamStart::Source::kNotFound;
    variance[r] = deadReckoningVariance(input.robots[r], options, dt_s[r], (*poses)[r]);
  }
  std::map<int, Eigen::Vector2d> surveyed;
  for (const Beacon& beacon : input.beacons) surveyed[beacon.id] = Eigen::Vector2d(beacon.x_m, beacon.y_m);
  const auto sigma = [&](const Range& range) { return range.sigma_m > 0.0 ? range.sigma_m : options.range_sigma_m; };

  // Robot u's ranges to what is placed, as the registration takes them.
  const auto observationsOf = [&](int u) {
    std::vector<estimation::StartRangeObservation> out;
    for (const Range& range : input.robot_ranges) {
      if (range.robot != u && range.other_robot != u) continue;
      const int other = range.robot == u ? range.other_robot : range.robot;
      StepLocation at_u, at_other;
      if (!placed[other] || !locate(times[u], range.utime, &at_u) || !locate(times[other], range.utime, &at_other))
        continue;
      estimation::StartRangeObservation o;
      o.local_m = positionAt((*poses)[u], at_u);
      o.world_m = positionAt((*poses)[other], at_other);
      o.range_m = range.range_m;
      const double var_u = variance[u][static_cast<size_t>(at_u.step) + 1];
      const double var_other = variance[other][static_cast<size_t>(at_other.step) + 1];
      o.sigma_m = std::sqrt(sigma(range) * sigma(range) + var_u + var_other);
      out.push_back(o);
    }
    if (!options.use_beacon_ranges) return out;
    for (const Range& range : input.robots[u].beacon_ranges) {
      const auto beacon = surveyed.find(range.beacon_id);
      StepLocation at;
      if (beacon == surveyed.end() || !locate(times[u], range.utime, &at)) continue;
      estimation::StartRangeObservation o;
      o.local_m = positionAt((*poses)[u], at);
      o.world_m = beacon->second;
      o.range_m = range.range_m;
      o.sigma_m = std::sqrt(sigma(range) * sigma(range) + variance[u][static_cast<size_t>(at.step) + 1]);
      out.push_back(o);
    }
    return out;
  };

  // The robot with the most ranges to what is placed goes first; one that failed is tried again
  // only once more has been placed.
  std::vector<size_t> tried_with(static_cast<size_t>(num_robots), 0);
  for (;;) {
    int next = -1;
    std::vector<estimation::StartRangeObservation> best;
    for (int u = 0; u < num_robots; ++u) {
      if (placed[u]) continue;
      std::vector<estimation::StartRangeObservation> observations = observationsOf(u);
      if (observations.size() > tried_with[u] && observations.size() > best.size()) {
        next = u;
        best = std::move(observations);
      }
    }
    if (next < 0) break;
    tried_with[next] = best.size();
    const estimation::StartRegistration found = estimation::registerStart(best);
    starts[next].registration = found;
    if (found.status != estimation::StartRegistration::Status::kFound) continue;
    starts[next].source = TeamStart::Source::kFound;
    moveToWorld(found.start, &(*poses)[next]);
    placed[next] = true;
  }
  return starts;
}

}  // namespace spectral_batch
}  // namespace roam
