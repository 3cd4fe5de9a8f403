// spectral_batch::solve on noise-free synthetic runs: exact recovery from a perturbed start.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "batch_problem.hpp"
#include "sim.hpp"

namespace roam {
namespace spectral_batch {
namespace {

// Noise-free data has its optimum (zero cost) at the truth: the solve must land there.
constexpr double kExactTolerance_m = 1e-6;
constexpr double kExactHeadingTolerance_rad = 1e-6;

sim::SimConfig smallRun() {
  sim::SimConfig config;
  config.seed = 3;
  config.num_steps = 300;  // 60 s, a lawn mower over 20 m x 10 m: two turns
  config.area_width_m = 20.0;
  config.area_height_m = 10.0;
  config.schedule = sim::RangeSchedule::kEveryStepAllBeacons;
  return config;
}

State truthOf(const Dataset& run, const std::map<int, int>& beacon_index) {
  State truth;
  for (const Pose& pose : run.ground_truth) truth.poses.push_back({pose.x_m, pose.y_m, pose.heading_rad});
  truth.beacons.resize(beacon_index.size());
  for (const Beacon& beacon : run.beacons) truth.beacons[beacon_index.at(beacon.id)] = {beacon.x_m, beacon.y_m};
  return truth;
}

// The problem of a simulated run: its ranges are taken at pose times (alpha = 0).
Problem problemOf(const Dataset& run, const SpectralBatchConfig& config, std::map<int, int>* beacon_index) {
  Problem problem;
  problem.odometry = run.odometry;
  for (const Beacon& beacon : run.beacons) {
    (*beacon_index)[beacon.id] = static_cast<int>(beacon_index->size());
    problem.beacon_fixed.push_back(false);
  }
  std::map<int64_t, int> pose_of_utime;
  for (size_t k = 0; k < run.ground_truth.size(); ++k) pose_of_utime[run.ground_truth[k].utime] = static_cast<int>(k);
  for (const Range& range : run.ranges) {
    RangeObservation observation;
    observation.pose = pose_of_utime.at(range.utime);
    observation.beacon = beacon_index->at(range.beacon_id);
    observation.range_m = range.range_m;
    observation.sigma_m = config.range_sigma_m;
    problem.ranges.push_back(observation);
  }
  return problem;
}

// The truth plus seeded Gaussian errors: 0.3 m and 0.05 rad on poses (not the first), 1 m on
// beacons.
State perturbed(const State& truth, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> position_m(0.0, 0.3), heading_rad(0.0, 0.05), beacon_m(0.0, 1.0);
  State start = truth;
  for (size_t k = 1; k < start.poses.size(); ++k) {
    start.poses[k][0] += position_m(rng);
    start.poses[k][1] += position_m(rng);
    start.poses[k][2] += heading_rad(rng);
  }
  for (auto& beacon : start.beacons) {
    beacon[0] += beacon_m(rng);
    beacon[1] += beacon_m(rng);
  }
  return start;
}

void expectExact(const State& solved, const State& truth) {
  for (size_t k = 0; k < truth.poses.size(); ++k) {
    EXPECT_NEAR(solved.poses[k][0], truth.poses[k][0], kExactTolerance_m) << "pose " << k;
    EXPECT_NEAR(solved.poses[k][1], truth.poses[k][1], kExactTolerance_m) << "pose " << k;
    EXPECT_NEAR(std::remainder(solved.poses[k][2] - truth.poses[k][2], 2 * M_PI), 0.0,
                kExactHeadingTolerance_rad) << "pose " << k;
  }
  for (size_t j = 0; j < truth.beacons.size(); ++j) {
    EXPECT_NEAR(solved.beacons[j][0], truth.beacons[j][0], kExactTolerance_m) << "beacon " << j;
    EXPECT_NEAR(solved.beacons[j][1], truth.beacons[j][1], kExactTolerance_m) << "beacon " << j;
  }
}

TEST(BatchSolve, ExactRecoveryFromPerturbedStart) {
  const Dataset run = sim::simulate(smallRun());
  for (const char* loss : {"none", "cauchy", "tukey", "huber"}) {
    SpectralBatchConfig config;
    setOptions(&config, addSpectralBatchOptions, {{"loss", loss}});
    std::map<int, int> beacon_index;
    const Problem problem = problemOf(run, config, &beacon_index);
    const State truth = truthOf(run, beacon_index);
    State state = perturbed(truth, 11);
    const Summary summary = solve(config, problem, &state);
    ASSERT_TRUE(summary.usable) << summary.report;
    SCOPED_TRACE(loss);
    expectExact(state, truth);
    // Calibration estimated (the default): the true scale 1 and offset 0 come back.
    EXPECT_NEAR(state.calibration[0], 1.0, 1e-8);
    EXPECT_NEAR(state.calibration[1], 0.0, 1e-7);
  }
}

TEST(BatchSolve, ExactRecoveryWithRangesBetweenPoses) {
  // Ranges at 30 % and 70 % of each step, predicted exactly from the true positions: the sim's
  // robot moves straight along heading k during step k, so linear interpolation is exact.
  const Dataset run = sim::simulate(smallRun());
  SpectralBatchConfig config;
  Problem problem;
  problem.odometry = run.odometry;
  std::map<int, int> beacon_index;
  for (const Beacon& beacon : run.beacons) {
    beacon_index[beacon.id] = static_cast<int>(beacon_index.size());
    problem.beacon_fixed.push_back(false);
  }
  const State truth = truthOf(run, beacon_index);
  for (size_t k = 0; k + 1 < truth.poses.size(); ++k) {
    for (double alpha : {0.3, 0.7}) {
      const int j = static_cast<int>((k * 2 + (alpha > 0.5 ? 1 : 0)) % truth.beacons.size());
      const double x_m = truth.poses[k][0] + alpha * (truth.poses[k + 1][0] - truth.poses[k][0]);
      const double y_m = truth.poses[k][1] + alpha * (truth.poses[k + 1][1] - truth.poses[k][1]);
      RangeObservation observation;
      observation.pose = static_cast<int>(k);
      observation.alpha = alpha;
      observation.beacon = j;
      observation.range_m = std::hypot(truth.beacons[j][0] - x_m, truth.beacons[j][1] - y_m);
      observation.sigma_m = config.range_sigma_m;
      problem.ranges.push_back(observation);
    }
  }
  State state = perturbed(truth, 12);
  const Summary summary = solve(config, problem, &state);
  ASSERT_TRUE(summary.usable) << summary.report;
  expectExact(state, truth);
}

TEST(BatchSolve, FixedBeaconsAreTheGauge) {
  // anchor = beacons: beacons held at the truth, the first pose free (perturbed too).
  const Dataset run = sim::simulate(smallRun());
  SpectralBatchConfig config;
  std::map<int, int> beacon_index;
  Problem problem = problemOf(run, config, &beacon_index);
  problem.fix_first_pose = false;
  problem.beacon_fixed.assign(problem.beacon_fixed.size(), true);
  const State truth = truthOf(run, beacon_index);
  State state = perturbed(truth, 13);
  state.beacons = truth.beacons;
  state.poses[0][0] += 0.5;
  state.poses[0][1] -= 0.5;
  const Summary summary = solve(config, problem, &state);
  ASSERT_TRUE(summary.usable) << summary.report;
  expectExact(state, truth);
}

TEST(BatchSolve, ASeedAtTheInliersSpreadIsSolvedOnceAtTheFinalScale) {
  // The first stage starts at the seed's robust residual spread, clamped to the final scale:
  // from a seed within the ranges' noise every stage is at the final scale, so the annealed solve
  // is the single-stage solve (one Ceres solve, bit-identical) and loss_anneal_check has nothing
  // to add. From a seed metres off the stages and the check are all made.
  const Dataset run = sim::simulate(smallRun());
  SpectralBatchConfig config;  // cauchy, 3 stages, loss_anneal_check
  std::map<int, int> beacon_index;
  Problem problem = problemOf(run, config, &beacon_index);
  problem.from_seed = true;
  const State truth = truthOf(run, beacon_index);

  State annealed = truth;
  const Summary summary = solve(config, problem, &annealed);
  ASSERT_TRUE(summary.usable) << summary.report;
  EXPECT_EQ(summary.stages, 1) << summary.report;
  SpectralBatchConfig one_stage = config;
  one_stage.loss_anneal_stages = 1;
  State single = truth;
  ASSERT_TRUE(solve(one_stage, problem, &single).usable);
  for (size_t k = 0; k < truth.poses.size(); ++k)
    for (int i = 0; i < 3; ++i) ASSERT_EQ(annealed.poses[k][i], single.poses[k][i]) << "pose " << k;
  for (size_t j = 0; j < truth.beacons.size(); ++j)
    for (int i = 0; i < 2; ++i) ASSERT_EQ(annealed.beacons[j][i], single.beacons[j][i]) << "beacon " << j;

  State far = truth;
  for (auto& beacon : far.beacons) beacon[0] += 20.0;  // ranges off by metres: a wide first stage
  const Summary from_far = solve(config, problem, &far);
  ASSERT_TRUE(from_far.usable) << from_far.report;
  EXPECT_EQ(from_far.stages, 4) << from_far.report;  // three stages and the check
}

TEST(BatchSolve, RejectsInconsistentProblems) {
  SpectralBatchConfig config;
  Problem problem;
  problem.odometry.resize(2);
  State state;
  state.poses.resize(2);  // one too few
  EXPECT_THROW(solve(config, problem, &state), std::invalid_argument);
}

}  // namespace
}  // namespace spectral_batch
}  // namespace roam
