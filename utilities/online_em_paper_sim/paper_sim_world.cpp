#include "paper_sim_world.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Dense>

namespace roam {
namespace paper_sim {

namespace {
constexpr double kSideX_m = 60.0, kSideY_m = 40.0, kTurnRadius_m = 6.0;
constexpr int kLandmarks = 24;
constexpr double kLandmarkOffset_m = 6.0;
constexpr double kMinSpeed_mps = 0.01;  // the odometry (d, dth) cannot carry v^ <= 0 (a 4-sigma tail)
}  // namespace

std::vector<Control> route(int steps) {
  std::vector<Control> u;
  const double step_m = kSpeed_mps * kDt_s;
  const int turn_steps = static_cast<int>(std::lround(0.5 * M_PI * kTurnRadius_m / step_m));
  // dth per step = step sin(psi) / B: the steer that turns exactly a quarter in turn_steps.
  const double steer_rad = std::asin(kWheelbase_m * (0.5 * M_PI / turn_steps) / step_m);
  while (static_cast<int>(u.size()) < steps) {
    for (int side = 0; side < 4; ++side) {
      const double length_m = side % 2 == 0 ? kSideX_m : kSideY_m;
      const int straight_steps = static_cast<int>(std::lround(length_m / step_m));
      for (int k = 0; k < straight_steps; ++k) u.push_back({kSpeed_mps, 0.0});
      for (int k = 0; k < turn_steps; ++k) u.push_back({kSpeed_mps, steer_rad});
    }
  }
  u.resize(steps);
  return u;
}

Path truePath(const std::vector<Control>& controls) {
  Path path(1);
  for (const Control& c : controls) {
    const Pose& p = path.back();
    Pose next = p;
    next.utime = p.utime + static_cast<int64_t>(std::lround(kDt_s * 1e6));
    next.x_m += c.v_mps * kDt_s * std::cos(p.heading_rad + c.psi_rad);
    next.y_m += c.v_mps * kDt_s * std::sin(p.heading_rad + c.psi_rad);
    next.heading_rad += c.v_mps * kDt_s * std::sin(c.psi_rad) / kWheelbase_m;
    path.push_back(next);
  }
  return path;
}

Map landmarks() {
  // Along one lap, equally spaced in arc length, alternately left and right of the path.
  const Path lap = truePath(route(100000));
  std::vector<double> arc(1, 0.0);
  for (size_t k = 1; k < lap.size(); ++k)
    arc.push_back(arc.back() + std::hypot(lap[k].x_m - lap[k - 1].x_m, lap[k].y_m - lap[k - 1].y_m));
  const double lap_m = 2.0 * (kSideX_m + kSideY_m) + 2.0 * M_PI * kTurnRadius_m;
  Map map;
  size_t k = 0;
  for (int i = 0; i < kLandmarks; ++i) {
    const double s_m = (i + 0.5) * lap_m / kLandmarks;
    while (arc[k] < s_m) ++k;
    const double side = i % 2 == 0 ? 1.0 : -1.0;  // left, right
    const double th = lap[k].heading_rad;
    Beacon b;
    b.id = i;
    b.x_m = lap[k].x_m - side * kLandmarkOffset_m * std::sin(th);
    b.y_m = lap[k].y_m + side * kLandmarkOffset_m * std::cos(th);
    b.covariance = {0.0, 0.0, 0.0, 0.0};
    map.push_back(b);
  }
  return map;
}

RunData simulateRun(uint64_t seed, const std::vector<Control>& controls, const Path& truth, const Map& map) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::bernoulli_distribution wide(1.0 - kW0);
  Eigen::Matrix2d r;
  r << kSigmaR_m * kSigmaR_m, kRho, kRho, kSigmaB_rad * kSigmaB_rad;
  const Eigen::Matrix2d chol = r.llt().matrixL();
  RunData run;
  for (size_t t = 0; t < controls.size(); ++t) {
    const Pose& p = truth[t + 1];
    // Noisy controls (v^, psi^) ~ N(u_t, Q), given to the filter as (d, dth).
    const double v_mps = std::max(controls[t].v_mps + kSigmaV_mps * normal(rng), kMinSpeed_mps);
    const double psi_rad = controls[t].psi_rad + kSigmaPsi_rad * normal(rng);
    Odometry o;
    o.utime = p.utime;
    o.forward_m = v_mps * kDt_s;
    o.delta_heading_rad = v_mps * kDt_s * std::sin(psi_rad) / kWheelbase_m;
    run.odometry.push_back(o);
    for (const Beacon& b : map) {
      const double dx = b.x_m - p.x_m, dy = b.y_m - p.y_m;
      const double d_m = std::hypot(dx, dy);
      if (d_m > kSensingRadius_m) continue;
      const double k = wide(rng) ? kSigma1 : kSigma0;
      const Eigen::Vector2d noise = k * chol * Eigen::Vector2d(normal(rng), normal(rng));
      Range y;
      y.utime = p.utime;
      y.beacon_id = b.id;
      y.range_m = std::max(d_m + noise[0], 0.01);  // positive: a wide draw can be 2.4 sigma short at 6 m
      y.has_bearing = true;
      y.bearing_rad = wrapAngle(std::atan2(dy, dx) - p.heading_rad + noise[1]);
      run.ranges.push_back(y);
    }
  }
  return run;
}

}  // namespace paper_sim
}  // namespace roam
