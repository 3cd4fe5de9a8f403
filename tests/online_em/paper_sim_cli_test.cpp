// roam-online-em-paper-sim from the command line: help, bad options, a tiny study's table and files.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "../tools/tool_test_util.hpp"

namespace {

using roam_test::runTool;
using roam_test::tool;

const std::string kTool = "roam-online-em-paper-sim";

TEST(PaperSimTool, HelpExitsZeroWithoutSimulating) {
  const auto r = runTool(tool(kTool) + " --help");
  EXPECT_EQ(r.status, 0);
  for (const char* option : {"--runs", "--seed", "--steps", "--particles", "--svg", "--png", "--csv"})
    EXPECT_NE(r.out.find(option), std::string::npos) << option;
  EXPECT_EQ(r.out.find("run 1/"), std::string::npos) << r.out;
}

TEST(PaperSimTool, BadOptionsExitTwoWithAMessage) {
  const std::pair<std::string, std::string> cases[] = {
      {" --no-such-option", "roam-online-em-paper-sim: error:"},
      {" --runs", "roam-online-em-paper-sim: error:"},
      {" --runs many", "roam-online-em-paper-sim: error:"},
      {" --runs 0", "runs must be >= 1"},
      {" --particles 1", "particles must be >= 2"},
      {" --steps 100 --times 50 200", "--times: every time must be in [1, --steps]"},
      {" --indicators maybe", "--indicators: expected sampled or marginal"},
      {" --png x.png", "--png needs --svg"},
  };
  for (const auto& [args, message] : cases) {
    const auto r = runTool(tool(kTool) + args);
    EXPECT_EQ(r.status, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(message), std::string::npos) << args << "\n" << r.out;
  }
}

TEST(PaperSimTool, PrintsTheQuantilesAndWritesTheFiles) {
  roam_test::ScratchDir dir;
  const auto r = runTool(tool(kTool) + " --runs 2 --steps 120 --particles 20 --times 50 120 -q --csv " +
                         dir.file("e.csv") + " --svg " + dir.file("f.svg"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("x error (true - estimated), m"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| 50 |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| 120 |"), std::string::npos) << r.out;
  std::ifstream csv(dir.file("e.csv"));
  std::string line;
  int rows = 0;
  std::getline(csv, line);
  EXPECT_EQ(line, "run,t,x_error_m,y_error_m,map_error_m,aligned_map_error_m");
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 4);  // 2 runs x 2 times
  std::stringstream svg;
  svg << std::ifstream(dir.file("f.svg")).rdbuf();
  EXPECT_NE(svg.str().find("class=\"truth\""), std::string::npos);
  EXPECT_NE(svg.str().find("online EM, mean of 2 runs"), std::string::npos);
}

}  // namespace
