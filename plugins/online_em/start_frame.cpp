// The start pose's frame (anchor = start_pose; model in online_em_slam.hpp):
// - correctFrame: the frame the first landmarks were placed in, turned and moved to the window's
//   dead reckoning with the learned calibration (s, b) where that differs by more than the
//   window's own heading noise (the shared wheel model), or a calibrated re-run scheduled instead;
// - applyFrameMotion: a rigid motion applied to the particles, the path, the landmarks and their
//   sufficient statistics;
// - rerun: the filter re-run once from the start with the learned calibration fixed;
// - solveEarlyWindow: the early window's path and map solved jointly
//   (roam/estimation/window_solve.hpp) and used where its ranges refute the dead-reckoned path.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "online_em_slam.hpp"

namespace roam {
namespace online_em {

void OnlineEmSlam::correctFrame() {
  if (config_.anchor != OnlineEmConfig::Anchor::kStartPose || !config_.calibrate_odometry || config_.motion_model != OnlineEmConfig::MotionModel::kOdometry ||
      window_open_ || window_odometry_.empty() || replaying_)
    return;
  // The window dead-reckoned from the start without and with the calibration. Without: as
  // reported, stands included (a gyro bias turned the heading while the vehicle stood, so a
  // biased stand counts towards the correction and the calibrated re-run); after a re-run, with
  // the calibration and the stands it was made with. (With the standing rule on both sides from
  // the start, 30 % NLOS after a stand went 0.68 -> 1.04 m mean and Plaza 1 with injected
  // biases 0.76 -> 0.99: the re-run came later or not at all. online_em README, "Round 9".)
  const int m = static_cast<int>(window_odometry_.size());
  Eigen::Vector3d a(start_pose_.x_m, start_pose_.y_m, start_pose_.heading_rad), b = a;
  Eigen::Vector2d mean_a = a.head<2>(), mean_b = b.head<2>();
  std::vector<Eigen::Vector2d> pa{a.head<2>()}, pb{b.head<2>()};
  for (int j = 0; j < m; ++j) {
    a = estimation::step(a, estimation::calibratedIncrement(window_odometry_[j], window_dt_s_[j], window_calibration_,
                                                            window_stands_calibrated_ && window_standing_[j]));
    b = estimation::step(b, estimation::calibratedIncrement(window_odometry_[j], window_dt_s_[j], calibration_, window_standing_[j]));
    pa.push_back(a.head<2>());
    pb.push_back(b.head<2>());
    mean_a += a.head<2>();
    mean_b += b.head<2>();
  }
  mean_a /= m + 1.0;
  mean_b /= m + 1.0;
  double cross = 0.0, dot = 0.0;
  for (int j = 0; j <= m; ++j) {
    const Eigen::Vector2d u = pa[j] - mean_a, v = pb[j] - mean_b;
    dot += u.dot(v);
    cross += u.x() * v.y() - u.y() * v.x();
  }
  double angle_rad = std::atan2(cross, dot);
  Eigen::Vector2d translation_m = mean_b - Eigen::Rotation2Dd(angle_rad) * mean_a;
  // Significant only beyond twice the heading uncertainty the window's own noise gives the
  // frame (sigma_h sqrt(steps)); below it the frame stays where the data put it.
  // The window's heading noise under the shared wheel-odometry model (as the early window solve's
  // walk): per metre driven and per turn, a small per-step floor, so standing still before the
  // first metre (Plaza 1: ~45 s) adds almost none, where a per-step sigma counted every step.
  double heading_variance_rad2 = 0.0;
  for (const Odometry& odometry : window_odometry_)
    heading_variance_rad2 += estimation::wheelHeadingVariance_rad2(
        std::hypot(odometry.forward_m, odometry.lateral_m), odometry.delta_heading_rad, estimation::WheelHeadingNoise{});
  const double heading_noise_rad = 2.0 * std::sqrt(heading_variance_rad2);
  if (std::abs(angle_rad) < heading_noise_rad) {
    angle_rad = 0.0;
    translation_m.setZero();
  } else if (recording_ && heading_rate_bias_sigma_rad_s_ <
                               config_.rerun_bias_sigma_fraction * kHeadingRateBiasPriorSigma_rad_s) {
    rerun_pending_ = true;  // replaces the correction, after this step
    return;
  }
  // The part not applied yet: T_d T_a^-1.
  const double delta_rad = angle_rad - frame_angle_rad_;
  const Eigen::Vector2d delta_m = translation_m - Eigen::Rotation2Dd(delta_rad) * frame_translation_m_;
  constexpr double kMinAngle_rad = 1e-4, kMinShift_m = 1e-3;
  if (std::abs(delta_rad) < kMinAngle_rad && delta_m.norm() < kMinShift_m) return;
  applyFrameMotion(delta_rad, delta_m);
  frame_angle_rad_ = angle_rad;
  frame_translation_m_ = translation_m;
  setDiagnostic("frame_correction_rad", frame_angle_rad_);
}

bool OnlineEmSlam::biasSignificant(double k_sigmas) const {
  return k_sigmas > 0.0 && std::isfinite(heading_rate_bias_sigma_rad_s_) &&
         std::abs(calibration_.heading_rate_bias_rad_s) >= k_sigmas * heading_rate_bias_sigma_rad_s_;
}

void OnlineEmSlam::applyFrameMotion(double angle_rad, const Eigen::Vector2d& translation_m) {
  const Eigen::Matrix2d r = Eigen::Rotation2Dd(angle_rad).toRotationMatrix();
  auto move = [&](double* x, double* y, double* heading) {
    const Eigen::Vector2d p = r * Eigen::Vector2d(*x, *y) + translation_m;
    *x = p.x();
    *y = p.y();
    if (heading) *heading += angle_rad;
  };
  for (int k = 0; k < particles_.size(); ++k)
    move(&particles_.x_m[k], &particles_.y_m[k], &particles_.heading_rad[k]);
  const Eigen::Matrix3d r3 = (Eigen::Matrix3d() << r, Eigen::Vector2d::Zero(), 0.0, 0.0, 1.0).finished();
  for (Pose& pose : path_) {
    move(&pose.x_m, &pose.y_m, &pose.heading_rad);
    Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> covariance(pose.covariance.data());
    covariance = r3 * covariance * r3.transpose();
  }
  // phi = M phi' + c with M = diag(R^T, 1, 1), c = (-R^T t, 0, 0).
  Eigen::Matrix4d big_m = Eigen::Matrix4d::Identity();
  big_m.topLeftCorner<2, 2>() = r.transpose();
  Eigen::Vector4d c = Eigen::Vector4d::Zero();
  c.head<2>() = -r.transpose() * translation_m;
  for (int i = 0; i < static_cast<int>(landmarks_.size()); ++i) {
    Landmark& landmark = landmarks_[i];
    for (Eigen::Vector3d& p : landmark.pending_poses) move(&p.x(), &p.y(), &p.z());
    if (!landmark.initialised) continue;
    landmark.position_m = r * landmark.position_m + translation_m;
    landmark.covariance = r * landmark.covariance * r.transpose();
    for (int k = 0; k < statistics_.rows(); ++k) {
      double packed[kStatSize];
      for (int q = 0; q < kStatSize; ++q) packed[q] = statistics_(k, kStatSize * i + q);
      Eigen::Matrix4d information;
      Eigen::Vector4d vector;
      ObservationModel::unpack(packed, &information, &vector);
      const Eigen::Vector4d v2 = big_m.transpose() * (vector - information * c);
      const Eigen::Matrix4d a2 = big_m.transpose() * information * big_m;
      int q = 0;
      for (int row = 0; row < 4; ++row)
        for (int col = row; col < 4; ++col) statistics_(k, kStatSize * i + q++) = a2(row, col);
      for (int row = 0; row < 4; ++row) statistics_(k, kStatSize * i + q++) = v2[row];
    }
  }
  emitMap(currentMap());
}

void OnlineEmSlam::rerun() {
  rerun_pending_ = false;
  recording_ = false;
  std::vector<Input> inputs;
  inputs.swap(inputs_);
  // The calibration statistics keep their value; the replayed steps are not counted again.
  const Eigen::RowVector2d calibration_mean = weights_.matrix().transpose() * calibration_statistics_;
  const Eigen::Matrix2d calibration_information = calibration_information_;
  const int64_t motion_steps = motion_steps_;
  const estimation::OdometryCalibration learned = calibration_;
  // Back to the start: no landmarks, no path, the window reopened with the learned calibration.
  replaying_ = true;
  landmarks_.clear();
  index_of_id_.clear();
  statistics_.resize(config_.num_particles, 0);
  queued_ranges_.clear();
  path_.clear();
  transitions_.clear();
  smooth_first_ = 0;
  window_odometry_.clear();
  window_dt_s_.clear();
  window_standing_.clear();
  window_ranges_.clear();
  window_observations_.clear();
  window_open_ = true;
  frame_angle_rad_ = 0.0;
  frame_translation_m_.setZero();
  observing_steps_ = 0;
  window_calibration_ = learned;
  window_stands_calibrated_ = true;
  calibration_ = learned;
  start(start_pose_);
  for (const Input& input : inputs) {
    if (input.is_odometry)
      processOdometry(input.odometry);
    else
      queued_ranges_.push_back(input.range);
  }
  replaying_ = false;
  calibration_statistics_.rowwise() = calibration_mean;
  calibration_information_ = calibration_information;
  motion_steps_ = motion_steps;
  setDiagnostic("frame_correction_rad", 0.0);
  setDiagnostic("calibrated_rerun_inputs", static_cast<double>(inputs.size()));
  setDiagnostic("calibrated_rerun_bias_rad_s", learned.heading_rate_bias_rad_s);
  emitMap(currentMap());
}

void OnlineEmSlam::solveEarlyWindow() {
  window_solve_pending_ = false;
  const int m = static_cast<int>(window_odometry_.size());
  if (static_cast<int>(path_.size()) != m + 1 || window_ranges_.empty()) return;
  WindowProblem problem;
  for (const Pose& pose : path_) {
    problem.path.emplace_back(pose.x_m, pose.y_m, pose.heading_rad);
    problem.time_s.push_back(1e-6 * static_cast<double>(pose.utime - path_.front().utime));
  }
  std::vector<int> solve_index(landmarks_.size(), -1);
  std::vector<int> landmark_of;
  for (int i = 0; i < static_cast<int>(landmarks_.size()); ++i) {
    if (!landmarks_[i].initialised) continue;
    solve_index[i] = static_cast<int>(landmark_of.size());
    landmark_of.push_back(i);
    problem.landmarks_m.push_back(landmarks_[i].position_m);
  }
  for (WindowRange r : window_ranges_) {
    if (solve_index[r.landmark] < 0) continue;
    r.landmark = solve_index[r.landmark];
    problem.ranges.push_back(r);
  }
  problem.range_scale = range_scale_;
  problem.range_offset_m = range_offset_m_;
  if (config_.estimate_range_scale) problem.range_scale_prior_sigma = kRangeScalePriorSigma;
  // The heading walk of the shared wheel-odometry model (estimation::WheelHeadingNoise, its
  // defaults): a turn's scale error, a walk per metre driven and a small per-step floor, so a
  // vehicle standing still does not turn the frame.
  for (const Odometry& odometry : window_odometry_)
    problem.heading_variance_rad2.push_back(estimation::wheelHeadingVariance_rad2(
        std::hypot(odometry.forward_m, odometry.lateral_m), odometry.delta_heading_rad, estimation::WheelHeadingNoise{}));
  problem.block_s = config_.init_window_block_s;
  // The filter's mixture: inlier N(0, (sr sigma0)^2) with weight w0, outlier uniform over the
  // ranges' span (or the wide Gaussian).
  const bool uniform = config_.outlier_model == OnlineEmConfig::OutlierModel::kUniform && max_range_m_ > 0.0;
  const double w0 = mixture_weight0_;
  problem.weight = [&](const WindowRange& r, double e_m, double* log_likelihood) {
    const double sr = r.sigma_m;
    const double s0 = sr * inlier_sigma0_, s1 = sr * config_.mixture_sigma1;
    const double l0 = std::log(w0) - std::log(s0) - 0.5 * e_m * e_m / (s0 * s0);
    const double l1 = w0 >= 1.0 ? -std::numeric_limits<double>::infinity()
                                : std::log(1.0 - w0) + (uniform ? 0.5 * std::log(2.0 * M_PI) - std::log(max_range_m_)
                                                                : -std::log(s1) - 0.5 * e_m * e_m / (s1 * s1));
    const double top = std::max(l0, l1);
    const double inlier = std::exp(l0 - top) / (std::exp(l0 - top) + std::exp(l1 - top));
    *log_likelihood = top + std::log(std::exp(l0 - top) + std::exp(l1 - top));
    return inlier / (s0 * s0);
  };
  const WindowSolution solution = solveWindow(problem);
  if (!solution.solved) return;
  // Applied only where the ranges refute the dead-reckoned window: the same solve with the path
  // held (landmarks and range scale free) against it, a likelihood-ratio test at the inlier gate's
  // significance (twice the log-posterior gain >= gate^2): on Plaza 1 the gain is 6-8 (its
  // odometry is good to a metre over the window, its ranges carry errors the model has not), on
  // the 30 % NLOS runs 2-141 (the bad seeds 20-141).
  const WindowSolution dead_reckoned = solveWindow(estimation::withPathHeld(problem));
  const double gain = dead_reckoned.solved ? 2.0 * (solution.log_posterior - dead_reckoned.log_posterior) : 0.0;
  setDiagnostic("window_solve_gain", gain);
  const double gate = config_.init_outlier_gate_sigmas;
  setDiagnostic("window_solve_applied", gain >= gate * gate ? 1.0 : 0.0);
  if (gain < gate * gate) return;
  // The particles follow the window's end: the rigid motion taking the nominal end pose to the
  // solved one.
  const Eigen::Vector3d& old_end = problem.path.back();
  const Eigen::Vector3d& new_end = solution.path.back();
  const double turn_rad = new_end.z() - old_end.z();
  const Eigen::Matrix2d r = Eigen::Rotation2Dd(turn_rad).toRotationMatrix();
  const Eigen::Vector2d shift_m = new_end.head<2>() - r * old_end.head<2>();
  for (int k = 0; k < particles_.size(); ++k) {
    const Eigen::Vector2d p = r * Eigen::Vector2d(particles_.x_m[k], particles_.y_m[k]) + shift_m;
    particles_.x_m[k] = p.x();
    particles_.y_m[k] = p.y();
    particles_.heading_rad[k] += turn_rad;
  }
  smooth_first_ = static_cast<size_t>(m);
  for (int j = 1; j <= m; ++j) {
    path_[j].x_m = solution.path[j].x();
    path_[j].y_m = solution.path[j].y();
    path_[j].heading_rad = solution.path[j].z();
  }
  // Each landmark's statistic: the average over its window ranges at the solved path, with the
  // mixture's posterior probabilities (as at initialisation).
  for (size_t a = 0; a < landmark_of.size(); ++a) landmarks_[landmark_of[a]].position_m = solution.landmarks_m[a];
  range_scale_ = solution.range_scale;
  std::vector<Eigen::Matrix<double, 1, kStatSize>> sums(landmark_of.size(), Eigen::Matrix<double, 1, kStatSize>::Zero());
  std::vector<int> counts(landmark_of.size(), 0);
  double stat0[kStatSize], stat1[kStatSize];
  for (size_t q = 0; q < window_ranges_.size(); ++q) {
    const WindowRange& w = window_ranges_[q];
    const int a = solve_index[w.landmark];
    if (a < 0) continue;
    const Eigen::Vector3d p = (1.0 - w.fraction) * solution.path[w.step] + w.fraction * solution.path[w.step + 1];
    const Eigen::Vector4d phi_i = phi(w.landmark);
    double r1 = 0.0;
    mixtureLogLikelihood(window_observations_[q], p.x(), p.y(), p.z(), phi_i, &r1);
    observation_.statistic(window_observations_[q], p.x(), p.y(), p.z(), phi_i, 0, stat0);
    observation_.statistic(window_observations_[q], p.x(), p.y(), p.z(), phi_i, 1, stat1);
    for (int s = 0; s < kStatSize; ++s) sums[a][s] += (1.0 - r1) * stat0[s] + r1 * stat1[s];
    ++counts[a];
  }
  for (size_t a = 0; a < landmark_of.size(); ++a) {
    if (counts[a] == 0) continue;
    const int i = landmark_of[a];
    statistics_.middleCols(kStatSize * i, kStatSize).rowwise() = sums[a] / counts[a];
    landmarks_[i].count = counts[a];
  }
  setDiagnostic("window_solve_turn_rad", turn_rad);
  setDiagnostic("window_solve_turn_sigma_rad", solution.end_turn_sigma_rad);
  setDiagnostic("window_solve_range_scale", solution.range_scale);
  setDiagnostic("window_solve_ranges", static_cast<double>(problem.ranges.size()));
  mStep();
  emitMap(currentMap());
}

}  // namespace online_em
}  // namespace roam
