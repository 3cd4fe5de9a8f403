// Markers (true beacon, estimated beacon, start) and the legend row that explains them and the
// lines, shared by roam-plot's figures.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "svg_writer.hpp"

namespace roam {
namespace plot {

// kStyledLine: a team's path (colour, dash); kBand: a team robot's ground truth (colour).
enum class Mark { kLine, kDashedLine, kTruthLine, kTrueBeacon, kEstimatedBeacon, kEllipse, kStart, kStyledLine, kBand };

void drawTrueBeacon(SvgWriter& svg, double x, double y);
void drawEstimatedBeacon(SvgWriter& svg, double x, double y, const std::string& colour);
void drawStart(SvgWriter& svg, double x, double y);

// The ground truth's line style, and an estimate's (dashed: the odometry baseline).
Stroke truthStroke();
Stroke estimateStroke(const std::string& colour, bool dashed);
// A team's: a robot's path in its colour and the estimator's dash; a robot's ground truth.
Stroke teamPathStroke(const std::string& colour, const std::string& dash);
Stroke teamTruthStroke(const std::string& colour);

struct LegendItem {
  LegendItem() = default;
  LegendItem(Mark mark_, std::string colour_, std::string label_, std::string dash_ = "")
      : mark(mark_), colour(std::move(colour_)), label(std::move(label_)), dash(std::move(dash_)) {}
  Mark mark = Mark::kLine;
  std::string colour;
  std::string label;
  std::string dash;  // kStyledLine only
};

// Lays items out left to right from (x, y: the first row's text baseline), wrapping before
// max_x; draws them when svg is not null. Returns the baseline of the row after the last.
double drawLegend(SvgWriter* svg, const std::vector<LegendItem>& items, double x, double y, double max_x);

// A rough width of text in DejaVu Sans at size_px (for layout only).
double textWidth(const std::string& text, double size_px);

}  // namespace plot
}  // namespace roam
