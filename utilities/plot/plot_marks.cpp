#include "plot_marks.hpp"

namespace roam {
namespace plot {

namespace {
constexpr double kLegendTextPx = 12.0;
constexpr double kLegendRowPx = 18.0;
constexpr double kSwatchPx = 24.0;
}  // namespace

void drawTrueBeacon(SvgWriter& svg, double x, double y) {
  svg.polygon({{x, y - 7}, {x + 6.5, y + 4.5}, {x - 6.5, y + 4.5}}, "#FFD400", Stroke{"#222222", 1.4});
}

void drawEstimatedBeacon(SvgWriter& svg, double x, double y, const std::string& colour) {
  const Stroke s{colour, 2.4};
  svg.line(x - 5, y - 5, x + 5, y + 5, s);
  svg.line(x - 5, y + 5, x + 5, y - 5, s);
}

void drawStart(SvgWriter& svg, double x, double y) { svg.circle(x, y, 5, "#ffffff", Stroke{"#222222", 2.0}); }

Stroke truthStroke() { return Stroke{"#444444", 4.0, "", 0.35}; }

Stroke estimateStroke(const std::string& colour, bool dashed) {
  return Stroke{colour, dashed ? 1.4 : 1.6, dashed ? "6 4" : "", 0.95};
}

Stroke teamPathStroke(const std::string& colour, const std::string& dash) { return Stroke{colour, 1.8, dash, 0.95}; }

Stroke teamTruthStroke(const std::string& colour) { return Stroke{colour, 6.0, "", 0.25}; }

double textWidth(const std::string& text, double size_px) {
  size_t chars = 0;
  for (unsigned char c : text) chars += (c & 0xC0) != 0x80;  // UTF-8 code points
  return 0.6 * size_px * static_cast<double>(chars);
}

double drawLegend(SvgWriter* svg, const std::vector<LegendItem>& items, double x, double y, double max_x) {
  const double x0 = x;
  TextStyle text;
  text.size_px = kLegendTextPx;
  for (const LegendItem& item : items) {
    const double width = kSwatchPx + 6 + textWidth(item.label, kLegendTextPx) + 18;
    if (x > x0 && x + width > max_x) {
      x = x0;
      y += kLegendRowPx;
    }
    if (svg) {
      const double mid = y - 4, right = x + kSwatchPx;
      switch (item.mark) {
        case Mark::kLine: svg->line(x, mid, right, mid, estimateStroke(item.colour, false)); break;
        case Mark::kDashedLine: svg->line(x, mid, right, mid, estimateStroke(item.colour, true)); break;
        case Mark::kTruthLine: svg->line(x, mid, right, mid, truthStroke()); break;
        case Mark::kTrueBeacon: drawTrueBeacon(*svg, x + kSwatchPx / 2, mid); break;
        case Mark::kEstimatedBeacon: drawEstimatedBeacon(*svg, x + kSwatchPx / 2, mid, item.colour); break;
        case Mark::kEllipse:
          svg->ellipse(x + kSwatchPx / 2, mid, 11, 6, 0, "none", Stroke{item.colour, 1.0, "3 2"});
          break;
        case Mark::kStart: drawStart(*svg, x + kSwatchPx / 2, mid); break;
        case Mark::kStyledLine: svg->line(x, mid, right, mid, teamPathStroke(item.colour, item.dash)); break;
        case Mark::kBand: svg->line(x, mid, right, mid, teamTruthStroke(item.colour)); break;
      }
      svg->text(x + kSwatchPx + 6, y, item.label, text);
    }
    x += width;
  }
  return y + kLegendRowPx;
}

}  // namespace plot
}  // namespace roam
