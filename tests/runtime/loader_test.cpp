// The plugin loader against deliberately broken plugins (built beside this test).
#include <gtest/gtest.h>

#include "plugin_library.hpp"

namespace roam {
namespace runtime {
namespace {

const std::string kDir = ROAM_TEST_PLUGIN_DIR;

std::string openError(const std::string& name) {
  try {
    PluginLibrary::open(kDir, name);
  } catch (const PluginError& error) {
    return error.what();
  }
  return "(loaded)";
}

TEST(Loader, LoadsAGoodPluginAndChecksItsName) {
  auto library = PluginLibrary::open(kDir, "deadreckoning");
  EXPECT_STREQ(library->descriptor().name, "deadreckoning");
  EXPECT_EQ(library->descriptor().abi_version, ROAM_PLUGIN_ABI_VERSION);
}

TEST(Loader, RejectsAWrongAbiVersion) {
  EXPECT_EQ(openError("wrong_version"),
            kDir + "/libroam_wrong_version.so: plugin ABI version " +
                std::to_string(ROAM_PLUGIN_ABI_VERSION + 1) + ", but this roam-run speaks version " +
                std::to_string(ROAM_PLUGIN_ABI_VERSION) + ": rebuild the plugin");
}

TEST(Loader, RejectsAWrongDescriptorSize) {
  const size_t expected = sizeof(roam_plugin_descriptor);
  EXPECT_EQ(openError("wrong_size"), kDir + "/libroam_wrong_size.so: plugin descriptor is " +
                                         std::to_string(expected - 8) + " bytes, expected " +
                                         std::to_string(expected) +
                                         ": rebuild the plugin against this roam");
}

TEST(Loader, RejectsAStructLayoutThatDiffersFromTheHosts) {
  // wrong_layout was built with ABI-1's 24-byte roam_odometry (utime, distance, heading).
  EXPECT_EQ(openError("wrong_layout"),
            kDir + "/libroam_wrong_layout.so: the plugin's roam_odometry is 24 bytes aligned to 8, "
                   "this roam-run's is " + std::to_string(sizeof(roam_odometry)) +
                " aligned to 8: rebuild the plugin against this roam's plugin_abi.h");
  // utime, forward, lateral, heading, covariance, robot (4 bytes and 4 of padding to 8)
  EXPECT_EQ(sizeof(roam_odometry), 8u + 3 * 8 + 9 * 8 + 8);
}

TEST(Loader, RejectsALibraryWithoutTheEntrySymbol) {
  EXPECT_EQ(openError("no_entry"),
            kDir + "/libroam_no_entry.so: not a roam plugin: no 'roam_plugin_entry' symbol");
}

TEST(Loader, AMissingPluginGetsAHint) {
  EXPECT_EQ(openError("deadreckonin"),
            "no plugin 'deadreckonin' in " + kDir + " (did you mean 'deadreckoning'?)");
  EXPECT_EQ(openError("kalman"), "no plugin 'kalman' in " + kDir +
                                     " (available: aborts crashes create_fails deadreckoning ekf hangs "
                                     "hungry no_entry online_em spectral spectral_batch team_dr throws wrong_layout "
                                     "wrong_size wrong_version)");
}

TEST(Loader, CreateFailuresCarryTheKeyAndMessage) {
  auto library = PluginLibrary::open(kDir, "create_fails");
  try {
    PluginInstance instance(library, "x", {});
    FAIL() << "create should have failed";
  } catch (const PluginConfigError& error) {
    EXPECT_EQ(error.key(), "");
    EXPECT_STREQ(error.what(), "deliberate create failure");
  }
  auto good = PluginLibrary::open(kDir, "deadreckoning");
  try {
    PluginInstance instance(good, "x", {{"max_speed_mps", "-1"}});
    FAIL() << "create should have failed";
  } catch (const PluginConfigError& error) {
    EXPECT_EQ(error.key(), "max_speed_mps");
    EXPECT_STREQ(error.what(), "expected a value > 0, got '-1'");
  }
}

TEST(Loader, AnInstanceThatThrowsIsMarkedFailedAndIgnoresFurtherInput) {
  auto library = PluginLibrary::open(kDir, "throws");
  PluginInstance instance(library, "t", {{"fail_after", "2"}});
  roam_odometry step{};
  step.utime = 1000;
  step.forward_m = 0.5;
  EXPECT_TRUE(instance.addOdometry(step));
  EXPECT_TRUE(instance.addOdometry(step));
  EXPECT_FALSE(instance.addOdometry(step));
  EXPECT_TRUE(instance.failed());
  EXPECT_EQ(instance.error(), "add_odometry: deliberate failure at step 3");
  EXPECT_FALSE(instance.addOdometry(step));  // no more calls into the plugin
  EXPECT_EQ(instance.status().state, ROAM_STATE_FAILED);
  EXPECT_EQ(instance.status().odometry_accepted, 2);
}

TEST(Loader, NonFiniteInputsAreRejectedAndCountedBeforeTheEstimator) {
  auto library = PluginLibrary::open(kDir, "deadreckoning");
  PluginInstance instance(library, "dr", {});
  roam_range range{};
  range.range_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(instance.addRange(range));
  roam_odometry odometry{};
  odometry.utime = 1;
  odometry.forward_m = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(instance.addOdometry(odometry));
  const auto status = instance.status();
  EXPECT_EQ(status.ranges_rejected, 1);
  EXPECT_EQ(status.odometry_rejected, 1);
  EXPECT_EQ(status.last_rejection, "odometry: not finite");
  // Per-reason counts come first among the diagnostics.
  ASSERT_GE(status.keys.size(), 2u);
  EXPECT_EQ(status.keys[0], "rejected odometry: not finite");
  EXPECT_EQ(status.values[0], 1.0);
}

}  // namespace
}  // namespace runtime
}  // namespace roam
