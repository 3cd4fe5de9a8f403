// Plugins are code: roam-run refuses a plugin file or folder that others may write or that
// someone other than the user or root owns, and says how to fix it.
#include <gtest/gtest.h>
#include <unistd.h>

#include "plugin_library.hpp"
#include "test_util.hpp"

namespace roam {
namespace {

using runtime::PluginError;
using runtime::PluginLibrary;
using testing_util::run;
using testing_util::roamRun;
using testing_util::scratchDir;
using testing_util::writeFile;
namespace fs = std::filesystem;

// A private copy of the dead-reckoning plugin in <dir>/plugins (mode 0755, file 0644).
fs::path copyPlugin(const fs::path& dir) {
  const fs::path folder = dir / "plugins";
  fs::create_directories(folder);
  fs::permissions(folder, fs::perms(0755));
  const fs::path file = folder / "libroam_deadreckoning.so";
  fs::copy_file(fs::path(ROAM_TEST_PLUGIN_DIR) / "libroam_deadreckoning.so", file);
  fs::permissions(file, fs::perms(0644));
  return file;
}

std::string openError(const fs::path& folder) {
  try {
    PluginLibrary::open(folder.string(), "deadreckoning");
  } catch (const PluginError& error) {
    return error.what();
  }
  return "";
}

TEST(PluginPermissions, APluginOthersMayWriteIsRefusedWithTheFix) {
  const fs::path file = copyPlugin(scratchDir("permissions_file"));
  EXPECT_EQ(openError(file.parent_path()), "");  // 0644 in a 0755 folder: loads
  fs::permissions(file, fs::perms(0664));
  EXPECT_EQ(openError(file.parent_path()),
            file.string() + ": plugin writable by its group (mode 0664): anyone who can write it can change "
                            "the code roam-run runs; fix with: chmod go-w " + file.string());
  fs::permissions(file, fs::perms(0646));
  EXPECT_NE(openError(file.parent_path()).find("plugin writable by others (mode 0646)"), std::string::npos);
}

TEST(PluginPermissions, AFolderOthersMayWriteIsNotSearched) {
  const fs::path file = copyPlugin(scratchDir("permissions_folder"));
  const fs::path folder = file.parent_path();
  fs::permissions(folder, fs::perms(01777));  // like /tmp
  EXPECT_EQ(openError(folder), folder.string() + ": plugin folder writable by others (mode 1777): anyone who "
                                                 "can write it can change the code roam-run runs; fix with: "
                                                 "chmod go-w " + folder.string());
  // End to end: one line, exit status 2, before any data is read.
  const fs::path config = writeFile(folder.parent_path() / "run.ini",
                                    "[runtime]\ninput = x.lcmlog\nplugin_path = " + folder.string() +
                                        "\n[estimator.dr]\nplugin = deadreckoning\n");
  const auto result = run(roamRun() + " " + config.string());
  EXPECT_EQ(result.status, 2) << result.output;
  EXPECT_NE(result.output.find("run.ini:5 [estimator.dr] plugin: " + folder.string() +
                               ": plugin folder writable by others (mode 1777)"),
            std::string::npos)
      << result.output;
  fs::permissions(folder, fs::perms(0755));
  EXPECT_EQ(openError(folder), "");
}

TEST(PluginPermissions, APluginSomeoneElseOwnsIsRefused) {
  if (::getuid() != 0) GTEST_SKIP() << "giving a file to another user needs root";
  const fs::path file = copyPlugin(scratchDir("permissions_owner"));
  ASSERT_EQ(::chown(file.c_str(), 65534, 65534), 0);  // nobody
  const std::string error = openError(file.parent_path());
  EXPECT_NE(error.find(file.string() + ": plugin owned by nobody, not by you or root"), std::string::npos) << error;
}

}  // namespace
}  // namespace roam
