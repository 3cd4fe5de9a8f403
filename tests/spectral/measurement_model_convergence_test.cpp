// The spectral paper's Fig. 1B: the learned observation model converges as range readings
// accumulate, at the rate of its bound (Eq. 13), ||sin Psi||_2 <= N c sqrt(2 log(T) / T) / gamma.
//
// Psi are the principal angles between the true observation subspace, range(C) with
// C_n = [|m_n|^2/2, m_nx, m_ny, 1], and the learned one, range(U) of the top-4 left singular
// vectors of Y (Y_nt = r_nt^2 / 2 from noisy ranges). ||sin Psi||_2 = ||(I - U U^T) Q||_2 with Q an
// orthonormal basis of range(C). Range noise adds sigma^2/2 to every entry of Y on average: a
// constant, which lies in range(C) (its last column is all ones), so the estimate is unbiased and
// the error falls as 1/sqrt(T) up to the log factor: slope about -1/2 on log-log.
//
// The test prints the table (readings, mean error over the worlds) that the figure plots.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <map>
#include <vector>

#include <Eigen/Dense>

#include "sim.hpp"
#include "thin_svd.hpp"

namespace roam {
namespace {

constexpr int kWorlds = 60;      // random worlds per path length (the paper: 1000)
constexpr int kBeacons = 6;      // as the paper's Fig. 1A
// Range noise enters Y as d e + e^2/2: its mean (sigma^2/2) lies in range(C), but its variance
// d_n^2 sigma^2 differs per beacon, so the noise covariance is not isotropic and the top
// eigenvectors of Y Y^T carry an O(sigma^2) bias that the 1/sqrt(T) term meets after enough
// readings (with sigma = 0.5 m the error levels off near 0.02 after ~10^4 readings). 0.1 m keeps
// that floor 25x lower, so the rate of the bound is what the lengths below show.
constexpr double kRangeSigma_m = 0.1;
constexpr double kSlopeLow = -0.65, kSlopeHigh = -0.35;  // -1/2, up to sqrt(log T) and noise

double sinPsi(const sim::SimRun& run) {
  std::map<int, int> row_of;  // beacon id -> row
  for (const Beacon& b : run.beacons) row_of.emplace(b.id, static_cast<int>(row_of.size()));
  std::map<int64_t, int> column_of;  // pose utime -> column
  for (const Pose& p : run.ground_truth) column_of.emplace(p.utime, static_cast<int>(column_of.size()));
  Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(kBeacons, static_cast<Eigen::Index>(column_of.size()));
  Eigen::MatrixXi seen = Eigen::MatrixXi::Zero(Y.rows(), Y.cols());
  for (const Range& r : run.ranges) {
    const auto column = column_of.find(r.utime);
    if (column == column_of.end()) continue;
    Y(row_of.at(r.beacon_id), column->second) = 0.5 * r.range_m * r.range_m;
    seen(row_of.at(r.beacon_id), column->second) = 1;
  }
  EXPECT_EQ(seen.minCoeff(), 1) << "every beacon ranged at every pose";
  Eigen::MatrixXd C(kBeacons, 4);
  for (const Beacon& b : run.beacons)
    C.row(row_of.at(b.id)) << 0.5 * (b.x_m * b.x_m + b.y_m * b.y_m), b.x_m, b.y_m, 1.0;
  const Eigen::MatrixXd Q = Eigen::HouseholderQR<Eigen::MatrixXd>(C).householderQ() *
                            Eigen::MatrixXd::Identity(kBeacons, 4);
  const Eigen::MatrixXd U = topLeftSvd(Y, 4).U;
  const Eigen::MatrixXd residual = Q - U * (U.transpose() * Q);
  return Eigen::JacobiSVD<Eigen::MatrixXd>(residual).singularValues()(0);
}

TEST(MeasurementModel, ConvergesAtTheRateOfTheBound) {
  std::vector<double> log_readings, log_error;
  std::printf("%10s %10s %14s %14s\n", "steps", "readings", "mean sin(Psi)", "median");
  // From 400 steps on: shorter random walks barely span the plane, so the eigen-gap gamma of the
  // bound is still growing with T and the error falls faster than the asymptotic rate.
  for (int steps : {400, 800, 1600, 3200, 6400}) {
    double sum = 0.0;
    std::vector<double> errors;
    for (int world = 0; world < kWorlds; ++world) {
      sim::SimConfig c;
      c.seed = static_cast<uint64_t>(world + 1);  // the same worlds at every length (paired)
      c.num_steps = steps;
      c.path = sim::PathKind::kRandomWalk;
      c.area_width_m = 30.0;
      c.area_height_m = 30.0;
      c.num_beacons = kBeacons;
      c.schedule = sim::RangeSchedule::kEveryStepAllBeacons;
      c.range_sigma_m = kRangeSigma_m;
      errors.push_back(sinPsi(sim::simulate(c)));
      sum += errors.back();
    }
    const double readings = static_cast<double>(kBeacons) * (steps + 1);
    const double mean = sum / kWorlds;
    std::nth_element(errors.begin(), errors.begin() + kWorlds / 2, errors.end());
    std::printf("%10d %10.0f %14.5f %14.5f\n", steps, readings, mean, errors[kWorlds / 2]);
    log_readings.push_back(std::log(readings));
    // The median over worlds: a few worlds whose path is still nearly degenerate (small gamma)
    // dominate the mean at every length and hide the rate.
    log_error.push_back(std::log(errors[kWorlds / 2]));
  }
  // Least-squares slope of log(median error) on log(readings).
  const Eigen::Map<const Eigen::VectorXd> x(log_readings.data(), static_cast<Eigen::Index>(log_readings.size()));
  const Eigen::Map<const Eigen::VectorXd> y(log_error.data(), static_cast<Eigen::Index>(log_error.size()));
  const Eigen::VectorXd xc = x.array() - x.mean(), yc = y.array() - y.mean();
  const double slope = xc.dot(yc) / xc.dot(xc);
  std::printf("log-log slope %.3f (the bound: -1/2 up to sqrt(log T))\n", slope);
  EXPECT_GT(slope, kSlopeLow);
  EXPECT_LT(slope, kSlopeHigh);
}

}  // namespace
}  // namespace roam
