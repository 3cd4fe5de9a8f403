// Markers (true beacon, estimated beacon, start) and the legend row that explains them and the
// lines, shared by roam-plot's figures.
#pragma once

#include <string>
#include <vector>

#include "svg_writer.hpp"

namespace roam {
namespace plot {

enum class Mark { kLine, kDashedLine, kTruthLine, kTrueBeacon, kEstimatedBeacon, kEllipse, kStart };

void drawTrueBeacon(SvgWriter& svg, double x, double y);
void drawEstimatedBeacon(SvgWriter& svg, double x, double y, const std::string& colour);
void drawStart(SvgWriter& svg, double x, double y);

// The ground truth's line style, and an estimate's (dashed: the odometry baseline).
Stroke truthStroke();
Stroke estimateStroke(const std::string& colour, bool dashed);

struct LegendItem {
  Mark mark = Mark::kLine;
  std::string colour;
  std::string label;
};

// Lays items out left to right from (x, y: the first row's text baseline), wrapping before
// max_x; draws them when svg is not null. Returns the baseline of the row after the last.
double drawLegend(SvgWriter* svg, const std::vector<LegendItem>& items, double x, double y, double max_x);

// A rough width of text in DejaVu Sans at size_px (for layout only).
double textWidth(const std::string& text, double size_px);

}  // namespace plot
}  // namespace roam
