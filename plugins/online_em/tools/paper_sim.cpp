// roam-online-em-paper-sim: the simulation of Le Corff, Fort & Moulines 2011, Sec. 4.1.
//
// Setting (from the paper): the bicycle motion model f with wheelbase B = 1.5 m, noisy controls
// (v^, psi^) ~ N(u_t, Q), Q = diag(0.5^2 (m/s)^2, (pi/60)^2); range-bearing observations with
// mixture noise w0 = 0.8, sigma0 = 1, sigma1 = 5, R = [[0.5^2, 0.01], [0.01, (pi/60)^2]];
// N = 100 particles, prior kernel, gamma_t = t^-0.8, T = 1626 steps, 50 Monte-Carlo runs.
// Not given in the paper (chosen here): the route (a 60 x 40 m rounded rectangle driven at
// 2 m/s, 0.2 s steps), 24 landmarks 6 m either side of it, a 20 m sensing radius, the known start
// pose (anchor = start_pose; each landmark starts at its first observation).
//
// Prints the quantiles over the runs of the x error (true - estimated) at several times (the
// data behind the paper's Fig. 2) and writes an SVG with the true path and landmarks and the
// mean estimated path and map (its Fig. 1).
//
//   roam-online-em-paper-sim [--runs 50] [--svg paper_sim.svg]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "online_em_slam.hpp"

namespace {

constexpr int kSteps = 1626;
constexpr double kDt_s = 0.2, kSpeed_mps = 2.0, kWheelbase_m = 1.5;
constexpr double kSigmaV_mps = 0.5, kSigmaPsi_rad = M_PI / 60.0;
constexpr double kW0 = 0.8, kSigma0 = 1.0, kSigma1 = 5.0;
constexpr double kSigmaR_m = 0.5, kSigmaB_rad = M_PI / 60.0, kRho = 0.01;
constexpr double kSensingRadius_m = 20.0;

struct Control {
  double v_mps, psi_rad;
};

// Commanded controls: straight sides, constant-steer quarter turns, repeated.
std::vector<Control> route() {
  std::vector<Control> u;
  const double step_m = kSpeed_mps * kDt_s;
  const double turn_radius_m = 6.0;
  const double psi = std::asin(kWheelbase_m / turn_radius_m);  // dth/step = step sin(psi) / B
  const int turn_steps = static_cast<int>(std::lround(0.5 * M_PI * turn_radius_m / step_m));
  while (static_cast<int>(u.size()) < kSteps) {
    for (int side = 0; side < 4; ++side) {
      const double length_m = side % 2 == 0 ? 60.0 : 40.0;
      for (int k = 0; k < static_cast<int>(length_m / step_m); ++k) u.push_back({kSpeed_mps, 0.0});
      // Scale the steer so that the turn is exactly a quarter.
      const double dth = 0.5 * M_PI / turn_steps;
      const double steer = std::asin(std::clamp(kWheelbase_m * dth / step_m, -1.0, 1.0));
      (void)psi;
      for (int k = 0; k < turn_steps; ++k) u.push_back({kSpeed_mps, steer});
    }
  }
  u.resize(kSteps);
  return u;
}

roam::Map landmarks() {
  roam::Map map;
  int id = 0;
  // Along the planned rectangle (corners (0,0), (60,0), (60,40), (0,40) roughly), 6 m inside and outside.
  for (double s = 0.0; s < 60.0; s += 20.0) {
    map.push_back({id++, s + 5.0, -6.0, {}});
    map.push_back({id++, s + 15.0, 6.0, {}});
    map.push_back({id++, s + 5.0, 46.0 + 6.0, {}});
    map.push_back({id++, s + 15.0, 46.0 - 6.0, {}});
  }
  for (double s = 0.0; s < 40.0; s += 20.0) {
    map.push_back({id++, 66.0 + 6.0, s + 8.0, {}});
    map.push_back({id++, 66.0 - 6.0, s + 18.0, {}});
    map.push_back({id++, -6.0, s + 10.0, {}});
    map.push_back({id++, 6.0, s + 20.0, {}});
  }
  return map;
}

struct Run {
  roam::Path truth;
  std::vector<roam::Odometry> odometry;
  std::vector<roam::Range> ranges;
};

Run simulate(uint64_t seed, const roam::Map& map) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::bernoulli_distribution wide(1.0 - kW0);
  Eigen::Matrix2d r;
  r << kSigmaR_m * kSigmaR_m, kRho, kRho, kSigmaB_rad * kSigmaB_rad;
  const Eigen::Matrix2d chol = r.llt().matrixL();
  Run run;
  roam::Pose p;
  p.utime = 0;
  run.truth.push_back(p);
  for (const Control& u : route()) {
    // True motion with the noisy controls (paper Eq. for f).
    const double v = u.v_mps + kSigmaV_mps * normal(rng), psi = u.psi_rad + kSigmaPsi_rad * normal(rng);
    roam::Pose next = p;
    next.utime = p.utime + static_cast<int64_t>(kDt_s * 1e6);
    next.x_m += v * kDt_s * std::cos(p.heading_rad + psi);
    next.y_m += v * kDt_s * std::sin(p.heading_rad + psi);
    next.heading_rad += v * kDt_s * std::sin(psi) / kWheelbase_m;
    // The filter is given the commanded controls as (d, dth).
    roam::Odometry o;
    o.utime = next.utime;
    o.delta_distance_m = u.v_mps * kDt_s;
    o.delta_heading_rad = u.v_mps * kDt_s * std::sin(u.psi_rad) / kWheelbase_m;
    run.odometry.push_back(o);
    for (const roam::Beacon& b : map) {
      const double dx = b.x_m - next.x_m, dy = b.y_m - next.y_m;
      const double d = std::hypot(dx, dy);
      if (d > kSensingRadius_m) continue;
      const double k = wide(rng) ? kSigma1 : kSigma0;
      const Eigen::Vector2d noise = k * chol * Eigen::Vector2d(normal(rng), normal(rng));
      roam::Range y;
      y.utime = next.utime;
      y.beacon_id = b.id;
      y.range_m = std::max(d + noise[0], 0.01);
      y.has_bearing = true;
      y.bearing_rad = roam::wrapAngle(std::atan2(dy, dx) - next.heading_rad + noise[1]);
      run.ranges.push_back(y);
    }
    run.truth.push_back(next);
    p = next;
  }
  return run;
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const double pos = q * (v.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(pos));
  const size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - lo) * (v[hi] - v[lo]);
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 50;
  std::string svg_path = "paper_sim.svg";
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--runs")) runs = std::max(1, std::atoi(argv[i + 1]));
    else if (!std::strcmp(argv[i], "--svg")) svg_path = argv[i + 1];
    else {
      std::fprintf(stderr, "usage: roam-online-em-paper-sim [--runs 50] [--svg FILE]\n");
      return 2;
    }
  }
  roam::OnlineEmConfig config;
  config.motion_model = "bicycle";
  config.wheelbase_m = kWheelbase_m;
  config.speed_sigma_mps = kSigmaV_mps;
  config.steer_sigma_rad = kSigmaPsi_rad;
  config.estimate_range_scale = false;  // the paper's model has no range scale or offset
  config.estimate_range_offset = false;
  config.resampling = "multinomial";  // Algorithm 1
  const roam::Map truth_map = landmarks();
  const std::vector<int> times{100, 400, 800, 1200, kSteps};
  std::vector<std::vector<double>> x_errors(times.size());
  std::vector<double> mean_x(kSteps + 1, 0.0), mean_y(kSteps + 1, 0.0), map_errors;
  std::vector<Eigen::Vector2d> mean_map(truth_map.size(), Eigen::Vector2d::Zero());
  std::vector<int> map_counts(truth_map.size(), 0);
  roam::Path truth_path;
  for (int run_index = 0; run_index < runs; ++run_index) {
    const Run run = simulate(1000 + run_index, truth_map);
    if (run_index == 0) truth_path = run.truth;  // the route of run 0 is drawn as "true path"
    config.seed = run_index + 1;
    roam::OnlineEmSlam slam(config);
    slam.setInitialPose(run.truth.front());
    size_t r = 0;
    for (const roam::Odometry& o : run.odometry) {
      while (r < run.ranges.size() && run.ranges[r].utime <= o.utime) slam.addRange(run.ranges[r++]);
      slam.addOdometry(o);
    }
    slam.finish();
    const roam::Path& est = slam.filteredPath();
    for (size_t i = 0; i < times.size(); ++i)
      x_errors[i].push_back(run.truth[times[i]].x_m - est[times[i]].x_m);
    if (run_index == 0)
      for (int t = 0; t <= kSteps; ++t) mean_x[t] = mean_y[t] = 0.0;
    for (int t = 0; t <= kSteps; ++t) {
      mean_x[t] += est[t].x_m / runs;
      mean_y[t] += est[t].y_m / runs;
    }
    double sum = 0.0;
    int n = 0;
    for (const roam::Beacon& b : slam.currentMap()) {
      mean_map[b.id] += Eigen::Vector2d(b.x_m, b.y_m);
      ++map_counts[b.id];
      sum += std::hypot(b.x_m - truth_map[b.id].x_m, b.y_m - truth_map[b.id].y_m);
      ++n;
    }
    map_errors.push_back(n ? sum / n : NAN);
    std::fprintf(stderr, "run %d/%d: final x error %.3f m, mean landmark error %.3f m\n", run_index + 1, runs,
                 x_errors.back().back(), map_errors.back());
  }
  std::printf("x error (true - estimated, m) over %d runs: quantiles\n", runs);
  std::printf("%6s %8s %8s %8s %8s %8s\n", "t", "min", "q25", "median", "q75", "max");
  for (size_t i = 0; i < times.size(); ++i)
    std::printf("%6d %8.3f %8.3f %8.3f %8.3f %8.3f\n", times[i], quantile(x_errors[i], 0.0),
                quantile(x_errors[i], 0.25), quantile(x_errors[i], 0.5), quantile(x_errors[i], 0.75),
                quantile(x_errors[i], 1.0));
  std::printf("mean landmark error at T: median over runs %.3f m\n", quantile(map_errors, 0.5));

  std::ofstream svg(svg_path);
  const double scale = 6.0, ox = 20.0, oy = 20.0;  // px per m; origin offset (m)
  auto px = [&](double x) { return (x + ox) * scale; };
  auto py = [&](double y) { return (80.0 - y) * scale; };
  svg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << 110 * scale << "' height='" << 110 * scale << "'>\n";
  svg << "<polyline fill='none' stroke='black' stroke-width='2' points='";
  for (const roam::Pose& p : truth_path) svg << px(p.x_m) << ',' << py(p.y_m) << ' ';
  svg << "'/>\n<polyline fill='none' stroke='red' stroke-dasharray='6,3' points='";
  for (int t = 0; t <= kSteps; ++t) svg << px(mean_x[t]) << ',' << py(mean_y[t]) << ' ';
  svg << "'/>\n";
  for (size_t i = 0; i < truth_map.size(); ++i) {
    svg << "<circle cx='" << px(truth_map[i].x_m) << "' cy='" << py(truth_map[i].y_m) << "' r='4' fill='black'/>\n";
    if (map_counts[i]) {
      const Eigen::Vector2d m = mean_map[i] / map_counts[i];
      svg << "<text x='" << px(m.x()) - 5 << "' y='" << py(m.y()) + 5 << "' fill='red' font-size='16'>*</text>\n";
    }
  }
  svg << "<text x='10' y='20' font-size='14'>black: true path (run 1) and landmarks; red: mean estimated path "
         "and map over " << runs << " runs</text>\n</svg>\n";
  std::printf("wrote %s\n", svg_path.c_str());
  return 0;
}
