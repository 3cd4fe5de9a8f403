// Per-beacon range offsets of surveyed beacons (beacon_range_offset_sigma_m) on seeded
// AUV-like runs: ranges to each beacon carry its own offset (as GOATS' do: 1-2 m).
#include <cmath>
#include <cstdio>
#include <vector>
#include <map>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "feed.hpp"
#include "online_em_slam.hpp"
#include "roam/options.hpp"
#include "sim.hpp"

namespace roam {
namespace {

using online_em_test::deadReckoningError;
using online_em_test::feed;
using online_em_test::meanError;
using online_em::addOnlineEmOptions;
using online_em::OnlineEmConfig;
using online_em::OnlineEmSlam;

// Adds to every range to beacon b its offset: sign and magnitude (uniform in [1, 2] m) drawn
// per beacon from the stream `seed` (the sim's draw).
std::map<int, double> addBeaconOffsets(Dataset* data, uint64_t seed) {
  const std::map<int, double> offsets = sim::beaconOffsets(seed, 1.0, 2.0, data->beacons);
  for (Range& range : data->ranges) range.range_m += offsets.at(range.beacon_id);
  return offsets;
}

struct OffsetRun {
  double mean_m;
  std::map<int, double> offsets;
};

// scale_spread_sigma: distance_scale_particle_sigma (the default; 0 = round 4's model, which
// the offsets' figures were measured with).
OffsetRun runBeacons(const Dataset& data, double offset_sigma_m, uint64_t particle_seed = 1,
                     double scale_spread_sigma = OnlineEmConfig{}.distance_scale_particle_sigma) {
  OnlineEmConfig config;
  setOptions(&config, addOnlineEmOptions,
             {{"anchor", "beacons"}, {"estimate_beacon_range_offsets", offset_sigma_m > 0.0 ? "true" : "false"},
              {"beacon_range_offset_sigma_m", std::to_string(offset_sigma_m > 0.0 ? offset_sigma_m : 1.5)},
              {"seed", std::to_string(particle_seed)}});
  config.distance_scale_particle_sigma = scale_spread_sigma;  // an internal constant
  OnlineEmSlam slam(config);
  feed(data, slam);
  OffsetRun run{meanError(slam.filteredPath(), data.ground_truth), {}};
  for (const Beacon& beacon : data.beacons) run.offsets[beacon.id] = slam.beaconRangeOffset(beacon.id);
  return run;
}

// Plaza-like UWB run (tests/online_em/online_em_test.cpp's world): 30 x 20 m lawn mower, 4
// beacons, 2 Hz ranges with 0.5 m noise, 2 % odometry.
sim::SimConfig uwbWorld(uint64_t seed) {
  sim::SimConfig c;
  c.seed = seed;
  c.num_steps = 2000;
  c.path = sim::PathKind::kLawnMower;
  c.area_width_m = 30.0;
  c.area_height_m = 20.0;
  c.schedule = sim::RangeSchedule::kRoundRobin;
  c.range_rate_hz = 2.0;
  c.beacons = {{0, -8.0, -6.0, {}}, {1, 38.0, -5.0, {}}, {2, 36.0, 27.0, {}}, {3, -6.0, 26.0, {}}};
  c.odo_distance_sigma_rel = 0.02;
  c.odo_heading_sigma_rad = 0.005;
  c.range_sigma_m = 0.5;
  return c;
}

// UWB rates: each beacon's offset is recovered and the path no longer follows them. Off (the
// default) the offsets cost the path metres; on clean data the key costs little.
TEST(OnlineEmBeaconOffsets, UwbOffsetsAreRecovered) {
  const Dataset clean = sim::simulate(uwbWorld(7));
  Dataset biased = clean;
  const std::map<int, double> truth = addBeaconOffsets(&biased, 1007);
  // The offsets' own figures: round 4's model (no per-particle scale spread); the default below.
  const OffsetRun off = runBeacons(biased, 0.0, 1, 0.0), on = runBeacons(biased, 1.5, 1, 0.0);
  std::printf("UWB with offsets: path %.3f m off, %.3f m on\n", off.mean_m, on.mean_m);
  // Measured (seed 7): 1.03 m off, 0.32 m on; offsets within 0.4 m.
  EXPECT_GT(off.mean_m, 0.8);
  EXPECT_LT(on.mean_m, 0.4);
  for (const auto& [id, o] : truth) {
    EXPECT_EQ(off.offsets.at(id), 0.0);
    EXPECT_NEAR(on.offsets.at(id), o, 0.4) << "beacon " << id;
  }
  // With the scale spread (the default): the offsets trade with the distance and range scales a
  // little. Measured (seed 7): path 0.41 m, offsets within 0.53 m.
  const OffsetRun spread = runBeacons(biased, 1.5);
  std::printf("UWB with offsets, scale spread: path %.3f m\n", spread.mean_m);
  EXPECT_LT(spread.mean_m, 0.5);
  for (const auto& [id, o] : truth) EXPECT_NEAR(spread.offsets.at(id), o, 0.7) << "beacon " << id;
  const OffsetRun clean_off = runBeacons(clean, 0.0, 1, 0.0), clean_on = runBeacons(clean, 1.5, 1, 0.0);
  std::printf("UWB clean: path %.3f m off, %.3f m on\n", clean_off.mean_m, clean_on.mean_m);
  // Measured: 0.229 -> 0.247 m; offsets within 0.3 m of 0.
  EXPECT_LT(clean_on.mean_m, clean_off.mean_m + 0.08);
  for (const auto& [id, o] : clean_on.offsets) EXPECT_LT(std::abs(o), 0.3) << "beacon " << id;
}

// The prior is a count of pseudo-observations: at 1 cm the offsets stay at 0; the STATUS keys
// name each beacon; on by default, and the key turns them off.
TEST(OnlineEmBeaconOffsets, PriorHoldsAndStatusNamesEachBeacon) {
  Dataset biased = sim::simulate(uwbWorld(7));
  addBeaconOffsets(&biased, 1007);
  const OffsetRun tight = runBeacons(biased, 0.01);
  // Measured: 0.010-0.011 m where 1.5 m recovers 1.2-2.2 m.
  for (const auto& [id, o] : tight.offsets) EXPECT_LT(std::abs(o), 0.03) << "beacon " << id;
  OnlineEmConfig config;
  setOptions(&config, addOnlineEmOptions, {{"anchor", "beacons"}, {"estimate_beacon_range_offsets", "true"}});
  OnlineEmSlam slam(config);
  feed(biased, slam);
  for (const Beacon& beacon : biased.beacons)
    EXPECT_EQ(slam.diagnostics().at("range_offset_beacon_" + std::to_string(beacon.id) + "_m"),
              slam.beaconRangeOffset(beacon.id));
  EXPECT_TRUE(OnlineEmConfig{}.estimate_beacon_range_offsets);
  EXPECT_EQ(OnlineEmConfig{}.beacon_range_offset_sigma_m, 1.5);
  OnlineEmConfig defaults;
  setOptions(&defaults, addOnlineEmOptions, {{"anchor", "beacons"}, {"estimate_beacon_range_offsets", "false"}});
  OnlineEmSlam plain(defaults);
  feed(biased, plain);
  EXPECT_EQ(plain.diagnostics().count("range_offset_beacon_0_m"), 0u);
}

// Issue 15's AUV bound (1.25 x dead reckoning) with offsets in the ranges: the key on keeps it
// on the existing test's seeds, and on seed 309 (particle seed 3), where the path follows the
// offsets without it (25.1 m against the bound of 18.6 m). Over seeds 108, 203, 301-309 x
// particle seeds 1-3 (README): mean 5.41 -> 4.37 m, off breaks the bound once, on never.
TEST(OnlineEmBeaconOffsets, AuvWithOffsetsWithinDeadReckoningBound) {
  for (const auto& [seed, particle_seed] : std::vector<std::pair<uint64_t, uint64_t>>{{108, 1}, {203, 1}, {309, 3}}) {
    Dataset data = sim::simulate(sim::auvLikeWorld(seed, 500));
    addBeaconOffsets(&data, seed + 1000);
    const double dr_m = deadReckoningError(data);
    const double on_m = runBeacons(data, 1.5, particle_seed).mean_m;
    std::printf("AUV seed %d (particle seed %d) with offsets: %.2f m on, DR %.2f m\n", static_cast<int>(seed),
                static_cast<int>(particle_seed), on_m, dr_m);
    // Measured: 108: 3.37, 203: 3.16, 309: 4.37 m (the scale spread is off at these range rates).
    EXPECT_LT(on_m, 1.25 * dr_m);
    if (seed == 309) {
      // No offsets (and no scale spread, as at these range rates anyway): 25.1 m.
      EXPECT_GT(runBeacons(data, 0.0, particle_seed, 0.0).mean_m, 1.25 * dr_m);
    }
  }
}

}  // namespace
}  // namespace roam
