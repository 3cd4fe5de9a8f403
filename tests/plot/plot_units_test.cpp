// roam-plot's pieces: tick steps, tick labels, the 2-sigma ellipse, the metre-to-pixel frame and
// the SVG writer's escaping; expected values worked out by hand in the comments.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "loglog_figure.hpp"
#include "paths_figure.hpp"
#include "plot_axes.hpp"
#include "svg_writer.hpp"

namespace {

constexpr double kTolerance = 1e-12;
using namespace roam::plot;

TEST(NiceStep, IsTheSmallestOneTwoFiveAtOrAboveTheRawStep) {
  EXPECT_DOUBLE_EQ(niceStep(87.0, 6), 20.0);    // 14.5 -> 20
  EXPECT_DOUBLE_EQ(niceStep(100.0, 10), 10.0);  // exactly 10
  EXPECT_DOUBLE_EQ(niceStep(3.0, 10), 0.5);     // 0.3 -> 0.5
  EXPECT_DOUBLE_EQ(niceStep(1933.44, 10), 200.0);  // 193.3 -> 200
  EXPECT_DOUBLE_EQ(niceStep(0.011, 1), 0.02);
}

TEST(Ticks, MultiplesInsideTheRange) {
  const auto ticks = tickValues(-47.3, 24.0, 20.0);  // -40, -20, 0, 20
  ASSERT_EQ(ticks.size(), 4u);
  EXPECT_DOUBLE_EQ(ticks.front(), -40.0);
  EXPECT_DOUBLE_EQ(ticks.back(), 20.0);
  EXPECT_EQ(tickLabel(-40.0, 20.0), "-40");
  EXPECT_EQ(tickLabel(2.5, 0.5), "2.5");
  EXPECT_EQ(tickLabel(0.25, 0.05), "0.25");
  EXPECT_EQ(tickLabel(-1e-17, 0.1), "0.0");  // never "-0.0"
}

TEST(Ellipse, TwoSigmaAxesAndAngle) {
  Ellipse e;
  // [3 1; 1 3]: eigenvalues 3 +- 1 -> 4 (along (1, 1)) and 2: semi-axes 2*2 and 2*sqrt(2), 45 deg.
  ASSERT_TRUE(twoSigmaEllipse(3, 1, 3, &e));
  EXPECT_NEAR(e.major_m, 4.0, kTolerance);
  EXPECT_NEAR(e.minor_m, 2.0 * std::sqrt(2.0), kTolerance);
  EXPECT_NEAR(e.angle_rad, M_PI / 4, kTolerance);
  // diag(1, 9): major along y, semi-axes 6 and 2.
  ASSERT_TRUE(twoSigmaEllipse(1, 0, 9, &e));
  EXPECT_NEAR(e.major_m, 6.0, kTolerance);
  EXPECT_NEAR(e.minor_m, 2.0, kTolerance);
  EXPECT_NEAR(std::fabs(e.angle_rad), M_PI / 2, kTolerance);
  EXPECT_FALSE(twoSigmaEllipse(NAN, 0, 1, &e));
  EXPECT_FALSE(twoSigmaEllipse(1, 2, 1, &e));  // eigenvalues 3 and -1: not a covariance
}

TEST(Frame, MapsDataToPixelsWithYUp) {
  Frame f;
  f.left_px = 100; f.top_px = 50; f.width_px = 200; f.height_px = 100;
  f.x_lo = -10; f.x_hi = 10; f.y_lo = 0; f.y_hi = 10;  // 10 px per unit both ways
  const Point p = f.toPixel(0, 0);
  EXPECT_NEAR(p.x, 200.0, kTolerance);  // 100 + 10 * 10
  EXPECT_NEAR(p.y, 150.0, kTolerance);  // bottom edge
  const Point q = f.toPixel(10, 10);
  EXPECT_NEAR(q.x, 300.0, kTolerance);
  EXPECT_NEAR(q.y, 50.0, kTolerance);
  // Points closer than 0.7 px to the last kept one are dropped, the last one kept, NaN skipped.
  const auto pixels = toPixels(f, {0, 0.01, 0.02, NAN, 5}, {0, 0, 0, 1, 5});
  ASSERT_EQ(pixels.size(), 2u);
  EXPECT_NEAR(pixels[1].x, 250.0, kTolerance);
}

TEST(SvgWriter, EscapesTextAndBalancesGroups) {
  SvgWriter svg(10, 10);
  svg.openGroup("g");
  svg.text(1, 2, "a<b & \"c\"", TextStyle{});
  svg.closeGroup();
  const std::string out = svg.str();
  EXPECT_NE(out.find(">a&lt;b &amp; &quot;c&quot;</text>"), std::string::npos) << out;
  SvgWriter open(10, 10);
  open.openGroup();
  EXPECT_THROW(open.str(), std::logic_error);
}

}  // namespace

namespace {

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(LogLogFigure, TickLabelsAreCompact) {
  EXPECT_EQ(roam::plot::logTickLabel(1000.0), "1000");
  EXPECT_EQ(roam::plot::logTickLabel(0.01), "0.01");
  EXPECT_EQ(roam::plot::logTickLabel(1e6), "1e+06");
}

TEST(LogLogFigure, DrawsEverySeriesWithPointsOnDecades) {
  roam::plot::LogLogFigure figure;
  figure.title = "t";
  roam::plot::LogLogSeries a, b, empty;
  a.name = "a";
  a.x = {10, 100, 1000};
  a.y = {1, 0.1, 0.01};
  b.name = "b";
  b.x = {10, 1000};
  b.y = {2, 0.02};
  b.markers = false;
  empty.name = "nothing positive";
  empty.x = {-1};
  empty.y = {1};
  figure.series = {a, b, empty};
  const std::string svg = roam::plot::logLogFigureSvg(figure);
  EXPECT_EQ(count(svg, "<polyline"), 2);
  EXPECT_EQ(count(svg, "<circle"), 3);  // a's markers only
  // The x axis spans whole decades 10..1000, the y axis 0.01..10: labels at each.
  for (const char* label : {">10<", ">100<", ">1000<", ">0.01<", ">0.1<", ">1<"}) EXPECT_NE(svg.find(label), std::string::npos) << label;
}

TEST(LogLogFigure, RefusesAFigureWithNoUsablePoint) {
  roam::plot::LogLogFigure figure;
  roam::plot::LogLogSeries s;
  s.x = {0, 1};
  s.y = {1, -1};
  figure.series = {s};
  EXPECT_THROW(roam::plot::logLogFigureSvg(figure), std::invalid_argument);
}

}  // namespace
