// The SDK's self-check (roam/self_check.hpp) and its statistic (roam/range_fit.hpp), on paths
// and ranges made here: exact recovery on noise-free ranges, the decision both ways, and the
// anchor's observability.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "roam/range_fit.hpp"
#include "roam/self_check.hpp"

namespace roam {
namespace {

struct Beacon2 {
  int id;
  double x_m, y_m;
};
const std::vector<Beacon2> kBeacons = {{1, 12.0, 3.0}, {2, -4.0, 9.0}, {3, 5.0, -8.0}, {4, 20.0, 15.0}};

// kBeacons as a survey (BEACONS), each where it is.
Map surveyOfEveryBeacon() {
  Map survey;
  for (const Beacon2& b : kBeacons) {
    roam::Beacon beacon;
    beacon.id = b.id;
    beacon.x_m = b.x_m;
    beacon.y_m = b.y_m;
    survey.push_back(beacon);
  }
  return survey;
}

// A loop: 200 steps of 0.1 s, 0.5 m forward and a steady turn (a circle of radius ~8 m).
std::vector<Odometry> loopSteps() {
  std::vector<Odometry> steps;
  for (int k = 1; k <= 200; ++k) {
    Odometry step;
    step.utime = k * 100000;
    step.forward_m = 0.5;
    step.delta_heading_rad = 0.06;
    steps.push_back(step);
  }
  return steps;
}

Path compose(const Pose& start, const std::vector<Odometry>& steps, double heading_bias_rad = 0.0) {
  Path path{start};
  for (const Odometry& step : steps) {
    const Pose& last = path.back();
    Pose next;
    next.utime = step.utime;
    next.x_m = last.x_m + std::cos(last.heading_rad) * step.forward_m;
    next.y_m = last.y_m + std::sin(last.heading_rad) * step.forward_m;
    next.heading_rad = last.heading_rad + step.delta_heading_rad + heading_bias_rad;
    path.push_back(next);
  }
  return path;
}

// Every beacon ranged at every pose after the start, with Gaussian noise of `sigma_m`.
std::vector<Range> rangesAlong(const Path& truth, double sigma_m, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> noise(0.0, sigma_m);
  std::vector<Range> ranges;
  for (size_t k = 1; k < truth.size(); ++k)
    for (const Beacon2& b : kBeacons) {
      Range r;
      r.utime = truth[k].utime;
      r.beacon_id = b.id;
      r.range_m = std::hypot(b.x_m - truth[k].x_m, b.y_m - truth[k].y_m) + (sigma_m > 0 ? noise(random) : 0.0);
      ranges.push_back(r);
    }
  return ranges;
}

std::vector<RangeRecord> records(const std::vector<Range>& ranges) {
  std::vector<RangeRecord> out;
  for (const Range& r : ranges) out.push_back({r.utime, r.beacon_id, r.range_m});
  return out;
}

Pose startPose() {
  Pose start;
  start.utime = 0;
  return start;
}

TEST(RangeFit, TheTruePathExplainsNoiseFreeRangesExactlyInAnyFrame) {
  const Path truth = compose(startPose(), loopSteps());
  const auto ranges = records(rangesAlong(truth, 0.0, 1));
  const RangeFit fit = rangeFit(truth, ranges);
  EXPECT_EQ(fit.ranges, 800);
  EXPECT_LT(fit.mean_abs_residual_m, 1e-6);
  // A rigid motion of the path (rotated 0.7 rad, moved 30 m): its beacons move with it.
  Path moved = truth;
  for (Pose& p : moved) {
    const double x = p.x_m, y = p.y_m;
    p.x_m = std::cos(0.7) * x - std::sin(0.7) * y + 30.0;
    p.y_m = std::sin(0.7) * x + std::cos(0.7) * y - 5.0;
  }
  EXPECT_LT(rangeFit(moved, ranges).mean_abs_residual_m, 1e-6);
  // A drifted one does not.
  EXPECT_GT(rangeFit(compose(startPose(), loopSteps(), 0.003), ranges).mean_abs_residual_m, 0.1);
}

// With a survey the beacons stay where it puts them: the frame is fixed, and a rigid motion of
// the path is seen. The range scale and offset are fitted: a ranging system 7 % long and 0.3 m
// late costs the true path nothing.
TEST(RangeFit, SurveyedBeaconsFixTheFrameAndTheCalibrationIsFitted) {
  const Path truth = compose(startPose(), loopSteps());
  auto ranges = records(rangesAlong(truth, 0.0, 1));
  for (auto& r : ranges) r.range_m = 1.07 * r.range_m + 0.3;
  const Map survey = surveyOfEveryBeacon();
  const RangeFit fit = rangeFit(truth, ranges, survey, true);
  EXPECT_LT(fit.mean_abs_residual_m, 1e-6);
  EXPECT_NEAR(fit.scale, 1.07, 1e-6);
  EXPECT_NEAR(fit.offset_m, 0.3, 1e-5);
  // Half the survey: the other two are placed, the same exact fit.
  EXPECT_LT(rangeFit(truth, ranges, Map(survey.begin(), survey.begin() + 2), true).mean_abs_residual_m, 1e-6);
  // Held at scale 1 and offset 0, the same ranges are not explained.
  EXPECT_GT(rangeFit(truth, ranges, survey, false).mean_abs_residual_m, 0.5);
  Path turned = truth;
  for (Pose& p : turned) {
    const double x = p.x_m, y = p.y_m;
    p.x_m = std::cos(0.1) * x - std::sin(0.1) * y;
    p.y_m = std::sin(0.1) * x + std::cos(0.1) * y;
  }
  EXPECT_LT(rangeFit(turned, ranges, {}, true).mean_abs_residual_m, 1e-6);
  EXPECT_GT(rangeFit(turned, ranges, survey, true).mean_abs_residual_m, 0.3);
}

TEST(RangeFit, ABeaconBesideAStraightRunIsFoundOnEitherSide) {
  Path line;
  for (int k = 0; k <= 50; ++k) {
    Pose p;
    p.utime = k * 100000;
    p.x_m = 0.4 * k;
    line.push_back(p);
  }
  std::vector<RangeRecord> ranges;
  for (const Pose& p : line) ranges.push_back({p.utime, 7, std::hypot(8.0 - p.x_m, -6.0 - p.y_m)});
  EXPECT_LT(rangeFit(line, ranges).mean_abs_residual_m, 1e-6);
}

TEST(RangeFit, OnlyBeaconsRangedThreeTimesWithinTheSpanAreScored) {
  const std::vector<RangeRecord> ranges = {{10, 1, 5.0}, {20, 1, 5.0}, {30, 1, 5.0}, {10, 2, 4.0},
                                           {20, 2, 4.0}, {99, 2, 4.0}, {5, 3, 1.0}};
  const auto scored = rangesToScore(ranges, 10, 30);
  ASSERT_EQ(scored.size(), 3u);
  for (const auto& r : scored) EXPECT_EQ(r.beacon_id, 1);
}

// Worse beyond chance: paired differences against twice their batch-means standard error.
TEST(SelfCheck, WorseMeansWorseBeyondChance) {
  std::mt19937 random(5);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<double> a(1000), b(1000);
  for (size_t k = 0; k < a.size(); ++k) {
    a[k] = std::abs(noise(random));
    b[k] = std::abs(noise(random));
  }
  EXPECT_FALSE(worseBeyondChance(a, a));  // the same residuals
  // Equal in distribution: worse by chance alone, and not called worse either way.
  EXPECT_FALSE(worseBeyondChance(a, b));
  EXPECT_FALSE(worseBeyondChance(b, a));
  // 0.3 m worse on every range: far beyond the standard error (~0.03 m).
  std::vector<double> worse = a;
  for (double& r : worse) r += 0.3;
  EXPECT_TRUE(worseBeyondChance(worse, a));
  EXPECT_FALSE(worseBeyondChance(a, worse));
  // One range far off among a thousand equal ones: a batch mean moves, the rest do not.
  std::vector<double> one_off = a;
  one_off[500] += 50.0;
  EXPECT_FALSE(worseBeyondChance(one_off, a));
}

// An estimator that publishes a path it was handed.
class FixedPathEstimator : public Estimator {
 public:
  explicit FixedPathEstimator(Path path) : path_(std::move(path)) {}
  void addOdometry(const Odometry&) override { acceptOdometry(); }
  void addRange(const Range&) override { acceptRange(); }
  bool trajectory(bool, Path* path) override {
    *path = path_;
    return true;
  }

 private:
  Path path_;
};

// Feeds `estimator` and the self-check as the shim does; returns the path published.
Path publish(SelfCheck* check, FixedPathEstimator* estimator, const std::vector<Odometry>& steps,
             const std::vector<Range>& ranges) {
  check->startPose(startPose());
  for (const Odometry& step : steps) {
    estimator->addOdometry(step);
    check->odometry(step, true);
  }
  for (const Range& r : ranges) {
    estimator->addRange(r);
    check->range(r);
  }
  estimator->finish();
  check->finished();
  Path path;
  estimator->trajectory(true, &path);
  check->apply(*estimator, &path);
  return path;
}

double value(const SelfCheck& check, const std::string& key) {
  for (const auto& [k, v] : check.diagnostics())
    if (k == key) return v;
  return kNaN;
}

bool hasNoteStartingWith(const SelfCheck& check, const std::string& prefix) {
  for (const auto& [k, v] : check.diagnostics())
    if (k.rfind(prefix, 0) == 0 && v == 1.0) return true;
  return false;
}

// The odometry a drifting gyro gives (0.003 rad per step of bias); ranges of 0.1 m noise.
struct DriftingRun {
  std::vector<Odometry> steps = loopSteps();
  Path truth = compose(startPose(), steps);
  std::vector<Odometry> measured = [this] {
    auto out = steps;
    for (auto& s : out) s.delta_heading_rad += 0.003;
    return out;
  }();
  Path dead_reckoning = compose(startPose(), measured);
  std::vector<Range> ranges = rangesAlong(truth, 0.1, 7);
};

TEST(SelfCheck, APathTheRangesSupportIsPublishedAsItIs) {
  const DriftingRun run;
  SelfCheck check;
  FixedPathEstimator estimator(run.truth);
  const Path published = publish(&check, &estimator, run.measured, run.ranges);
  ASSERT_EQ(published.size(), run.truth.size());
  EXPECT_EQ(published[150].x_m, run.truth[150].x_m);
  EXPECT_LT(value(check, SelfCheck::kPathFit), 0.1);  // 0.8 sigma: |e| of a Gaussian
  EXPECT_GT(value(check, SelfCheck::kDeadReckoningFit), 0.5);
  EXPECT_EQ(value(check, SelfCheck::kRangesScored), 800.0);
  EXPECT_FALSE(hasNoteStartingWith(check, SelfCheck::kWorseNote));
}

TEST(SelfCheck, APathWorseThanDeadReckoningIsReplacedByItAndSaid) {
  const DriftingRun run;
  // Twice the drift, the other way: further from the ranges than the odometry is.
  auto worse_steps = run.steps;
  for (auto& s : worse_steps) s.delta_heading_rad -= 0.006;
  SelfCheck check;
  FixedPathEstimator estimator(compose(startPose(), worse_steps));
  const Path published = publish(&check, &estimator, run.measured, run.ranges);
  ASSERT_EQ(published.size(), run.dead_reckoning.size());
  for (size_t k = 0; k < published.size(); ++k) {
    ASSERT_NEAR(published[k].x_m, run.dead_reckoning[k].x_m, 1e-9) << k;
    ASSERT_NEAR(published[k].y_m, run.dead_reckoning[k].y_m, 1e-9) << k;
  }
  EXPECT_GT(value(check, SelfCheck::kPathFit), value(check, SelfCheck::kDeadReckoningFit));
  EXPECT_TRUE(hasNoteStartingWith(check, SelfCheck::kWorseNote));
  EXPECT_FALSE(check.replaced());  // that flag is the no-range rule's
}

// A path of the right shape in the wrong frame (the true path turned 0.3 rad about the start)
// explains the ranges as well as the truth when the beacons are free, and worse than dead
// reckoning against the survey: published only where there is no survey to tell.
TEST(SelfCheck, APathTurnedAwayFromTheSurveyIsReplacedWhereThereIsOne) {
  const auto steps = loopSteps();
  const Path truth = compose(startPose(), steps);
  auto measured = steps;
  for (auto& s : measured) s.delta_heading_rad += 0.0003;
  const auto ranges = rangesAlong(truth, 0.1, 11);
  Path turned = truth;
  for (Pose& p : turned) {
    const double x = p.x_m, y = p.y_m;
    p.x_m = std::cos(0.3) * x - std::sin(0.3) * y;
    p.y_m = std::sin(0.3) * x + std::cos(0.3) * y;
  }
  const Map survey = surveyOfEveryBeacon();
  for (bool surveyed : {false, true}) {
    SCOPED_TRACE(surveyed ? "with a survey" : "no survey");
    SelfCheck check;
    if (surveyed) check.surveyed(survey);
    FixedPathEstimator estimator(turned);
    const Path published = publish(&check, &estimator, measured, ranges);
    EXPECT_LT(value(check, SelfCheck::kPathFit), value(check, SelfCheck::kDeadReckoningFit));
    EXPECT_EQ(published[100].x_m == turned[100].x_m, !surveyed);
    EXPECT_EQ(hasNoteStartingWith(check, SelfCheck::kWorseNote), surveyed);
    if (surveyed)
      EXPECT_GT(value(check, SelfCheck::kPathSurveyFit), value(check, SelfCheck::kDeadReckoningSurveyFit));
    else
      EXPECT_TRUE(std::isnan(value(check, SelfCheck::kPathSurveyFit)));
  }
}

TEST(SelfCheck, DeadReckoningItselfIsLeftAsItIs) {
  const DriftingRun run;
  SelfCheck check;
  FixedPathEstimator estimator(run.dead_reckoning);
  const Path published = publish(&check, &estimator, run.measured, run.ranges);
  EXPECT_EQ(published.size(), run.dead_reckoning.size());
  EXPECT_FALSE(hasNoteStartingWith(check, SelfCheck::kWorseNote));
  EXPECT_NEAR(value(check, SelfCheck::kPathFit), value(check, SelfCheck::kDeadReckoningFit), 1e-9);
}

TEST(SelfCheck, AnchorOnBeaconsSaysWhenTheSurveyCannotFixTheFrame) {
  const DriftingRun run;
  struct Case {
    std::vector<int> surveyed_ids;
    bool line;
    bool note;
  };
  for (const Case& c : {Case{{1}, false, true}, Case{{1, 2}, false, true}, Case{{1, 2, 3}, false, false},
                        Case{{1, 2, 3}, true, true}, Case{{1, 2, 3, 4}, false, false}}) {
    SCOPED_TRACE(std::to_string(c.surveyed_ids.size()) + (c.line ? " on a line" : ""));
    SelfCheck check;
    check.anchor("beacons");
    Map survey;
    for (int id : c.surveyed_ids) {
      roam::Beacon b;
      b.id = id;
      b.x_m = c.line ? 3.0 * id : kBeacons[id - 1].x_m;
      b.y_m = c.line ? 1.0 * id : kBeacons[id - 1].y_m;
      survey.push_back(b);
    }
    check.surveyed(survey);
    FixedPathEstimator estimator(run.truth);
    publish(&check, &estimator, run.measured, run.ranges);
    EXPECT_EQ(hasNoteStartingWith(check, SelfCheck::kAnchorNote), c.note);
  }
  // With anchor = start_pose the survey is not the anchor: no note.
  SelfCheck check;
  check.anchor("start_pose");
  check.surveyed(Map(1));
  FixedPathEstimator estimator(run.truth);
  publish(&check, &estimator, run.measured, run.ranges);
  EXPECT_FALSE(hasNoteStartingWith(check, SelfCheck::kAnchorNote));
}

}  // namespace
}  // namespace roam
