// roam-spectral-fig1b from the command line: help, bad options, a small study's table and files.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "tool_test_util.hpp"

namespace {

using roam_test::runTool;
using roam_test::tool;

TEST(Fig1bTool, HelpExitsZero) {
  const auto r = runTool(tool("roam-spectral-fig1b") + " --help");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("--worlds"), std::string::npos);
}

TEST(Fig1bTool, BadOptionsExitTwoWithAMessage) {
  auto r = runTool(tool("roam-spectral-fig1b") + " --no-such-option");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("roam-spectral-fig1b: error:"), std::string::npos) << r.out;
  r = runTool(tool("roam-spectral-fig1b") + " --worlds 0 --steps 400 800");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("worlds must be >= 1"), std::string::npos) << r.out;
  r = runTool(tool("roam-spectral-fig1b") + " --png x.png");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("--png needs --svg"), std::string::npos) << r.out;
}

TEST(Fig1bTool, WritesTheTableAndTheFigure) {
  roam_test::ScratchDir dir;
  const auto r = runTool(tool("roam-spectral-fig1b") + " --worlds 4 --steps 400 1600 --csv " + dir.file("t.csv") +
                         " --svg " + dir.file("f.svg"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("log-log slope of the median:"), std::string::npos);
  std::ifstream csv(dir.file("t.csv"));
  std::string header, first, second, extra;
  std::getline(csv, header);
  std::getline(csv, first);
  std::getline(csv, second);
  EXPECT_EQ(header, "steps,readings,mean,median,p25,p75");
  EXPECT_EQ(first.rfind("400,2406,", 0), 0u) << first;  // 6 beacons x 401 poses
  EXPECT_EQ(second.rfind("1600,9606,", 0), 0u) << second;
  EXPECT_FALSE(std::getline(csv, extra));
  std::stringstream svg;
  svg << std::ifstream(dir.file("f.svg")).rdbuf();
  EXPECT_NE(svg.str().find("<polyline"), std::string::npos);
}

}  // namespace
