// multilaterate(): exact recovery, the mirror wait, the geometry gates, the bias unknowns.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "roam/estimation/multilateration.hpp"

namespace roam {
namespace estimation {
namespace {

constexpr double kExact_m = 1e-8;

std::vector<Sighting> sightingsOf(const Eigen::Vector2d& beacon, const std::vector<Eigen::Vector2d>& at,
                                  double scale = 1.0, double offset_m = 0.0) {
  std::vector<Sighting> out;
  for (size_t i = 0; i < at.size(); ++i) {
    Sighting s;
    s.step = static_cast<int64_t>(i);
    s.x_m = at[i].x();
    s.y_m = at[i].y();
    s.range_m = scale * (beacon - at[i]).norm() + offset_m;
    s.sigma_m = 0.3;
    out.push_back(s);
  }
  return out;
}

// An L-shaped path: 10 m along +x, then 10 m along +y, a point per metre.
std::vector<Eigen::Vector2d> lPath() {
  std::vector<Eigen::Vector2d> at;
  for (int i = 0; i <= 10; ++i) at.emplace_back(i, 0.0);
  for (int i = 1; i <= 10; ++i) at.emplace_back(10.0, i);
  return at;
}

TEST(Multilateration, ExactRangesGiveTheBeacon) {
  const Eigen::Vector2d beacon(3.0, 7.0);  // seen from the L over more than 1 rad
  const MultilaterationResult r = multilaterate(sightingsOf(beacon, lPath()), RangeBiasPrior{}, MultilaterationConfig{});
  EXPECT_EQ(r.status, MultilaterationResult::Status::kReady);
  EXPECT_NEAR(r.world_m.x(), 3.0, kExact_m);
  EXPECT_NEAR(r.world_m.y(), 7.0, kExact_m);
  EXPECT_NEAR(r.chi2, 0.0, 1e-12);
}

TEST(Multilateration, EstimatesTheRangeBiasWithItsPrior) {
  // Ranges 7 % long plus 0.2 m. With a prior too weak to pull (scale 1 +- 100, offset 0 +- 1000)
  // exact ranges from the L determine beacon, scale and offset exactly (4 unknowns, 21 ranges,
  // the ranges' distance varies along the L in a way no other (m, s, b) reproduces).
  const Eigen::Vector2d beacon(3.0, 7.0);
  RangeBiasPrior weak;
  weak.scale_sigma = 100.0;
  weak.offset_sigma_m = 1000.0;
  const MultilaterationResult r =
      multilaterate(sightingsOf(beacon, lPath(), 1.07, 0.2), weak, MultilaterationConfig{});
  constexpr double kTolerance = 1e-6;  // the priors' pull: ~ (0.07 / 100)^2 of the data's weight
  EXPECT_NEAR(r.scale, 1.07, kTolerance);
  EXPECT_NEAR(r.offset_m, 0.2, kTolerance);
  EXPECT_NEAR((r.world_m - beacon).norm(), 0.0, kTolerance);
  // With the filter's usual prior (scale 1 +- 0.1) the prior pulls the scale towards 1 and the
  // marginal covariance of the beacon grows: the bias uncertainty is in cov_m2.
  RangeBiasPrior usual;
  usual.scale_sigma = 0.1;
  usual.offset_sigma_m = 0.5;
  const MultilaterationResult pulled =
      multilaterate(sightingsOf(beacon, lPath(), 1.07, 0.2), usual, MultilaterationConfig{});
  EXPECT_GT(pulled.scale, 1.0);
  EXPECT_LT(pulled.scale, 1.07);
  const MultilaterationResult fixed = multilaterate(sightingsOf(beacon, lPath()), RangeBiasPrior{}, MultilaterationConfig{});
  EXPECT_GT(pulled.cov_m2.trace(), fixed.cov_m2.trace());
}

TEST(Multilateration, SolvesTheHeadingRateBiasThatCurlsThePath) {
  // The recorded path is the true one turned about the start by db t (a gyro bias error db after
  // t seconds, 1 s per metre): position = truth - (dx_db, dy_db) db with (dx_db, dy_db) the
  // derivative of that turn, t (-y, x) (linear in db, as the EKF's regression is). With the
  // bias error solved for (a prior of 1 rad/s, which barely pulls) exact ranges give the beacon
  // and db; without it the fit is far outside the noise and the beacon is off.
  const Eigen::Vector2d beacon(3.0, 7.0);
  const double db_rad_s = 0.01;
  const std::vector<Eigen::Vector2d> truth = lPath();
  std::vector<Sighting> sightings = sightingsOf(beacon, truth);
  for (size_t i = 0; i < sightings.size(); ++i) {
    const double t_s = static_cast<double>(i);
    sightings[i].dx_db = -t_s * truth[i].y();
    sightings[i].dy_db = t_s * truth[i].x();
    sightings[i].x_m -= sightings[i].dx_db * db_rad_s;
    sightings[i].y_m -= sightings[i].dy_db * db_rad_s;
  }
  RangeBiasPrior with_db;
  with_db.heading_rate_bias_sigma_rad_s = 1.0;
  const MultilaterationResult solved = multilaterate(sightings, with_db, MultilaterationConfig{});
  EXPECT_NEAR(solved.world_m.x(), beacon.x(), 1e-3);
  EXPECT_NEAR(solved.world_m.y(), beacon.y(), 1e-3);
  EXPECT_NEAR(solved.heading_rate_bias_rad_s, db_rad_s, 1e-5);
  EXPECT_LT(solved.chi2, 1e-3);
  const MultilaterationResult plain = multilaterate(sightings, RangeBiasPrior{}, MultilaterationConfig{});
  EXPECT_EQ(plain.heading_rate_bias_rad_s, 0.0);
  EXPECT_GT((plain.world_m - beacon).norm(), 0.5);
  EXPECT_GT(plain.chi2, 5.0);  // measured 7.7 (sigma 0.3 m), against < 1e-3
}

TEST(Multilateration, StraightPathIsAmbiguous) {
  // Sightings on the x axis: (5, 4) and its mirror (5, -4) fit every range exactly.
  std::vector<Eigen::Vector2d> line;
  for (int i = 0; i <= 20; ++i) line.emplace_back(0.5 * i, 0.0);
  const MultilaterationResult r =
      multilaterate(sightingsOf(Eigen::Vector2d(5.0, 4.0), line), RangeBiasPrior{}, MultilaterationConfig{});
  EXPECT_EQ(r.status, MultilaterationResult::Status::kAmbiguous);
  EXPECT_NEAR(std::abs(r.world_m.y()), 4.0, 1e-6);
  EXPECT_NEAR(r.rival_chi2 - r.chi2, 0.0, 1e-9);
}

TEST(Multilateration, GeometryGates) {
  MultilaterationConfig config;
  // Too few ranges.
  const std::vector<Eigen::Vector2d> path = lPath();
  const std::vector<Eigen::Vector2d> few(path.begin(), path.begin() + 3);
  EXPECT_EQ(multilaterate(sightingsOf(Eigen::Vector2d(3, 7), few), RangeBiasPrior{}, config).status,
            MultilaterationResult::Status::kTooFew);
  // A far beacon (100 m) seen from the 10 m L spans about 0.14 rad < min_angle_rad = 1.
  EXPECT_EQ(multilaterate(sightingsOf(Eigen::Vector2d(-60, 80), lPath()), RangeBiasPrior{}, config).status,
            MultilaterationResult::Status::kNarrowAngle);
  // All sightings within 1 m: short baseline.
  std::vector<Eigen::Vector2d> cluster;
  for (int i = 0; i < 10; ++i) cluster.emplace_back(0.1 * i, 0.05 * i);
  EXPECT_EQ(multilaterate(sightingsOf(Eigen::Vector2d(3, 7), cluster), RangeBiasPrior{}, config).status,
            MultilaterationResult::Status::kShortBaseline);
}

}  // namespace
}  // namespace estimation
}  // namespace roam
