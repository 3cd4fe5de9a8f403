// The shared standstill rule (roam/estimation/standstill.hpp): slow steps in a row turning at one
// rate are a standstill from the min_steps-th on; a fast step, a changing rate or a reset start
// the count again.
#include <gtest/gtest.h>

#include "roam/estimation/standstill.hpp"

namespace roam {
namespace estimation {
namespace {

Odometry makeStep(double forward_m, double turn_rad) {
  Odometry o;
  o.forward_m = forward_m;
  o.delta_heading_rad = turn_rad;
  return o;
}

// 0.2 s steps, turn sigma 1e-4 rad (rate sigma 5e-4 rad/s), gate 9: rates agree within
// 3 sqrt(2) x 5e-4 = 2.1e-3 rad/s.
constexpr double kDt_s = 0.2, kTurnVar_rad2 = 1e-8;

TEST(Standstill, ConfirmedOnTheFifthSlowStepAtOneRate) {
  Standstill standstill({0.02, 5, 9.0});
  // A gyro at rest drifting at 0.01 rad/s (0.002 rad a step), creeping 1 mm a step (5 mm/s).
  for (int k = 1; k <= 4; ++k) EXPECT_FALSE(standstill.confirm(makeStep(0.001, 0.002), kDt_s, kTurnVar_rad2)) << k;
  EXPECT_TRUE(standstill.confirm(makeStep(0.001, 0.002), kDt_s, kTurnVar_rad2));
  EXPECT_TRUE(standstill.confirm(makeStep(0.0, 0.0021), kDt_s, kTurnVar_rad2));  // 5e-4 rad/s apart: agrees
  // 0.005 m in 0.2 s is 0.025 m/s: moving, and the count starts again.
  EXPECT_FALSE(standstill.confirm(makeStep(0.005, 0.002), kDt_s, kTurnVar_rad2));
  for (int k = 1; k <= 4; ++k) EXPECT_FALSE(standstill.confirm(makeStep(0.0, 0.002), kDt_s, kTurnVar_rad2)) << k;
  EXPECT_TRUE(standstill.confirm(makeStep(0.0, 0.002), kDt_s, kTurnVar_rad2));
  standstill.reset();
  EXPECT_FALSE(standstill.confirm(makeStep(0.0, 0.002), kDt_s, kTurnVar_rad2));
}

TEST(Standstill, ASlowVehicleTurningAtChangingRatesIsNotStandingStill) {
  // An AUV drifting at 1 cm/s, its turn rate changing by 0.01 rad/s (~5 gate widths) a step.
  Standstill standstill({0.02, 5, 9.0});
  for (int k = 0; k < 20; ++k)
    EXPECT_FALSE(standstill.confirm(makeStep(0.002, (k % 2 ? 0.002 : 0.0)), kDt_s, kTurnVar_rad2)) << k;
  // dt = 0 and the rule off never stand still.
  EXPECT_FALSE(standstill.confirm(makeStep(0.0, 0.0), 0.0, kTurnVar_rad2));
  Standstill off({0.0, 1, 9.0});
  EXPECT_FALSE(off.confirm(makeStep(0.0, 0.0), kDt_s, kTurnVar_rad2));
}

TEST(Standstill, ARobotTurningInPlaceAtASteadyRateIsNotStandingStill) {
  // A ground robot turning on the spot at 0.067 rad/s, steady to the gyro's noise: beyond the
  // bias prior's gate (3 x 0.01 rad/s), so never a standstill however many steps it lasts.
  Standstill standstill({0.02, 5, 9.0});
  for (int k = 0; k < 20; ++k)
    EXPECT_FALSE(standstill.confirm(makeStep(0.0, 0.067 * kDt_s), kDt_s, kTurnVar_rad2)) << k;
  // The same robot at rest, its gyro drifting at 0.02 rad/s (2 sigma of the prior): a standstill.
  for (int k = 1; k <= 4; ++k) EXPECT_FALSE(standstill.confirm(makeStep(0.0, 0.02 * kDt_s), kDt_s, kTurnVar_rad2)) << k;
  EXPECT_TRUE(standstill.confirm(makeStep(0.0, 0.02 * kDt_s), kDt_s, kTurnVar_rad2));
}

}  // namespace
}  // namespace estimation
}  // namespace roam
