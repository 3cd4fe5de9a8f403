#include "sim.hpp"

#include "roam/estimation/motion_model.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace roam {
namespace sim {
namespace {

// True (distance, heading change) per step for each path kind.
struct Control {
  double distance_m;
  double dheading_rad;
};

std::vector<Control> lawnMowerControls(const SimConfig& c) {
  // Straight lane of area_width_m, then a half-circle turn of diameter lane_spacing_m,
  // alternating left and right, sweeping back and forth over area_height_m.
  std::vector<Control> controls;
  const double step_m = c.speed_mps * c.dt_s;
  const double radius_m = 0.5 * c.lane_spacing_m;
  const int lanes = std::max(1, static_cast<int>(std::floor(c.area_height_m / c.lane_spacing_m)) + 1);
  int lane = 0;
  bool sweeping_up = true;
  while (static_cast<int>(controls.size()) < c.num_steps) {
    const int straight_steps = std::max(1, static_cast<int>(std::lround(c.area_width_m / step_m)));
    for (int i = 0; i < straight_steps; ++i) controls.push_back({step_m, 0.0});
    // Left turns when sweeping up on even lanes, right on odd; reverse when sweeping down.
    const bool left = ((lane % 2) == 0) == sweeping_up;
    const int turn_steps = std::max(2, static_cast<int>(std::lround(M_PI * radius_m / step_m)));
    const double dheading = (left ? 1.0 : -1.0) * M_PI / turn_steps;
    const double arc_step_m = M_PI * radius_m / turn_steps;
    for (int i = 0; i < turn_steps; ++i) controls.push_back({arc_step_m, dheading});
    if (sweeping_up) {
      if (++lane >= lanes - 1) sweeping_up = false;
    } else {
      if (--lane <= 0) sweeping_up = true;
    }
  }
  controls.resize(c.num_steps);
  return controls;
}

std::vector<Control> loopControls(const SimConfig& c) {
  const double step_m = c.speed_mps * c.dt_s;
  return std::vector<Control>(c.num_steps, Control{step_m, step_m / c.loop_radius_m});
}

std::vector<Control> racetrackControls(const SimConfig& c) {
  // A straight of area_width_m, then a half circle to the left of radius loop_radius_m, repeated:
  // one way round a running track, the loop a robot drives round a plaza.
  const double step_m = c.speed_mps * c.dt_s;
  const int straight_steps = std::max(1, static_cast<int>(std::lround(c.area_width_m / step_m)));
  const int turn_steps = std::max(2, static_cast<int>(std::lround(M_PI * c.loop_radius_m / step_m)));
  const double arc_m = M_PI * c.loop_radius_m / turn_steps;
  std::vector<Control> controls;
  while (static_cast<int>(controls.size()) < c.num_steps) {
    controls.insert(controls.end(), straight_steps, Control{step_m, 0.0});
    controls.insert(controls.end(), turn_steps, Control{arc_m, M_PI / turn_steps});
  }
  controls.resize(c.num_steps);
  return controls;
}

std::vector<Control> figureEightControls(const SimConfig& c) {
  // One full circle to the left, then one to the right, of radius loop_radius_m, repeated:
  // the two lobes meet at the start.
  const double step_m = c.speed_mps * c.dt_s;
  const int lobe_steps = std::max(4, static_cast<int>(std::lround(2.0 * M_PI * c.loop_radius_m / step_m)));
  const double turn = 2.0 * M_PI / lobe_steps;
  const double arc_m = 2.0 * M_PI * c.loop_radius_m / lobe_steps;
  std::vector<Control> controls;
  for (int k = 0; k < c.num_steps; ++k) {
    const bool left = (k / lobe_steps) % 2 == 0;
    controls.push_back({arc_m, left ? turn : -turn});
  }
  return controls;
}

std::vector<Control> randomWalkControls(const SimConfig& c, std::mt19937_64& rng,
                                        const Pose& start) {
  // Smooth turn rate (Ornstein-Uhlenbeck, 5 s time constant) plus a pull back to the box.
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<Control> controls;
  const double step_m = c.speed_mps * c.dt_s;
  const double tau_s = 5.0;
  double turn_rate = 0.0;
  double x = start.x_m, y = start.y_m, heading = start.heading_rad;
  const double cx = start.x_m + 0.5 * c.area_width_m, cy = start.y_m + 0.5 * c.area_height_m;
  for (int k = 0; k < c.num_steps; ++k) {
    turn_rate += -turn_rate * c.dt_s / tau_s +
                 c.turn_rate_sigma_radps * std::sqrt(2.0 * c.dt_s / tau_s) * normal(rng);
    double rate = turn_rate;
    const bool outside = std::abs(x - cx) > 0.5 * c.area_width_m || std::abs(y - cy) > 0.5 * c.area_height_m;
    if (outside) {
      const double to_centre = std::atan2(cy - y, cx - x);
      rate += 0.5 * wrapAngle(to_centre - heading);
    }
    const double dheading = rate * c.dt_s;
    controls.push_back({step_m, dheading});
    x += step_m * std::cos(heading);
    y += step_m * std::sin(heading);
    heading += dheading;
  }
  return controls;
}

}  // namespace

PathKind parsePathKind(const std::string& name) {
  if (name == "random_walk") return PathKind::kRandomWalk;
  if (name == "lawn_mower") return PathKind::kLawnMower;
  if (name == "loop") return PathKind::kLoop;
  if (name == "figure8") return PathKind::kFigureEight;
  if (name == "racetrack") return PathKind::kRacetrack;
  throw std::invalid_argument("unknown path '" + name +
                              "' (expected random_walk | lawn_mower | loop | figure8 | racetrack)");
}

RangeGap parseRangeGap(const std::string& text) {
  const std::string usage = "range gap '" + text + "': expected START_S:DURATION_S, e.g. 120:30";
  const size_t colon = text.find(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size()) throw std::invalid_argument(usage);
  RangeGap gap;
  try {
    size_t used = 0;
    gap.start_s = std::stod(text.substr(0, colon), &used);
    if (used != colon) throw std::invalid_argument(usage);
    const std::string duration = text.substr(colon + 1);
    gap.duration_s = std::stod(duration, &used);
    if (used != duration.size()) throw std::invalid_argument(usage);
  } catch (const std::logic_error&) {
    throw std::invalid_argument(usage);
  }
  if (!(gap.start_s >= 0.0) || !std::isfinite(gap.start_s))
    throw std::invalid_argument(usage + " (start must be a finite number >= 0)");
  if (!(gap.duration_s > 0.0) || !std::isfinite(gap.duration_s))
    throw std::invalid_argument(usage + " (duration must be a finite number > 0)");
  return gap;
}

SimConfig auvLikeWorld(uint64_t seed, int num_steps) {
  SimConfig c;
  c.seed = seed;
  c.num_steps = num_steps;
  c.dt_s = 3.0;
  c.speed_mps = 1.5;
  c.path = PathKind::kLawnMower;
  c.area_width_m = 300.0;
  c.area_height_m = 200.0;
  c.lane_spacing_m = 50.0;
  c.num_beacons = 4;
  c.beacon_margin_m = 200.0;
  c.schedule = RangeSchedule::kRoundRobin;
  c.range_rate_hz = 0.3;
  c.range_sigma_m = 2.0;
  c.range_sigma_reported_m = 0.75;
  c.outlier_fraction = 0.45;
  c.outlier_min_m = -150.0;
  c.outlier_max_m = 100.0;
  c.odo_distance_sigma_rel = 0.15;
  c.odo_lateral_sigma_rel = 0.15;
  c.odo_heading_sigma_rad = 0.005;
  c.odo_distance_scale = 0.97;
  return c;
}

SimConfig goatsLikeWorld(uint64_t seed, int num_steps) {
  SimConfig c;
  c.seed = seed;
  c.num_steps = num_steps;
  c.dt_s = 7.0;
  c.speed_mps = 0.7;
  c.path = PathKind::kLawnMower;
  c.area_width_m = 250.0;
  c.area_height_m = 150.0;
  c.lane_spacing_m = 40.0;
  c.num_beacons = 4;
  c.beacon_margin_m = 250.0;
  c.schedule = RangeSchedule::kEveryStepAllBeacons;
  c.range_dropout = 0.3;
  c.range_sigma_m = 2.0;
  c.range_sigma_reported_m = 0.75;
  c.outlier_fraction = 0.5;
  c.outlier_min_m = -200.0;
  c.outlier_max_m = 20.0;
  c.beacon_offset_min_m = 1.0;
  c.beacon_offset_max_m = 2.0;
  c.odo_distance_sigma_rel = 0.2;
  c.odo_lateral_sigma_rel = 0.2;
  c.odo_heading_sigma_rad = 0.001;
  c.odo_distance_scale = 0.97;
  c.odo_sigma_reported_m = 0.02;
  c.odo_heading_sigma_reported_rad = 0.002;
  return c;
}

SimConfig gyroDriftFigure8World(uint64_t seed, int num_steps) {
  SimConfig c;
  c.seed = seed;
  c.num_steps = num_steps;
  c.dt_s = 0.2;
  c.speed_mps = 1.0;
  c.path = PathKind::kFigureEight;
  c.loop_radius_m = 12.0;
  c.num_beacons = 6;
  c.schedule = RangeSchedule::kRoundRobin;
  c.range_rate_hz = 2.0;
  c.range_sigma_m = 0.3;
  c.odo_distance_sigma_rel = 0.02;
  c.odo_heading_sigma_rad = 0.003;
  c.odo_heading_bias_radps = 0.01;
  return c;
}

SimConfig slowUwbWorld(uint64_t seed, int num_steps) {
  SimConfig c = gyroDriftFigure8World(seed, num_steps);
  c.dt_s = 1.0;
  c.speed_mps = 0.5;
  c.range_rate_hz = 0.5;
  c.odo_heading_sigma_rad = 0.0067;
  c.odo_heading_bias_radps = 0.005;
  return c;
}

SimConfig fastUwbWorld(uint64_t seed, int num_steps) {
  SimConfig c = gyroDriftFigure8World(seed, num_steps);
  c.dt_s = 0.02;
  c.range_rate_hz = 10.0;
  c.odo_heading_sigma_rad = 0.00095;
  c.odo_heading_bias_radps = 0.005;
  return c;
}

SimConfig racetrackWorld(uint64_t seed, int num_steps) {
  SimConfig c = gyroDriftFigure8World(seed, num_steps);
  c.path = PathKind::kRacetrack;
  c.area_width_m = 40.0;
  c.loop_radius_m = 12.0;
  c.num_beacons = 4;
  c.range_rate_hz = 1.4;
  c.odo_heading_bias_radps = 0.005;
  return c;
}

SimConfig nlos30LawnMowerWorld(uint64_t seed, int num_steps) {
  SimConfig c;
  c.seed = seed;
  c.num_steps = num_steps;
  c.dt_s = 0.2;
  c.speed_mps = 1.0;
  c.path = PathKind::kLawnMower;
  c.area_width_m = 40.0;
  c.area_height_m = 30.0;
  c.lane_spacing_m = 5.0;
  c.num_beacons = 6;
  c.schedule = RangeSchedule::kRoundRobin;
  c.range_rate_hz = 2.0;
  c.range_sigma_m = 0.3;
  c.odo_distance_sigma_rel = 0.02;
  c.odo_heading_sigma_rad = 0.003;
  c.outlier_fraction = 0.3;
  c.outlier_min_m = 2.0;
  c.outlier_max_m = 40.0;
  return c;
}

SimConfig nlos50LawnMowerWorld(uint64_t seed, int num_steps) {
  SimConfig c = nlos30LawnMowerWorld(seed, num_steps);
  c.outlier_fraction = 0.5;
  return c;
}

SimConfig longLanesWorld(uint64_t seed, int num_steps) {
  SimConfig c = nlos30LawnMowerWorld(seed, num_steps);
  c.area_width_m = 60.0;
  c.area_height_m = 40.0;
  c.outlier_fraction = 0.0;
  c.odo_heading_bias_radps = 0.005;
  return c;
}

SimRun simulate(const SimConfig& c) {
  if (c.num_steps < 1) throw std::invalid_argument("num_steps must be >= 1");
  if (c.dt_s <= 0.0) throw std::invalid_argument("dt_s must be > 0");
  if (!(c.odo_sigma_reported_m >= 0.0) || !(c.odo_heading_sigma_reported_rad >= 0.0) ||
      ((c.odo_sigma_reported_m > 0.0) != (c.odo_heading_sigma_reported_rad > 0.0)))
    throw std::invalid_argument(
        "odo_sigma_reported_m and odo_heading_sigma_reported_rad must both be > 0 (a stated covariance) or both 0 "
        "(none)");
  if (!(c.hold_s >= 0.0) || !std::isfinite(c.hold_s)) throw std::invalid_argument("hold_s must be a finite number >= 0");
  if (!(c.odo_heading_bias_walk_radps_per_sqrt_s >= 0.0) || !std::isfinite(c.odo_heading_bias_walk_radps_per_sqrt_s))
    throw std::invalid_argument("the gyro bias walk must be a finite number >= 0 (rad/s per sqrt(s))");
  for (const RangeGap& gap : c.range_gaps) {
    if (!(gap.start_s >= 0.0) || !std::isfinite(gap.start_s) || !(gap.duration_s > 0.0) ||
        !std::isfinite(gap.duration_s))
      throw std::invalid_argument("range gap: expected start_s >= 0 and duration_s > 0");
  }
  std::mt19937_64 rng(c.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);

  SimRun run;
  run.start = c.start;
  run.start.utime = c.start_utime;

  std::vector<Control> controls;
  switch (c.path) {
    case PathKind::kLawnMower: controls = lawnMowerControls(c); break;
    case PathKind::kLoop: controls = loopControls(c); break;
    case PathKind::kFigureEight: controls = figureEightControls(c); break;
    case PathKind::kRacetrack: controls = racetrackControls(c); break;
    case PathKind::kRandomWalk: controls = randomWalkControls(c, rng, run.start); break;
  }
  // Standing start: zero steps first, the path after them (num_steps in all).
  const int hold_steps = std::min(c.num_steps, static_cast<int>(std::lround(c.hold_s / c.dt_s)));
  if (hold_steps > 0) {
    controls.insert(controls.begin(), hold_steps, Control{0.0, 0.0});
    controls.resize(c.num_steps);
  }

  // Ground truth and odometry. The gyro bias walks on its own stream (seeded from the seed) and
  // its own distribution (a normal_distribution keeps the second draw of each pair), so a run
  // with a walk differs from the same seed's without one only in the reported turns.
  std::mt19937_64 bias_rng(c.seed ^ 0x9e3779b97f4a7c15ULL);
  std::normal_distribution<double> bias_normal(0.0, 1.0);
  double bias_radps = c.odo_heading_bias_radps;
  const int64_t dt_us = static_cast<int64_t>(std::llround(c.dt_s * 1e6));
  Pose pose = run.start;
  run.ground_truth.push_back(pose);
  for (int k = 0; k < c.num_steps; ++k) {
    const Control& u = controls[k];
    Pose next = pose;
    next.utime = pose.utime + dt_us;
    const Eigen::Vector3d moved = estimation::step(Eigen::Vector3d(pose.x_m, pose.y_m, pose.heading_rad),
                                                   Eigen::Vector3d(u.distance_m, 0.0, u.dheading_rad));
    next.x_m = moved[0];
    next.y_m = moved[1];
    next.heading_rad = moved[2];
    run.ground_truth.push_back(next);
    Odometry odo;
    odo.utime = next.utime;
    const double sigma_d = c.odo_distance_sigma_rel * u.distance_m + c.odo_distance_sigma_m;
    odo.forward_m = std::max(0.0, c.odo_distance_scale * u.distance_m + sigma_d * normal(rng));
    if (c.odo_lateral_sigma_rel > 0.0) odo.lateral_m = c.odo_lateral_sigma_rel * u.distance_m * normal(rng);
    const double heading_sigma_rad = k < hold_steps && c.hold_heading_sigma_rad >= 0.0 ? c.hold_heading_sigma_rad : c.odo_heading_sigma_rad;
    odo.delta_heading_rad = u.dheading_rad + bias_radps * c.dt_s + heading_sigma_rad * normal(rng);
    if (c.odo_sigma_reported_m > 0.0 || c.odo_heading_sigma_reported_rad > 0.0) {
      odo.covariance = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
      odo.covariance[0] = odo.covariance[4] = c.odo_sigma_reported_m * c.odo_sigma_reported_m;
      odo.covariance[8] = c.odo_heading_sigma_reported_rad * c.odo_heading_sigma_reported_rad;
    }
    if (c.odo_heading_bias_walk_radps_per_sqrt_s > 0.0)
      bias_radps += c.odo_heading_bias_walk_radps_per_sqrt_s * std::sqrt(c.dt_s) * bias_normal(bias_rng);
    run.odometry.push_back(odo);
    pose = next;
  }

  // Beacons: given, or uniform around the swept area.
  if (!c.beacons.empty()) {
    run.beacons = c.beacons;
  } else {
    double min_x = 1e300, max_x = -1e300, min_y = 1e300, max_y = -1e300;
    for (const Pose& p : run.ground_truth) {
      min_x = std::min(min_x, p.x_m);
      max_x = std::max(max_x, p.x_m);
      min_y = std::min(min_y, p.y_m);
      max_y = std::max(max_y, p.y_m);
    }
    for (int i = 0; i < c.num_beacons; ++i) {
      Beacon b;
      b.id = i;
      b.x_m = min_x - c.beacon_margin_m + uniform(rng) * (max_x - min_x + 2 * c.beacon_margin_m);
      b.y_m = min_y - c.beacon_margin_m + uniform(rng) * (max_y - min_y + 2 * c.beacon_margin_m);
      run.beacons.push_back(b);
    }
  }

  // Ranges.
  auto measure = [&](const Pose& at, const Beacon& beacon) {
    const double dx = beacon.x_m - at.x_m, dy = beacon.y_m - at.y_m;
    const double true_range = std::hypot(dx, dy);
    const bool wide = c.mixture_weight1 > 0.0 && uniform(rng) < c.mixture_weight1;
    const double sigma = wide ? c.range_sigma1_m : c.range_sigma_m;
    Range r;
    r.utime = at.utime;
    r.beacon_id = beacon.id;
    r.range_m = c.range_scale * true_range + c.range_offset_m + sigma * normal(rng);
    if (c.outlier_fraction > 0.0 && !(c.outlier_episode_s > 0.0) && uniform(rng) < c.outlier_fraction) {
      r.range_m = true_range + c.outlier_min_m + uniform(rng) * (c.outlier_max_m - c.outlier_min_m);
    }
    r.range_m = std::max(r.range_m, 1e-3);
    r.sigma_m = c.range_sigma_reported_m;
    if (c.bearing) {
      r.has_bearing = true;
      r.bearing_rad = wrapAngle(std::atan2(dy, dx) - at.heading_rad + c.bearing_sigma_rad * normal(rng));
    }
    return r;
  };
  if (c.schedule == RangeSchedule::kEveryStepAllBeacons) {
    for (size_t k = 0; k < run.ground_truth.size(); ++k) {
      for (const Beacon& beacon : run.beacons) {
        if (c.range_dropout > 0.0 && uniform(rng) < c.range_dropout) continue;
        run.ranges.push_back(measure(run.ground_truth[k], beacon));
      }
    }
  } else {
    const double period_s = 1.0 / c.range_rate_hz;
    double next_time_s = period_s;
    size_t next_beacon = 0;
    for (size_t k = 1; k < run.ground_truth.size(); ++k) {
      const double t_s = static_cast<double>(k) * c.dt_s;
      while (next_time_s <= t_s + 1e-9) {
        const Beacon& beacon = run.beacons[next_beacon];
        next_beacon = (next_beacon + 1) % run.beacons.size();
        next_time_s += period_s;
        if (c.range_dropout > 0.0 && uniform(rng) < c.range_dropout) continue;
        run.ranges.push_back(measure(run.ground_truth[k], beacon));
      }
    }
  }
  // NLOS stretches, per-beacon offsets, then gaps: every random draw above is made as without them.
  const double duration_s = static_cast<double>(run.ground_truth.back().utime - run.start.utime) * 1e-6;
  const std::map<int, std::vector<OutlierEpisode>> episodes = outlierEpisodes(c, run.beacons, duration_s);
  for (Range& r : run.ranges) {
    const auto found = episodes.find(r.beacon_id);
    if (found == episodes.end()) continue;
    const double t_s = static_cast<double>(r.utime - run.start.utime) * 1e-6;
    for (const OutlierEpisode& e : found->second)
      if (t_s >= e.start_s && t_s < e.end_s) r.range_m = std::max(r.range_m + e.excess_m, 1e-3);
  }
  const std::map<int, double> offsets_m = beaconOffsets(c, run.beacons);
  if (!offsets_m.empty())
    for (Range& r : run.ranges) r.range_m = std::max(r.range_m + offsets_m.at(r.beacon_id), 1e-3);
  const std::map<int, std::array<double, 2>> survey_m = beaconSurveyErrors(c, run.beacons);
  for (Beacon& b : run.beacons) {
    const auto found = survey_m.find(b.id);
    if (found == survey_m.end()) continue;
    b.x_m += found->second[0];
    b.y_m += found->second[1];
  }
  if (!c.range_gaps.empty()) {
    auto in_gap = [&](const Range& r) {
      const double t_s = static_cast<double>(r.utime - run.start.utime) * 1e-6;
      for (const RangeGap& gap : c.range_gaps)
        if (t_s >= gap.start_s && t_s < gap.start_s + gap.duration_s) return true;
      return false;
    };
    run.ranges.erase(std::remove_if(run.ranges.begin(), run.ranges.end(), in_gap), run.ranges.end());
  }
  return run;
}

std::map<int, double> beaconOffsets(const SimConfig& c, const Map& beacons) {
  if (!(c.beacon_offset_max_m > 0.0)) return {};
  // Its own stream (as the gyro bias walk's): seeded apart from the run's, so the offsets do not
  // repeat the run's first noise draws.
  return beaconOffsets(c.beacon_offset_seed != 0 ? c.beacon_offset_seed : c.seed ^ 0xbf58476d1ce4e5b9ULL,
                       c.beacon_offset_min_m, c.beacon_offset_max_m, beacons);
}

std::map<int, std::array<double, 2>> beaconSurveyErrors(const SimConfig& c, const Map& beacons) {
  std::map<int, std::array<double, 2>> errors_m;
  if (!(c.beacon_survey_sigma_m > 0.0)) return errors_m;
  std::mt19937_64 rng(c.seed ^ 0x94d049bb133111ebULL);
  std::normal_distribution<double> normal(0.0, c.beacon_survey_sigma_m);
  for (const Beacon& beacon : beacons) {
    const double dx = normal(rng);
    errors_m[beacon.id] = {dx, normal(rng)};
  }
  return errors_m;
}

std::map<int, std::vector<OutlierEpisode>> outlierEpisodes(const SimConfig& c, const Map& beacons,
                                                           double duration_s) {
  std::map<int, std::vector<OutlierEpisode>> episodes;
  if (!(c.outlier_episode_s > 0.0) || !(c.outlier_fraction > 0.0)) return episodes;
  // Its own stream, as the offsets' and the survey's: a two-state Markov chain per beacon in
  // continuous time, started from its stationary law (NLOS with probability f).
  std::mt19937_64 rng(c.seed ^ 0xd6e8feb86659fd93ULL);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double f = c.outlier_fraction;
  const double nlos_mean_s = c.outlier_episode_s;
  const double los_mean_s = f < 1.0 ? c.outlier_episode_s * (1.0 - f) / f : 0.0;
  for (const Beacon& beacon : beacons) {
    std::vector<OutlierEpisode>& mine = episodes[beacon.id];
    bool nlos = uniform(rng) < f;
    double t_s = 0.0;
    while (t_s <= duration_s) {
      const double mean_s = nlos ? nlos_mean_s : los_mean_s;
      const double length_s = mean_s > 0.0 ? -mean_s * std::log(1.0 - uniform(rng)) : 0.0;
      if (nlos) {
        const double excess_m = c.outlier_min_m + uniform(rng) * (c.outlier_max_m - c.outlier_min_m);
        mine.push_back({t_s, f < 1.0 ? t_s + length_s : duration_s + 1.0, excess_m});
        if (!(f < 1.0)) break;
      }
      t_s += length_s;
      nlos = !nlos;
    }
  }
  return episodes;
}

std::map<int, double> beaconOffsets(uint64_t stream_seed, double min_m, double max_m, const Map& beacons) {
  std::map<int, double> offsets_m;
  std::mt19937_64 rng(stream_seed);
  std::uniform_real_distribution<double> magnitude_m(min_m, max_m);
  for (const Beacon& beacon : beacons) {
    const double m = magnitude_m(rng);
    offsets_m[beacon.id] = (rng() & 1u) ? m : -m;
  }
  return offsets_m;
}

}  // namespace sim
}  // namespace roam
