#include "roam/estimation/rotation_about_start.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace roam {
namespace estimation {
namespace {

// A reference path (an arc) and the same path turned by angle about a first pose moved elsewhere.
struct Paths {
  std::vector<std::array<double, 2>> reference, solved;
  std::vector<double> step_m;
};

Paths turnedArc(double angle_rad, int n) {
  Paths p;
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  for (int k = 0; k < n; ++k) {
    const double x = 10.0 * std::sin(0.05 * k), y = 10.0 * (1.0 - std::cos(0.05 * k));
    p.reference.push_back({x + 3.0, y - 1.0});
    p.solved.push_back({-7.0 + c * x - s * y, 4.0 + s * x + c * y});
    if (k > 0) p.step_m.push_back(0.5);
  }
  return p;
}

TEST(RotationAboutStart, RecoversTheTurnAboutTheFirstPoseExactly) {
  for (double angle : {0.0, 0.03, -0.4, 2.5}) {
    const Paths p = turnedArc(angle, 200);
    const StartRotation r = fitRotationAboutStart(p.solved, p.reference, p.step_m, 50.0);
    ASSERT_TRUE(r.defined);
    // The solved path is the reference turned by +angle: turning it back takes -angle.
    EXPECT_NEAR(r.angle_rad, -angle, 1e-12) << angle;
    EXPECT_DOUBLE_EQ(r.travelled_m, 50.5);  // poses enter while the travel before them is <= 50 m
  }
}

TEST(RotationAboutStart, UsesOnlyTheWindowAndSaysWhenThereWasNoTravel) {
  Paths p = turnedArc(0.2, 200);
  // Beyond the window (101 poses cover 50.5 m) the solved path may do anything.
  for (size_t k = 102; k < p.solved.size(); ++k) p.solved[k] = {1e3, -1e3};
  EXPECT_NEAR(fitRotationAboutStart(p.solved, p.reference, p.step_m, 50.0).angle_rad, -0.2, 1e-12);
  const Paths still{{{1.0, 1.0}, {1.0, 1.0}}, {{2.0, 2.0}, {2.0, 2.0}}, {0.0}};
  EXPECT_FALSE(fitRotationAboutStart(still.solved, still.reference, still.step_m, 50.0).defined);
  EXPECT_FALSE(fitRotationAboutStart({}, {}, {}, 50.0).defined);
}

TEST(RotationAboutStart, MismatchedSizesAreNamed) {
  const Paths p = turnedArc(0.1, 10);
  try {
    fitRotationAboutStart(p.solved, p.reference, p.step_m.size() > 1 ? std::vector<double>(3) : p.step_m, 5.0);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("10 solved positions, 10 reference positions and 3 steps"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace estimation
}  // namespace roam
