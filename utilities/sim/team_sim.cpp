// roam::sim::simulateTeam: N simulate() runs and the ranges between them (see team_sim.hpp).
#include "team_sim.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <utility>

namespace roam {
namespace sim {
namespace {

// SplitMix64's finaliser: well-spread seeds from the team's seed and a robot's index.
uint64_t mix(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

uint64_t robotSeed(uint64_t team_seed, int robot) { return mix(team_seed ^ mix(static_cast<uint64_t>(robot) + 1)); }

// Robot i's config: its own seed and start pose; the team's beacons (none yet: `beacons` empty).
SimConfig memberConfig(const TeamSimConfig& team, int robot, const Map& beacons) {
  SimConfig c = team.robot;
  c.seed = robotSeed(team.robot.seed, robot);
  const double heading_rad = team.robot.start.heading_rad;
  c.start.x_m += robot * team.robot_spacing_m * -std::sin(heading_rad);
  c.start.y_m += robot * team.robot_spacing_m * std::cos(heading_rad);
  c.start.heading_rad = wrapAngle(heading_rad + 2.0 * M_PI * robot / team.num_robots);
  c.beacons = beacons;
  c.num_beacons = 0;
  if (beacons.empty()) c.schedule = RangeSchedule::kEveryStepAllBeacons;  // no beacon, no range
  // One offset per beacon for the whole team; the survey error is drawn once, by the team.
  c.beacon_offset_seed = team.robot.beacon_offset_seed != 0 ? team.robot.beacon_offset_seed
                                                            : team.robot.seed ^ 0xbf58476d1ce4e5b9ULL;
  c.beacon_survey_sigma_m = 0.0;
  return c;
}

// num_beacons uniform in the box around every robot's path, widened by the margin.
Map teamBeacons(const SimConfig& c, const std::vector<Path>& paths) {
  double min_x = 1e300, max_x = -1e300, min_y = 1e300, max_y = -1e300;
  for (const Path& path : paths) {
    for (const Pose& p : path) {
      min_x = std::min(min_x, p.x_m);
      max_x = std::max(max_x, p.x_m);
      min_y = std::min(min_y, p.y_m);
      max_y = std::max(max_y, p.y_m);
    }
  }
  std::mt19937_64 rng(c.seed ^ 0x5851f42d4c957f2dULL);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Map beacons;
  for (int i = 0; i < c.num_beacons; ++i) {
    Beacon b;
    b.id = i;
    b.x_m = min_x - c.beacon_margin_m + uniform(rng) * (max_x - min_x + 2 * c.beacon_margin_m);
    b.y_m = min_y - c.beacon_margin_m + uniform(rng) * (max_y - min_y + 2 * c.beacon_margin_m);
    beacons.push_back(b);
  }
  return beacons;
}

// The ranges between robots, round robin over the pairs (see team_sim.hpp).
std::vector<Range> robotRanges(const TeamSimConfig& team, const std::vector<Dataset>& members) {
  const SimConfig& c = team.robot;
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < team.num_robots; ++i)
    for (int j = i + 1; j < team.num_robots; ++j) pairs.emplace_back(i, j);
  std::vector<Range> ranges;
  if (pairs.empty()) return ranges;
  const Path& clock = members[0].ground_truth;  // every robot's poses are at these utimes
  const int64_t start_utime = clock.front().utime;
  const double duration_s = static_cast<double>(clock.back().utime - start_utime) * 1e-6;
  // NLOS stretches per pair, drawn as outlierEpisodes draws them per beacon (id = the pair's index).
  Map pair_ids;
  for (size_t p = 0; p < pairs.size(); ++p) pair_ids.push_back(Beacon{static_cast<int>(p), 0.0, 0.0, {}});
  SimConfig episode_config = c;
  episode_config.seed = c.seed ^ 0x2545f4914f6cdd1dULL;
  const auto episodes = outlierEpisodes(episode_config, pair_ids, duration_s);

  std::mt19937_64 rng(c.seed ^ 0x6a09e667f3bcc909ULL);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double period_s = 1.0 / (team.robot_range_rate_hz * static_cast<double>(pairs.size()));
  double next_time_s = period_s;
  size_t next_pair = 0;
  long round = 0;
  for (size_t k = 1; k < clock.size(); ++k) {
    const double t_s = static_cast<double>(clock[k].utime - start_utime) * 1e-6;
    while (next_time_s <= t_s + 1e-9) {
      const size_t p = next_pair;
      const auto [i, j] = pairs[p];
      const bool i_measures = round % 2 == 0;
      if (++next_pair == pairs.size()) {
        next_pair = 0;
        ++round;
      }
      next_time_s += period_s;
      if (c.range_dropout > 0.0 && uniform(rng) < c.range_dropout) continue;
      const Pose& a = members[static_cast<size_t>(i)].ground_truth[k];
      const Pose& b = members[static_cast<size_t>(j)].ground_truth[k];
      const double true_range = std::hypot(a.x_m - b.x_m, a.y_m - b.y_m);
      const bool wide = c.mixture_weight1 > 0.0 && uniform(rng) < c.mixture_weight1;
      const double sigma = wide ? c.range_sigma1_m : c.range_sigma_m;
      Range r;
      r.utime = clock[k].utime;
      r.robot = i_measures ? i : j;
      r.other_robot = i_measures ? j : i;
      r.range_m = c.range_scale * true_range + c.range_offset_m + sigma * normal(rng);
      if (c.outlier_fraction > 0.0 && !(c.outlier_episode_s > 0.0) && uniform(rng) < c.outlier_fraction)
        r.range_m = true_range + c.outlier_min_m + uniform(rng) * (c.outlier_max_m - c.outlier_min_m);
      const auto stretches = episodes.find(static_cast<int>(p));
      if (stretches != episodes.end()) {
        for (const OutlierEpisode& e : stretches->second)
          if (t_s >= e.start_s && t_s < e.end_s) r.range_m += e.excess_m;
      }
      r.range_m = std::max(r.range_m, 1e-3);
      r.sigma_m = c.range_sigma_reported_m;
      ranges.push_back(r);
    }
  }
  return ranges;
}

}  // namespace

TeamDataset simulateTeam(const TeamSimConfig& team) {
  if (team.num_robots < 1 || team.num_robots > 26) throw std::invalid_argument("num_robots must be 1 to 26 (A to Z)");
  if (!(team.robot_spacing_m > 0.0) || !std::isfinite(team.robot_spacing_m))
    throw std::invalid_argument("robot_spacing_m must be a finite number > 0 (robots must not start together)");
  if (!(team.robot_range_rate_hz > 0.0) || !std::isfinite(team.robot_range_rate_hz))
    throw std::invalid_argument("robot_range_rate_hz must be a finite number > 0");
  if (team.robot.num_beacons < 0) throw std::invalid_argument("num_beacons must be >= 0");
  // The beacons: the config's, or drawn around every robot's path (their paths do not depend on
  // the beacons, so a first run without beacons gives them).
  Map beacons = team.robot.beacons;
  if (beacons.empty() && team.robot.num_beacons > 0) {
    std::vector<Path> paths;
    for (int i = 0; i < team.num_robots; ++i) paths.push_back(simulate(memberConfig(team, i, {})).ground_truth);
    beacons = teamBeacons(team.robot, paths);
  }
  TeamDataset result;
  for (int i = 0; i < team.num_robots; ++i) {
    Dataset member = simulate(memberConfig(team, i, beacons));
    member.beacons.clear();
    member.start.robot = i;
    for (Pose& p : member.ground_truth) p.robot = i;
    for (Odometry& o : member.odometry) o.robot = i;
    for (Range& r : member.ranges) r.robot = i;
    result.robots.push_back(std::string(1, static_cast<char>('A' + i)));
    result.members.push_back(std::move(member));
  }
  result.robot_ranges = robotRanges(team, result.members);
  const auto survey_m = beaconSurveyErrors(team.robot, beacons);
  for (Beacon& b : beacons) {
    const auto found = survey_m.find(b.id);
    if (found == survey_m.end()) continue;
    b.x_m += found->second[0];
    b.y_m += found->second[1];
  }
  result.beacons = beacons;
  return result;
}

}  // namespace sim
}  // namespace roam
