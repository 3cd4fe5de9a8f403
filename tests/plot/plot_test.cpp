// roam-plot on a small fixture log written here: the SVGs parse back (balanced tags), hold one
// path per estimator plus the ground truth with the estimators' names as labels, the figures
// inside them are the ones worked out below, and the PNGs have the stated size.
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <lcm/lcm-cpp.hpp>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../common/fixture_log.hpp"
#include "../tools/tool_test_util.hpp"
#include "roam/map_t.hpp"
#include "roam/odometry_t.hpp"
#include "roam/pose_t.hpp"
#include "roam/trajectory_t.hpp"
#include "svg_scan.hpp"

namespace {

using roam_test::Element;

using roam::test::FixtureLog;
using roam::test::fixturePose;

// Ground truth: 21 poses at t = 0..20 s, at (t, 0); odometry 1 m straight ahead per second, so
// the odometry baseline is exact (mean error 0).
// "alpha": POSE_ALPHA at every t at (t, 0.5): error 0.5 m at 21 times. MAP_ALPHA: beacon 1 at
//   (10, 10) with covariance [3 1; 1 3] (eigenvalues 4 and 2, major axis at 45 degrees: a 2-sigma
//   ellipse with semi-axes 4 m and 2 sqrt(2) m, ratio sqrt(2)), beacon 2 with a NaN covariance
//   (no ellipse).
// "beta": POSE_BETA far off (not scored) and TRAJECTORY_BETA at t = 5..15 at (t, -1): error 1 m
//   at the 11 ground-truth times inside its span.
std::string writeFixture(const roam_test::ScratchDir& dir) {
  const std::string path = dir.file("fixture.lcmlog");
  FixtureLog log(path);
  const roam::map_t beacons = roam::test::fixtureMap({{1, 10, 10}, {2, 5, -6}});
  log.write("INITIAL_POSE", 0, fixturePose(0, 0, 0));
  log.write("BEACONS", 0, beacons);
  roam::trajectory_t beta{};
  beta.estimator = "beta";
  for (int t = 0; t <= 20; ++t) {
    const int64_t utime = t * 1000000LL;
    log.write("GROUND_TRUTH", utime, fixturePose(utime, t, 0));
    if (t > 0) {
      roam::odometry_t odometry{};
      odometry.utime = utime;
      odometry.delta_distance = 1.0;
      log.write("ODOMETRY", utime, odometry);
    }
    log.write("POSE_ALPHA", utime, fixturePose(utime, t, 0.5, "alpha"));
    log.write("POSE_BETA", utime, fixturePose(utime, 500, 500, "beta"));
    if (t >= 5 && t <= 15) {
      beta.utimes.push_back(utime);
      beta.x.push_back(t);
      beta.y.push_back(-1.0);
      beta.heading.push_back(0.0);
    }
  }
  beta.num_poses = static_cast<int32_t>(beta.utimes.size());
  beta.utime = 20000000;
  log.write("TRAJECTORY_BETA", beta.utime, beta);
  roam::map_t map = beacons;
  map.estimator = "alpha";
  map.beacons[0].covariance[0] = 3;
  map.beacons[0].covariance[1] = 1;
  map.beacons[0].covariance[2] = 1;
  map.beacons[0].covariance[3] = 3;
  log.write("MAP_ALPHA", 20000000, map);
  return path;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// PNG: 8-byte signature, then the IHDR chunk (length, "IHDR", width, height big-endian).
bool pngSize(const std::string& path, uint32_t* width, uint32_t* height) {
  const std::string png = readFile(path);
  if (png.size() < 24 || png.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0 || png.compare(12, 4, "IHDR") != 0) return false;
  auto be32 = [&](size_t at) {
    return (uint32_t(uint8_t(png[at])) << 24) | (uint32_t(uint8_t(png[at + 1])) << 16) |
           (uint32_t(uint8_t(png[at + 2])) << 8) | uint32_t(uint8_t(png[at + 3]));
  };
  *width = be32(16);
  *height = be32(20);
  return true;
}

std::vector<const Element*> withClass(const roam_test::ScanResult& svg, const std::string& name,
                                      const std::string& css_class) {
  std::vector<const Element*> found;
  for (const Element& e : svg.elements) {
    const auto it = e.attributes.find("class");
    if (e.name == name && it != e.attributes.end() && it->second == css_class) found.push_back(&e);
  }
  return found;
}

size_t count(const roam_test::ScanResult& svg, const std::string& name) {
  size_t n = 0;
  for (const Element& e : svg.elements) n += e.name == name;
  return n;
}

// The <title> following a polyline in document order is its label.
std::vector<std::string> polylineTitles(const roam_test::ScanResult& svg, const std::string& css_class) {
  std::vector<std::string> titles;
  for (size_t i = 0; i + 1 < svg.elements.size(); ++i) {
    const Element& e = svg.elements[i];
    const auto it = e.attributes.find("class");
    if (e.name == "polyline" && it != e.attributes.end() && it->second == css_class &&
        svg.elements[i + 1].name == "title")
      titles.push_back(svg.elements[i + 1].text);
  }
  return titles;
}

bool hasText(const roam_test::ScanResult& svg, const std::string& text) {
  for (const Element& e : svg.elements)
    if (e.name == "text" && e.text == text) return true;
  return false;
}

size_t pointCount(const Element& polyline) {
  std::istringstream points(polyline.attributes.at("points"));
  size_t n = 0;
  std::string pair;
  while (points >> pair) ++n;
  return n;
}

class PlotTest : public ::testing::Test {
 protected:
  roam_test::ScratchDir dir;
  std::string log = writeFixture(dir);
  std::string prefix = dir.file("fig");

  roam_test::ToolResult plot(const std::string& options) {
    return roam_test::runTool(roam_test::tool("roam-plot") + " " + log + " -o " + prefix + " " + options);
  }
  roam_test::ScanResult scan(const std::string& figure) {
    return roam_test::scanXml(readFile(prefix + "-" + figure + ".svg"));
  }
};

TEST_F(PlotTest, OverlayHasOnePathPerEstimatorAndTheGroundTruth) {
  const auto r = plot("--width 640 --height 480 --layout overlay");
  ASSERT_EQ(r.status, 0) << r.out;
  const auto svg = scan("paths");
  ASSERT_TRUE(svg.balanced) << svg.problem;
  EXPECT_EQ(svg.root, "svg");
  EXPECT_EQ(count(svg, "polyline"), 4u);  // ground truth + odometry, alpha, beta
  EXPECT_EQ(withClass(svg, "polyline", "truth").size(), 1u);
  EXPECT_EQ(polylineTitles(svg, "estimate"), (std::vector<std::string>{"odometry", "alpha", "beta"}));
  // Labels: the legend names each estimator with its mean error (0, 0.5 and 1 m, see above).
  EXPECT_TRUE(hasText(svg, "odometry (mean error 0.00 m)"));
  EXPECT_TRUE(hasText(svg, "alpha (mean error 0.50 m)"));
  EXPECT_TRUE(hasText(svg, "beta (mean error 1.00 m)"));
  EXPECT_TRUE(hasText(svg, "ground truth"));
  EXPECT_TRUE(hasText(svg, "1"));  // true beacon ids
  EXPECT_TRUE(hasText(svg, "2"));
  bool scale_bar = false;
  for (const Element& e : svg.elements) scale_bar |= e.name == "text" && e.text.size() > 2 &&
                                                     e.text.compare(e.text.size() - 2, 2, " m") == 0 &&
                                                     std::isdigit(static_cast<unsigned char>(e.text[0]));
  EXPECT_TRUE(scale_bar) << "no '<n> m' scale bar label";
}

TEST_F(PlotTest, EllipseOnlyWhereTheCovarianceIsFinite) {
  ASSERT_EQ(plot("--layout overlay --no-png").status, 0);
  const auto svg = scan("paths");
  ASSERT_TRUE(svg.balanced) << svg.problem;
  // One legend swatch (rx 11, ry 6, no rotation) and alpha's beacon 1: semi-axes 4 m and
  // 2 sqrt(2) m (ratio sqrt(2), written with 2 decimals), major axis at +45 degrees in the world,
  // which is -45 degrees on screen (y points down).
  std::vector<const Element*> ellipses;
  for (const Element& e : svg.elements)
    if (e.name == "ellipse" && e.attributes.at("rx") != "11") ellipses.push_back(&e);
  ASSERT_EQ(ellipses.size(), 1u);
  const double rx = std::stod(ellipses[0]->attributes.at("rx")), ry = std::stod(ellipses[0]->attributes.at("ry"));
  EXPECT_NEAR(rx / ry, std::sqrt(2.0), 0.01);
  EXPECT_NE(ellipses[0]->attributes.at("transform").find("rotate(-45)"), std::string::npos)
      << ellipses[0]->attributes.at("transform");
}

TEST_F(PlotTest, PanelsShareTheWindowAndEachShowsTheGroundTruth) {
  ASSERT_EQ(plot("--width 900 --height 500 --no-png").status, 0);
  const auto svg = scan("paths");
  ASSERT_TRUE(svg.balanced) << svg.problem;
  EXPECT_EQ(withClass(svg, "polyline", "truth").size(), 3u);  // one per panel
  EXPECT_EQ(polylineTitles(svg, "estimate"), (std::vector<std::string>{"odometry", "alpha", "beta"}));
  EXPECT_TRUE(hasText(svg, "alpha"));  // panel titles
  EXPECT_TRUE(hasText(svg, "beta"));
  EXPECT_TRUE(hasText(svg, "mean error 0.50 m"));
  // A shared window: the ground truth is drawn with the same length in every panel.
  const auto truths = withClass(svg, "polyline", "truth");
  auto span = [](const Element* e) {
    std::istringstream points(e->attributes.at("points"));
    std::string first, pair, last;
    points >> first;
    last = first;
    while (points >> pair) last = pair;
    return std::stod(last.substr(0, last.find(','))) - std::stod(first.substr(0, first.find(',')));
  };
  EXPECT_GT(span(truths[0]), 10.0);
  for (const Element* t : truths) EXPECT_NEAR(span(t), span(truths[0]), 0.011);
}

TEST_F(PlotTest, ErrorCurvesMatchGroundTruthInsideEachSpan) {
  ASSERT_EQ(plot("--width 800 --height 400 --no-png").status, 0);
  const auto svg = scan("error");
  ASSERT_TRUE(svg.balanced) << svg.problem;
  EXPECT_EQ(polylineTitles(svg, "error"), (std::vector<std::string>{"odometry", "alpha", "beta"}));
  const auto curves = withClass(svg, "polyline", "error");
  ASSERT_EQ(curves.size(), 3u);
  // alpha matches all 21 ground-truth times, beta the 11 inside its trajectory's span (5..15 s);
  // ~35 px between samples on this axis, so none is dropped as a duplicate pixel.
  EXPECT_EQ(pointCount(*curves[1]), 21u);
  EXPECT_EQ(pointCount(*curves[2]), 11u);
  EXPECT_TRUE(hasText(svg, "alpha (mean 0.50 m)"));
  EXPECT_TRUE(hasText(svg, "beta (mean 1.00 m)"));
  EXPECT_TRUE(hasText(svg, "time since start (s)"));
  EXPECT_TRUE(hasText(svg, "position error (m)"));
}

TEST_F(PlotTest, PngsHaveTheStatedSize) {
  const auto r = plot("--width 640 --height 360");
  ASSERT_EQ(r.status, 0) << r.out;
  for (const char* figure : {"paths", "error"}) {
    uint32_t width = 0, height = 0;
    ASSERT_TRUE(pngSize(prefix + "-" + figure + ".png", &width, &height)) << figure;
    EXPECT_EQ(width, 640u) << figure;
    EXPECT_EQ(height, 360u) << figure;
  }
}

TEST_F(PlotTest, EstimatorsOptionSelectsAndNamesTheMissing) {
  ASSERT_EQ(plot("--estimators BETA --layout overlay --no-png").status, 0);  // a channel suffix works too
  EXPECT_EQ(polylineTitles(scan("paths"), "estimate"), (std::vector<std::string>{"beta"}));
  const auto r = plot("--estimators gamma --no-png");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("no estimator 'gamma'"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("odometry, alpha, beta"), std::string::npos) << r.out;
}

TEST_F(PlotTest, MissingRsvgConvertIsAClearError) {
  const auto r = roam_test::runTool("env PATH=" + dir.path() + " " + roam_test::tool("roam-plot") + " " + log +
                                    " -o " + prefix);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("rsvg-convert not found on PATH"), std::string::npos) << r.out;
  EXPECT_TRUE(roam_test::scanXml(readFile(prefix + "-paths.svg")).balanced);  // the SVGs are written first
}

TEST_F(PlotTest, BadOptionsExitTwo) {
  EXPECT_EQ(plot("--layout grid").status, 2);
  EXPECT_EQ(roam_test::runTool(roam_test::tool("roam-plot") + " " + log).status, 2);  // no -o
  EXPECT_EQ(roam_test::runTool(roam_test::tool("roam-plot") + " " + dir.file("none.lcmlog") + " -o x").status, 2);
}

}  // namespace

namespace {

// A team of two robots: A's ground truth at (t, 0), B's at (t, 10), t = 0..10 s.
// "alpha" (one-robot plugin instances alpha_A, alpha_B): POSE_ALPHA_A at (t, 1) (error 1 m),
//   POSE_ALPHA_B at (t, 10) (error 0): team mean over 22 matches 0.5 m.
// "beta" (a team plugin): TRAJECTORY_BETA_A at (t, 2) (error 2 m), nothing for B: team mean 2 m.
std::string writeTeamFixture(const roam_test::ScratchDir& dir) {
  const std::string path = dir.file("team.lcmlog");
  FixtureLog log(path);
  log.write("BEACONS", 0, roam::test::fixtureMap({{1, 5, 5}}));
  roam::trajectory_t beta{};
  beta.estimator = "beta";
  for (int t = 0; t <= 10; ++t) {
    const int64_t utime = t * 1000000LL;
    log.write("GROUND_TRUTH_A", utime, fixturePose(utime, t, 0));
    log.write("GROUND_TRUTH_B", utime, fixturePose(utime, t, 10));
    log.write("POSE_ALPHA_A", utime, fixturePose(utime, t, 1, "alpha_A"));
    log.write("POSE_ALPHA_B", utime, fixturePose(utime, t, 10, "alpha_B"));
    beta.utimes.push_back(utime);
    beta.x.push_back(t);
    beta.y.push_back(2.0);
    beta.heading.push_back(0.0);
  }
  beta.num_poses = static_cast<int32_t>(beta.utimes.size());
  beta.utime = 10000000;
  log.write("TRAJECTORY_BETA_A", beta.utime, beta);
  return path;
}

class TeamPlotTest : public ::testing::Test {
 protected:
  roam_test::ScratchDir dir;
  std::string log = writeTeamFixture(dir);
  std::string prefix = dir.file("team");

  roam_test::ToolResult plot(const std::string& options) {
    return roam_test::runTool(roam_test::tool("roam-plot") + " " + log + " -o " + prefix + " " + options);
  }
  roam_test::ScanResult scan(const std::string& figure) {
    return roam_test::scanXml(readFile(prefix + "-" + figure + ".svg"));
  }
};

std::string attribute(const Element* e, const std::string& name) {
  const auto it = e->attributes.find(name);
  return it == e->attributes.end() ? "" : it->second;
}

// One colour per robot, one line style per estimator, and a legend that says which is which.
TEST_F(TeamPlotTest, OneColourPerRobotAndOneStylePerEstimator) {
  const auto r = plot("--layout overlay --no-png");
  ASSERT_EQ(r.status, 0) << r.out;
  const auto svg = scan("paths");
  ASSERT_TRUE(svg.balanced) << svg.problem;
  EXPECT_EQ(polylineTitles(svg, "truth"), (std::vector<std::string>{"ground truth A", "ground truth B"}));
  EXPECT_EQ(polylineTitles(svg, "estimate"), (std::vector<std::string>{"alpha A", "alpha B", "beta A"}));
  const auto truths = withClass(svg, "polyline", "truth");
  const auto paths = withClass(svg, "polyline", "estimate");
  ASSERT_EQ(truths.size(), 2u);
  ASSERT_EQ(paths.size(), 3u);
  EXPECT_NE(attribute(truths[0], "stroke"), attribute(truths[1], "stroke"));
  EXPECT_EQ(attribute(paths[0], "stroke"), attribute(truths[0], "stroke"));  // alpha A: A's colour
  EXPECT_EQ(attribute(paths[1], "stroke"), attribute(truths[1], "stroke"));  // alpha B: B's colour
  EXPECT_EQ(attribute(paths[2], "stroke"), attribute(truths[0], "stroke"));  // beta A: A's colour
  EXPECT_EQ(attribute(paths[0], "stroke-dasharray"), "");                     // alpha solid
  EXPECT_EQ(attribute(paths[1], "stroke-dasharray"), "");
  EXPECT_NE(attribute(paths[2], "stroke-dasharray"), "");                     // beta dashed
  EXPECT_TRUE(hasText(svg, "robot A"));
  EXPECT_TRUE(hasText(svg, "robot B"));
  EXPECT_TRUE(hasText(svg, "alpha (solid, team mean error 0.50 m)"));
  EXPECT_TRUE(hasText(svg, "beta (dashed, team mean error 2.00 m)"));
}

TEST_F(TeamPlotTest, PanelsPerEstimatorShowEveryRobot) {
  ASSERT_EQ(plot("--no-png").status, 0);
  const auto svg = scan("paths");
  ASSERT_TRUE(svg.balanced) << svg.problem;
  EXPECT_EQ(withClass(svg, "polyline", "truth").size(), 4u);  // both robots in each of two panels
  EXPECT_TRUE(hasText(svg, "alpha (solid)"));
  EXPECT_TRUE(hasText(svg, "team mean error 2.00 m"));
}

// The error figure: one curve per robot and estimator, each against its own robot's truth.
TEST_F(TeamPlotTest, ErrorCurvePerRobotAndEstimator) {
  ASSERT_EQ(plot("--width 800 --height 400 --no-png").status, 0);
  const auto svg = scan("error");
  ASSERT_TRUE(svg.balanced) << svg.problem;
  EXPECT_EQ(polylineTitles(svg, "error"), (std::vector<std::string>{"alpha A", "alpha B", "beta A"}));
  const auto curves = withClass(svg, "polyline", "error");
  ASSERT_EQ(curves.size(), 3u);
  for (const Element* curve : curves) EXPECT_EQ(pointCount(*curve), 11u);
  EXPECT_NE(attribute(curves[2], "stroke-dasharray"), "");
  EXPECT_TRUE(hasText(svg, "robot B"));
  const auto r = plot("--estimators gamma --no-png");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("alpha, beta"), std::string::npos) << r.out;
}

}  // namespace
