// roam-sim -o LOG [options]: a seeded synthetic run (roam::sim::simulate, utilities/sim/sim.hpp)
// written as the same kind of log roam-import writes. The same options give the same log.
// --robots N (N >= 2): a team run (roam::sim::simulateTeam, utilities/sim/team_sim.hpp) written
// as a team log (writeTeamLog).
#include <boost/program_options.hpp>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "csv_dataset.hpp"
#include "dataset_log.hpp"
#include "sim.hpp"
#include "team_sim.hpp"

namespace po = boost::program_options;

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::runtime_error(what);
}

}  // namespace

int main(int argc, char** argv) {
  roam::sim::SimConfig c;
  std::string output, path_kind = "lawn_mower", schedule = "all", beacons_csv;
  std::vector<std::string> range_gaps;
  double start_x = 0, start_y = 0, start_heading = 0, range_latency_s = 0;
  long long start_utime = c.start_utime;
  roam::sim::TeamSimConfig team;
  po::options_description visible("roam-sim -o LOG [options]: a seeded synthetic range-only SLAM run");
  // clang-format off
  visible.add_options()
      ("help,h", "this help")
      ("output,o", po::value(&output), "the LCM log to write (required)")
      ("seed", po::value(&c.seed)->default_value(c.seed), "random seed")
      ("robots", po::value(&team.num_robots)->default_value(1),
       "N >= 2: a team run (robots A, B, ... each on the path from its own start, own noise; ranges "
       "between robots; a team log with ODOMETRY_A, ROBOT_RANGE_A, ...); 1: one robot")
      ("robot-range-rate-hz", po::value(&team.robot_range_rate_hz)->default_value(team.robot_range_rate_hz),
       "team: ranges per second per pair of robots (round robin over the pairs; noise and outliers as "
       "for beacons)")
      ("robot-spacing", po::value(&team.robot_spacing_m)->default_value(team.robot_spacing_m),
       "team: metres between neighbouring starts (to the left of --start-heading; robot i's heading "
       "turned by 2 pi i / N)")
      ("steps", po::value(&c.num_steps)->default_value(c.num_steps), "odometry steps (poses = steps + 1)")
      ("dt", po::value(&c.dt_s)->default_value(c.dt_s), "seconds per step")
      ("speed", po::value(&c.speed_mps)->default_value(c.speed_mps), "m/s")
      ("start-utime", po::value(&start_utime)->default_value(start_utime), "utime of the start pose")
      ("start-x", po::value(&start_x)->default_value(0.0), "start pose x (m)")
      ("start-y", po::value(&start_y)->default_value(0.0), "start pose y (m)")
      ("start-heading", po::value(&start_heading)->default_value(0.0), "start pose heading (rad)")
      ("hold-s", po::value(&c.hold_s)->default_value(c.hold_s),
       "stand still this many seconds first (odometry keeps its heading noise and gyro bias, "
       "ranges are taken), then drive the path; --steps counts both")
      ("hold-heading-sigma", po::value(&c.hold_heading_sigma_rad)->default_value(c.hold_heading_sigma_rad),
       "heading noise per step while standing (rad; < 0: --odo-heading-sigma); a gyro at rest "
       "drifts by its bias and angle random walk only")
      ("path", po::value(&path_kind)->default_value(path_kind), "random_walk | lawn_mower | loop | figure8 | racetrack (straights of --area-width joined by half circles of --loop-radius, one way round)")
      ("area-width", po::value(&c.area_width_m)->default_value(c.area_width_m), "lane length / box width / racetrack straight (m)")
      ("area-height", po::value(&c.area_height_m)->default_value(c.area_height_m), "sweep / box height (m)")
      ("lane-spacing", po::value(&c.lane_spacing_m)->default_value(c.lane_spacing_m), "lawn-mower lane spacing (m)")
      ("loop-radius", po::value(&c.loop_radius_m)->default_value(c.loop_radius_m), "loop radius; figure-8 lobes; racetrack turns (m)")
      ("turn-rate-sigma", po::value(&c.turn_rate_sigma_radps)->default_value(c.turn_rate_sigma_radps),
       "random walk: turn-rate std (rad/s)")
      ("beacons", po::value(&c.num_beacons)->default_value(c.num_beacons), "number of random beacons (a team: 0 allowed)")
      ("beacons-csv", po::value(&beacons_csv), "FILE: beacons as beacon_id,x_m,y_m instead of random ones")
      ("beacon-margin", po::value(&c.beacon_margin_m)->default_value(c.beacon_margin_m), "margin around the area (m)")
      ("odo-distance-sigma-rel", po::value(&c.odo_distance_sigma_rel)->default_value(c.odo_distance_sigma_rel),
       "odometry distance noise, relative")
      ("odo-distance-sigma", po::value(&c.odo_distance_sigma_m)->default_value(c.odo_distance_sigma_m),
       "odometry distance noise (m per step)")
      ("odo-heading-sigma", po::value(&c.odo_heading_sigma_rad)->default_value(c.odo_heading_sigma_rad),
       "odometry heading noise (rad per step)")
      ("odo-lateral-sigma-rel", po::value(&c.odo_lateral_sigma_rel)->default_value(c.odo_lateral_sigma_rel),
       "lateral odometry noise std per metre of the step")
      ("odo-distance-scale", po::value(&c.odo_distance_scale)->default_value(c.odo_distance_scale),
       "reported forward distance = scale * true (an odometry scale error)")
      ("odo-sigma-reported", po::value(&c.odo_sigma_reported_m)->default_value(c.odo_sigma_reported_m),
       "translation sigma (m, both axes) each odometry message states (a diagonal covariance; "
       "0 with odo-heading-sigma-reported 0: none stated)")
      ("odo-heading-sigma-reported", po::value(&c.odo_heading_sigma_reported_rad)->default_value(c.odo_heading_sigma_reported_rad),
       "heading sigma (rad) each odometry message states")
      ("gyro-bias", po::value(&c.odo_heading_bias_radps)->default_value(c.odo_heading_bias_radps),
       "reported turn = true + bias * dt (rad/s; a drifting gyro)")
      ("gyro-bias-walk", po::value(&c.odo_heading_bias_walk_radps_per_sqrt_s)->default_value(c.odo_heading_bias_walk_radps_per_sqrt_s),
       "the gyro bias's random walk (rad/s per sqrt(s); 0: constant; a MEMS gyro's bias instability: ~1e-5)")
      ("schedule", po::value(&schedule)->default_value(schedule),
       "all (every beacon at every pose) | round_robin (one beacon at a time, like UWB)")
      ("range-rate", po::value(&c.range_rate_hz)->default_value(c.range_rate_hz), "round robin: ranges per second")
      ("range-dropout", po::value(&c.range_dropout)->default_value(c.range_dropout), "probability a range is missing")
      ("range-sigma", po::value(&c.range_sigma_m)->default_value(c.range_sigma_m), "range noise std (m)")
      ("range-scale", po::value(&c.range_scale)->default_value(c.range_scale), "range = scale * true + offset")
      ("range-offset", po::value(&c.range_offset_m)->default_value(c.range_offset_m), "range offset (m)")
      ("range-latency-s", po::value(&range_latency_s)->default_value(range_latency_s),
       "each range logged this long after its stamp (a late sensor; roam-run's reorder_window_s)")
      ("range-sigma-reported", po::value(&c.range_sigma_reported_m)->default_value(c.range_sigma_reported_m),
       "sigma written into each range (0: unknown)")
      ("mixture-weight", po::value(&c.mixture_weight1)->default_value(c.mixture_weight1),
       "probability of the second noise component")
      ("mixture-sigma", po::value(&c.range_sigma1_m)->default_value(c.range_sigma1_m),
       "std of the second noise component (m)")
      ("outlier-fraction", po::value(&c.outlier_fraction)->default_value(c.outlier_fraction),
       "fraction of ranges replaced by true + U(outlier-min, outlier-max)")
      ("outlier-min", po::value(&c.outlier_min_m)->default_value(c.outlier_min_m), "m")
      ("outlier-max", po::value(&c.outlier_max_m)->default_value(c.outlier_max_m), "m")
      ("outlier-episode-s", po::value(&c.outlier_episode_s)->default_value(c.outlier_episode_s),
       "outliers in stretches per beacon (a wall or a hull in the way): mean NLOS stretch (s); "
       "--outlier-fraction of the time each beacon is NLOS, every range of a stretch long by one "
       "excess U(outlier-min, outlier-max) (0: range by range)")
      ("range-gap", po::value(&range_gaps)->composing(),
       "START_S:DURATION_S: no range from any beacon in [start, start + duration), seconds after "
       "the start pose (repeatable; the rest of the run is the same as without it)")
      ("beacon-offset-min", po::value(&c.beacon_offset_min_m)->default_value(c.beacon_offset_min_m),
       "each beacon's own range offset: magnitude at least this (m)")
      ("beacon-offset-max", po::value(&c.beacon_offset_max_m)->default_value(c.beacon_offset_max_m),
       "... and at most this (m; random sign per beacon, added to every range to it, as an acoustic "
       "transponder's delay: GOATS' are 1-2 m; 0: none)")
      ("beacon-survey-sigma", po::value(&c.beacon_survey_sigma_m)->default_value(c.beacon_survey_sigma_m),
       "survey error of the published beacons: N(0, sigma^2) m on each axis (ranges are to the true "
       "positions; 0: exact)")
      ("bearing", po::bool_switch(&c.bearing), "also measure the robot-relative bearing")
      ("bearing-sigma", po::value(&c.bearing_sigma_rad)->default_value(c.bearing_sigma_rad), "rad");
  // clang-format on
  try {
    po::variables_map vm;
    if (!roam::tools::parseCommandLine(argc, argv, visible, &vm)) return 0;
    require(!output.empty(), "missing -o LOG (the log to write)");
    require(c.num_steps > 0, "--steps: expected > 0");
    require(c.dt_s > 0, "--dt: expected > 0");
    require(c.speed_mps >= 0, "--speed: expected >= 0");
    require(c.hold_s >= 0 && std::isfinite(c.hold_s), "--hold-s: expected a finite number >= 0");
    require(c.range_dropout >= 0 && c.range_dropout <= 1, "--range-dropout: expected in [0, 1]");
    require(c.mixture_weight1 >= 0 && c.mixture_weight1 <= 1, "--mixture-weight: expected in [0, 1]");
    require(c.outlier_fraction >= 0 && c.outlier_fraction <= 1, "--outlier-fraction: expected in [0, 1]");
    require(c.outlier_min_m <= c.outlier_max_m, "--outlier-min: expected <= --outlier-max");
    require(std::isfinite(c.outlier_episode_s) && c.outlier_episode_s >= 0,
            "--outlier-episode-s: expected a finite number >= 0");
    require(c.range_sigma_m >= 0 && c.range_sigma1_m >= 0 && c.bearing_sigma_rad >= 0,
            "--range-sigma, --mixture-sigma, --bearing-sigma: expected >= 0");
    require(c.range_rate_hz > 0, "--range-rate: expected > 0");
    require(range_latency_s >= 0 && range_latency_s <= 3600, "--range-latency-s: expected in [0, 3600]");
    require(c.beacon_offset_min_m >= 0 && c.beacon_offset_min_m <= c.beacon_offset_max_m,
            "--beacon-offset-min: expected 0 <= --beacon-offset-min <= --beacon-offset-max");
    require(c.beacon_survey_sigma_m >= 0 && std::isfinite(c.beacon_survey_sigma_m),
            "--beacon-survey-sigma: expected a finite number >= 0");
    require(c.odo_sigma_reported_m >= 0 && std::isfinite(c.odo_sigma_reported_m) &&
                c.odo_heading_sigma_reported_rad >= 0 && std::isfinite(c.odo_heading_sigma_reported_rad) &&
                (c.odo_sigma_reported_m > 0) == (c.odo_heading_sigma_reported_rad > 0),
            "--odo-sigma-reported, --odo-heading-sigma-reported: expected both > 0 (a stated covariance) or both 0");
    for (const std::string& gap : range_gaps) {
      try {
        c.range_gaps.push_back(roam::sim::parseRangeGap(gap));
      } catch (const std::invalid_argument& e) {
        throw std::runtime_error(std::string("--range-gap: ") + e.what());
      }
    }
    c.path = roam::sim::parsePathKind(path_kind);  // throws std::invalid_argument with the choices
    if (schedule == "all") c.schedule = roam::sim::RangeSchedule::kEveryStepAllBeacons;
    else if (schedule == "round_robin") c.schedule = roam::sim::RangeSchedule::kRoundRobin;
    else throw std::runtime_error("--schedule: expected all | round_robin, got '" + schedule + "'");
    if (!beacons_csv.empty()) c.beacons = roam::loadLandmarksCsv(beacons_csv);
    else require(c.num_beacons > 0 || (team.num_robots >= 2 && c.num_beacons == 0),
                 "--beacons: expected > 0 (0 for a team, --robots 2 or more)");
    require(team.num_robots >= 1 && team.num_robots <= 26, "--robots: expected 1 to 26");
    c.start_utime = start_utime;
    c.start.x_m = start_x;
    c.start.y_m = start_y;
    c.start.heading_rad = start_heading;

    if (team.num_robots >= 2) {
      require(range_latency_s == 0, "--range-latency-s: not for a team run (--robots)");
      require(team.robot_range_rate_hz > 0 && std::isfinite(team.robot_range_rate_hz), "--robot-range-rate-hz: expected > 0");
      require(team.robot_spacing_m > 0 && std::isfinite(team.robot_spacing_m), "--robot-spacing: expected > 0");
      team.robot = c;
      const roam::TeamDataset run = roam::sim::simulateTeam(team);
      const roam::TeamLogWriteSummary s = roam::writeTeamLog(output, run);
      long robot_ranges = 0;
      for (long count : s.robot_ranges) robot_ranges += count;
      std::printf("roam-sim: %s: a team of %d robots, %ld events (%ld ranges between robots, %ld beacons), seed %llu\n",
                  output.c_str(), team.num_robots, s.events, robot_ranges, s.beacons,
                  static_cast<unsigned long long>(c.seed));
      for (size_t r = 0; r < run.robots.size(); ++r)
        std::printf("roam-sim: robot %s: %ld odometry, %ld ranges to beacons, %ld ranges to robots, %ld ground truth\n",
                    run.robots[r].c_str(), s.members[r].odometry, s.members[r].ranges, s.robot_ranges[r],
                    s.members[r].ground_truth);
      return 0;
    }
    const roam::Dataset run = roam::sim::simulate(c);
    const roam::LogWriteSummary s =
        roam::writeDatasetLog(output, run, static_cast<int64_t>(std::llround(range_latency_s * 1e6)));
    std::printf("roam-sim: %s: %ld events (%ld odometry, %ld ranges, %ld ground truth, %ld beacons), seed %llu\n",
                output.c_str(), s.events, s.odometry, s.ranges, s.ground_truth, s.beacons,
                static_cast<unsigned long long>(c.seed));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "roam-sim: error: %s\n", e.what());
    return 2;
  }
}
