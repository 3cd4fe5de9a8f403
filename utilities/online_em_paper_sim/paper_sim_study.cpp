#include "paper_sim_study.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

#include "online_em_slam.hpp"

namespace roam {
namespace paper_sim {

using online_em::OnlineEmSlam;

OnlineEmConfig paperConfig(int particles, uint64_t seed, const std::string& indicators) {
  OnlineEmConfig config;
  config.num_particles = particles;
  config.seed = static_cast<int>(seed);
  config.anchor = OnlineEmConfig::Anchor::kStartPose;
  config.motion_model = OnlineEmConfig::MotionModel::kBicycle;  // the paper's f
  config.wheelbase_m = kWheelbase_m;
  config.speed_sigma_mps = kSigmaV_mps;
  config.steer_sigma_rad = kSigmaPsi_rad;
  config.mixture_weight0 = kW0;
  config.mixture_sigma0 = kSigma0;
  config.mixture_sigma1 = kSigma1;
  config.range_sigma_m = kSigmaR_m;
  config.bearing_sigma_rad = kSigmaB_rad;
  config.range_bearing_cov = kRho;
  setOptions(&config, online_em::addOnlineEmOptions, {{"indicators", indicators}});  // sampled: Algorithm 1
  config.resampling = OnlineEmConfig::Resampling::kMultinomial;           // Algorithm 1
  config.step_c = 1.0;                // gamma = 1 / t^0.8
  config.step_alpha = 0.8;
  config.estimate_range_scale = false;  // the paper's theta is the landmarks only
  config.estimate_range_offset = false;
  return config;
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) throw std::invalid_argument("quantile of no values");
  std::sort(values.begin(), values.end());
  const double pos = q * static_cast<double>(values.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(pos));
  const size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (pos - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

Quantiles quantiles(const std::vector<double>& values) {
  return {quantile(values, 0.0), quantile(values, 0.25), quantile(values, 0.5), quantile(values, 0.75),
          quantile(values, 1.0)};
}

std::vector<double> column(const Study& study, std::vector<double> RunResult::*series, size_t time_index) {
  std::vector<double> out;
  for (const RunResult& run : study.runs) out.push_back((run.*series)[time_index]);
  return out;
}

namespace {

// Mean landmark error after the best rigid fit (rotation and translation) of the estimate onto
// the truth: the shape of the map without its frame.
double alignedMapError(const Map& estimate, const Map& truth) {
  if (estimate.size() < 2) return NAN;
  Eigen::Vector2d mean_est = Eigen::Vector2d::Zero(), mean_true = Eigen::Vector2d::Zero();
  for (const Beacon& b : estimate) {
    mean_est += Eigen::Vector2d(b.x_m, b.y_m);
    mean_true += Eigen::Vector2d(truth[b.id].x_m, truth[b.id].y_m);
  }
  const double n = static_cast<double>(estimate.size());
  mean_est /= n;
  mean_true /= n;
  Eigen::Matrix2d cross = Eigen::Matrix2d::Zero();
  for (const Beacon& b : estimate)
    cross += (Eigen::Vector2d(b.x_m, b.y_m) - mean_est) * (Eigen::Vector2d(truth[b.id].x_m, truth[b.id].y_m) - mean_true).transpose();
  const double angle_rad = std::atan2(cross(0, 1) - cross(1, 0), cross(0, 0) + cross(1, 1));
  const Eigen::Rotation2Dd rotation(angle_rad);
  double sum_m = 0.0;
  for (const Beacon& b : estimate)
    sum_m += (rotation * (Eigen::Vector2d(b.x_m, b.y_m) - mean_est) + mean_true -
              Eigen::Vector2d(truth[b.id].x_m, truth[b.id].y_m)).norm();
  return sum_m / n;
}

double meanMapError(const Map& estimate, const Map& truth) {
  double sum = 0.0;
  int n = 0;
  for (const Beacon& b : estimate) {
    sum += std::hypot(b.x_m - truth[b.id].x_m, b.y_m - truth[b.id].y_m);
    ++n;
  }
  return n ? sum / n : NAN;
}

}  // namespace

Study runStudy(const StudyOptions& options) {
  if (options.runs < 1) throw std::invalid_argument("runs must be >= 1");
  if (options.steps < 1) throw std::invalid_argument("steps must be >= 1");
  if (options.particles < 2) throw std::invalid_argument("particles must be >= 2");
  Study study;
  study.options = options;
  study.options.times.erase(std::remove_if(study.options.times.begin(), study.options.times.end(),
                                           [&](int t) { return t < 1 || t > options.steps; }),
                            study.options.times.end());
  const std::vector<int>& times = study.options.times;
  const std::vector<Control> controls = route(options.steps);
  study.truth = truePath(controls);
  study.true_map = landmarks();
  std::vector<double> sum_x(options.steps + 1, 0.0), sum_y(options.steps + 1, 0.0);
  std::vector<double> map_sum_x(study.true_map.size(), 0.0), map_sum_y(study.true_map.size(), 0.0);
  std::vector<int> map_count(study.true_map.size(), 0);
  for (int r = 0; r < options.runs; ++r) {
    const uint64_t seed = options.seed + static_cast<uint64_t>(r);
    const RunData data = simulateRun(seed, controls, study.truth, study.true_map);
    OnlineEmSlam slam(paperConfig(options.particles, seed, options.indicators));
    slam.setInitialPose(study.truth.front());
    RunResult result;
    size_t next_range = 0, next_time = 0;
    for (size_t t = 0; t < data.odometry.size(); ++t) {
      const Odometry& o = data.odometry[t];
      while (next_range < data.ranges.size() && data.ranges[next_range].utime <= o.utime)
        slam.addRange(data.ranges[next_range++]);
      slam.addOdometry(o);
      const int step = static_cast<int>(t) + 1;
      if (next_time < times.size() && times[next_time] == step) {
        const Pose& est = slam.filteredPath().back();
        result.x_error_m.push_back(study.truth[step].x_m - est.x_m);
        result.y_error_m.push_back(study.truth[step].y_m - est.y_m);
        const Map map = slam.currentMap();
        result.map_error_m.push_back(meanMapError(map, study.true_map));
        result.aligned_map_error_m.push_back(alignedMapError(map, study.true_map));
        ++next_time;
      }
    }
    slam.finish();
    result.path = slam.filteredPath();
    result.map = slam.currentMap();
    for (int t = 0; t <= options.steps; ++t) {
      const double e = std::hypot(study.truth[t].x_m - result.path[t].x_m, study.truth[t].y_m - result.path[t].y_m);
      result.max_position_error_m = std::max(result.max_position_error_m, e);
      sum_x[t] += result.path[t].x_m;
      sum_y[t] += result.path[t].y_m;
    }
    result.diverged = !(result.max_position_error_m <= options.diverged_m);
    for (const Beacon& b : result.map) {
      map_sum_x[b.id] += b.x_m;
      map_sum_y[b.id] += b.y_m;
      ++map_count[b.id];
    }
    if (options.progress)
      std::fprintf(options.progress, "run %d/%d: final x error %.2f m, max position error %.2f m, map error %.2f m (%.2f m after a rigid fit)\n",
                   r + 1, options.runs, study.truth.back().x_m - result.path.back().x_m,
                   result.max_position_error_m, meanMapError(result.map, study.true_map), alignedMapError(result.map, study.true_map));
    study.runs.push_back(std::move(result));
  }
  study.mean_path = study.truth;
  for (int t = 0; t <= options.steps; ++t) {
    study.mean_path[t].x_m = sum_x[t] / options.runs;
    study.mean_path[t].y_m = sum_y[t] / options.runs;
  }
  for (size_t i = 0; i < study.true_map.size(); ++i) {
    if (!map_count[i]) continue;
    Beacon b = study.true_map[i];
    b.x_m = map_sum_x[i] / map_count[i];
    b.y_m = map_sum_y[i] / map_count[i];
    b.covariance = {NAN, NAN, NAN, NAN};
    study.mean_map.push_back(b);
  }
  return study;
}

}  // namespace paper_sim
}  // namespace roam
