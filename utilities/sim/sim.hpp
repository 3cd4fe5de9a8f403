// roam::sim — seeded synthetic range-only SLAM runs with ground truth.
//
// Motion model: the shared one (roam/estimation/motion_model.hpp), so noise-free odometry
// integrates exactly to the ground truth: x += d cos(theta); y += d sin(theta); theta += dtheta.
// Odometry is the true step distorted as a real sensor distorts it:
//   forward = odo_distance_scale * d + noise,  lateral = noise,
//   dtheta_reported = dtheta + b_k * dt + noise   (a gyro's bias b; b_0 = odo_heading_bias_radps,
//   b_k+1 = b_k + odo_heading_bias_walk_radps_per_sqrt_s * sqrt(dt) * N(0, 1): a MEMS gyro's bias
//   instability, drawn from its own random stream so the rest of the run is the same seed's)
// so a calibrating estimator should recover distance_scale = 1 / odo_distance_scale and
// heading_rate_bias = odo_heading_bias_radps. Ranges are taken at pose
// times (the end of an odometry step) to beacons in the world frame:
//   range = scale * |beacon - robot| + offset + noise (+ o_b),
// noise ~ N(0, range_sigma) (or the two-component mixture), occasionally replaced by outliers;
// o_b is beacon b's own offset (a transponder's turn-around delay, an anchor's antenna delay),
// |o_b| uniform in [beacon_offset_min_m, beacon_offset_max_m] with a random sign, drawn from its
// own stream and added to every range to b last, so a run without offsets is otherwise the same.
// The published beacons may carry a survey error (beacon_survey_sigma_m): ranges are made from the
// true positions, BEACONS gives them displaced, so an estimator anchored on them must not trust
// them to centimetres. Dataset::beacons (and so roam-eval's beacon error) are the published ones.
// A standing start (hold_s): the vehicle stands still for the first hold_s seconds (zero true
// steps; the odometry still carries its heading noise and gyro bias, ranges are still taken),
// then drives its path; num_steps counts both.
// Range gaps (every beacon silent for a while) remove the ranges inside them after everything
// is drawn, so the rest of the run is identical, bit for bit, to the same seed without gaps.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "dataset.hpp"
#include "roam/types.hpp"

namespace roam {
namespace sim {

// Every beacon silent over [start_s, start_s + duration_s), seconds after the start pose.
struct RangeGap {
  double start_s = 0.0;
  double duration_s = 0.0;
};

enum class PathKind { kRandomWalk, kLawnMower, kLoop, kFigureEight, kRacetrack };
enum class RangeSchedule {
  kEveryStepAllBeacons,  // every pose sees every beacon (complete measurement matrix)
  kRoundRobin            // one beacon at a time at range_rate_hz, cycling, like UWB
};

struct SimConfig {
  uint64_t seed = 1;
  int num_steps = 2000;          // odometry steps; poses = num_steps + 1
  double dt_s = 0.2;             // time per step
  double speed_mps = 1.0;
  int64_t start_utime = 1000000;  // utime of the start pose
  Pose start;                     // start pose (utime overwritten by start_utime)

  PathKind path = PathKind::kLawnMower;
  double area_width_m = 40.0;    // lawn-mower lane length / random-walk box width / racetrack straight
  double area_height_m = 30.0;   // lawn-mower sweep height / random-walk box height
  double lane_spacing_m = 5.0;   // lawn-mower distance between lanes
  double loop_radius_m = 15.0;   // loop path radius; each lobe of the figure-8; racetrack turns
  double turn_rate_sigma_radps = 0.3;  // random walk: std of the smooth turn-rate process
  // Standing start: the first round(hold_s / dt_s) steps do not move (a robot waiting before it
  // drives, like Plaza 1's ~45 s); the path's own steps follow, up to num_steps in all.
  double hold_s = 0.0;
  // Heading noise per step while standing (rad; < 0: odo_heading_sigma_rad). A gyro standing
  // still drifts by its bias and angle random walk only, far less than a driving robot's per-step
  // heading noise; that noise, accrued before the first metre, turns the whole start frame by an
  // amount nothing later observes (0.003 rad x sqrt(225 steps) = 0.045 rad: ~2 m at 40 m).
  double hold_heading_sigma_rad = -1.0;

  // Beacons: given, or num_beacons uniform in the box [-margin, W+margin] x [-margin, H+margin]
  // around the area swept by the robot (in the start frame for lawn-mower/random walk).
  Map beacons;
  int num_beacons = 4;
  double beacon_margin_m = 10.0;

  // Odometry noise: sigma_d = odo_distance_sigma_rel * d + odo_distance_sigma_m,
  // sigma_dtheta = odo_heading_sigma_rad (per step).
  double odo_distance_sigma_rel = 0.0;
  double odo_distance_sigma_m = 0.0;
  double odo_heading_sigma_rad = 0.0;
  double odo_lateral_sigma_rel = 0.0;    // lateral noise sigma per metre of the step
  double odo_distance_scale = 1.0;       // reported forward = scale * true
  double odo_heading_bias_radps = 0.0;   // reported turn = true + bias * dt
  double odo_heading_bias_walk_radps_per_sqrt_s = 0.0;  // the bias's random walk (0: constant)
  // Noise the odometry messages state: a diagonal covariance (translation sigma on both axes, m;
  // heading sigma, rad) written into every step, as a log's generator does (GOATS 16 states 0.02 m
  // and 0.002 rad per edge, for translation good to a metre). Both 0: none stated.
  double odo_sigma_reported_m = 0.0;
  double odo_heading_sigma_reported_rad = 0.0;

  RangeSchedule schedule = RangeSchedule::kEveryStepAllBeacons;
  double range_rate_hz = 2.0;       // round-robin rate (ranges per second, all beacons)
  double range_dropout = 0.0;       // probability a scheduled range is missing
  double range_sigma_m = 0.0;
  double range_scale = 1.0;
  double range_offset_m = 0.0;
  double range_sigma_reported_m = 0.0;  // written into Range::sigma_m (0: unknown)
  // Two-component mixture: with probability mixture_weight1 the noise has sigma range_sigma1_m.
  double mixture_weight1 = 0.0;
  double range_sigma1_m = 0.0;
  double outlier_fraction = 0.0;    // fraction of ranges replaced by true + U(outlier_min, max)
                                    // (negative outlier_min: short ranges too, e.g. echoes)
  double outlier_min_m = 5.0;
  double outlier_max_m = 30.0;
  // Episodes (> 0): outliers come in stretches per beacon, as a wall or a hull blocks the line of
  // sight for a while, instead of range by range. Each beacon alternates line-of-sight and
  // non-line-of-sight stretches of exponential length (mean outlier_episode_s in NLOS,
  // outlier_episode_s * (1 - f) / f in sight, f = outlier_fraction, so f of the time is NLOS);
  // every range of one stretch is true + one excess U(outlier_min, max), drawn per stretch, + the
  // range's own noise. Drawn on their own stream: the run is otherwise the same as without them.
  double outlier_episode_s = 0.0;
  std::vector<RangeGap> range_gaps;  // dropouts of every beacon (start >= 0, duration > 0)
  // Per-beacon range offsets o_b: |o_b| ~ U(min, max), sign random (max 0: none). GOATS' acoustic
  // beacons carry 1-2 m each.
  double beacon_offset_min_m = 0.0;
  double beacon_offset_max_m = 0.0;
  uint64_t beacon_offset_seed = 0;  // the offsets' stream (0: derived from seed, apart from the run's)
  // Survey error: the published beacon positions (BEACONS, Dataset::beacons) are the true ones
  // plus N(0, beacon_survey_sigma_m^2) on each axis, drawn from their own stream after every
  // range is made from the true positions, so the run is otherwise the same. An acoustic
  // transponder dropped from a ship and surveyed from it is known to metres (0: exact).
  double beacon_survey_sigma_m = 0.0;

  bool bearing = false;
  double bearing_sigma_rad = 0.0;
};

// ground_truth has num_steps + 1 poses (ground_truth[0] == start); odometry[k] moves from
// pose k to pose k+1 and carries pose k+1's utime; ranges are in time order; beacons are true.
using SimRun = Dataset;

SimRun simulate(const SimConfig& config);

// The per-beacon range offsets simulate() adds (beacon id -> o_b, m; empty with max 0): drawn
// from their own std::mt19937_64 (beacon_offset_seed, or one derived from seed apart from the
// run's stream), per beacon in order, magnitude then sign.
std::map<int, double> beaconOffsets(const SimConfig& config, const Map& beacons);
// The same draw from the stream seeded with stream_seed: |o_b| ~ U(min_m, max_m), random sign.
std::map<int, double> beaconOffsets(uint64_t stream_seed, double min_m, double max_m, const Map& beacons);

// The survey errors simulate() adds to the published beacons (beacon id -> (dx, dy), m; empty
// with sigma 0): from their own std::mt19937_64 (seed-derived, apart from the run's and the
// offsets' streams), per beacon in order, x then y.
std::map<int, std::array<double, 2>> beaconSurveyErrors(const SimConfig& config, const Map& beacons);

// The NLOS stretches of outlier_episode_s, per beacon id: [start_s, end_s) after the start pose
// and the excess range (m) of every range in it. Empty when outlier_episode_s is 0.
struct OutlierEpisode {
  double start_s;
  double end_s;
  double excess_m;
};
std::map<int, std::vector<OutlierEpisode>> outlierEpisodes(const SimConfig& config, const Map& beacons,
                                                           double duration_s);

// Parses "START_S:DURATION_S" (e.g. "120:30"); throws std::invalid_argument naming the problem
// (not two numbers, start < 0, duration <= 0).
RangeGap parseRangeGap(const std::string& text);

// Parses "random_walk" | "lawn_mower" | "loop" | "figure8" | "racetrack"; throws std::invalid_argument otherwise.
PathKind parsePathKind(const std::string& name);

// The AUV-like world of logs/synthetic/auv-sparse (there with seed 108 and 500 steps): 3 s steps
// at 1.5 m/s on a 300 x 200 m lawn mower, 4 beacons up to 200 m outside, one range every ~3 s
// (0.3 Hz round robin), 2 m of noise stated as 0.75 m, 45 % outliers from -150 to +100 m,
// odometry 15 % noisy forward and sideways and 3 % short. Every suite's AUV test starts here.
SimConfig auvLikeWorld(uint64_t seed, int num_steps);

// GOATS 16's sensors as its README states them (utilities/seed-sweep's auv-goats kind, 210
// steps): 7 s between poses at 0.7 m/s on a 250 x 150 m lawn mower, 4 beacons up to 250 m
// outside, each ranged at ~70 % of poses, 2 m of noise stated as 0.75 m, half the ranges outliers
// from -200 to +20 m, each beacon's own offset of 1-2 m, odometry heading nearly exact (0.001 rad
// per step), translation 20 % noisy forward and sideways and 3 % short; each step states GOATS
// 16's covariance (0.02 m, 0.002 rad).
SimConfig goatsLikeWorld(uint64_t seed, int num_steps);

// The drifting-gyro world of logs/synthetic/drift-figure8 (there seed 106, 4000 steps): a
// figure-8 of two 12 m circles at 1 m/s in 0.2 s steps, 6 beacons at 2 Hz round robin, 0.3 m
// range noise, 2 % odometry, 0.003 rad heading noise per step and 0.01 rad/s (0.57 deg/s) of
// gyro bias.
SimConfig gyroDriftFigure8World(uint64_t seed, int num_steps);

// The same figure-8 driven by a slow UWB robot (utilities/seed-sweep's slow-uwb, 2400 steps):
// 1 s steps at 0.5 m/s, one range every 2 s (0.5 Hz round robin), the same gyro noise per
// sqrt(s) (0.0067 rad per step) and 0.005 rad/s of bias.
SimConfig slowUwbWorld(uint64_t seed, int num_steps);

// And by a fast one (utilities/seed-sweep's fast-uwb, 15000 steps): 50 Hz odometry at 1 m/s, 10
// ranges a second round robin, the same gyro noise per sqrt(s) (0.00095 rad per step) and
// 0.005 rad/s of bias.
SimConfig fastUwbWorld(uint64_t seed, int num_steps);

// A loop driven one way round (utilities/seed-sweep's drift-racetrack, 6500 steps = 1.3 km):
// 40 m straights joined by half circles of 12 m at 1 m/s in 0.2 s steps, 4 beacons ranged 1.4
// times a second round robin (the spectral paper's Plaza 2: a loop, 1.3 km, 1816 ranges to 4
// beacons over 4091 poses), 0.3 m range noise, 2 % odometry, 0.003 rad heading noise per step and
// 0.005 rad/s of gyro bias.
SimConfig racetrackWorld(uint64_t seed, int num_steps);

// The heavy-NLOS world of logs/synthetic/nlos30-lawnmower (there seed 107, 3000 steps): a
// 40 x 30 m lawn mower with 5 m lanes at 1 m/s in 0.2 s steps, 6 beacons at 2 Hz round robin,
// 0.3 m range noise, 30 % of the ranges 2-40 m too long, 2 % odometry and 0.003 rad heading noise.
SimConfig nlos30LawnMowerWorld(uint64_t seed, int num_steps);

// utilities/seed-sweep's nlos50: the same with half the ranges NLOS.
SimConfig nlos50LawnMowerWorld(uint64_t seed, int num_steps);

// utilities/seed-sweep's long-lanes (1500 steps): the same sensors on a 60 x 40 m lawn mower with
// clean ranges and 0.005 rad/s of gyro bias, so no landmark can be placed before the first 60 m
// lane ends (its mirror images fit alike).
SimConfig longLanesWorld(uint64_t seed, int num_steps);

}  // namespace sim
}  // namespace roam
