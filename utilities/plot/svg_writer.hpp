// SvgWriter: a small SVG 1.1 document builder — the only place roam-plot writes markup.
//
// Coordinates are pixels, origin top-left, y down (SVG's own frame); callers map metres to
// pixels themselves (plot_axes.hpp). Text is XML-escaped; numbers are written with 2 decimals,
// enough for a picture and small files. Groups nest; str() closes nothing for the caller, so an
// unbalanced openGroup/closeGroup throws std::logic_error there (a programmer error).
#pragma once

#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace roam {
namespace plot {

struct Point {
  double x = 0.0, y = 0.0;
};

struct Stroke {
  Stroke() = default;
  Stroke(std::string colour_, double width_px_, std::string dash_ = "", double opacity_ = 1.0)
      : colour(std::move(colour_)), width_px(width_px_), dash(std::move(dash_)), opacity(opacity_) {}
  std::string colour = "none";  // any SVG colour, e.g. "#0072B2"
  double width_px = 1.0;
  std::string dash;             // stroke-dasharray, e.g. "6 3"; empty: solid
  double opacity = 1.0;
};

struct TextStyle {
  double size_px = 12.0;
  std::string anchor = "start";  // start | middle | end
  std::string colour = "#222222";
  bool bold = false;
  double rotate_deg = 0.0;       // about the anchor point
};

class SvgWriter {
 public:
  SvgWriter(int width_px, int height_px);

  void rect(double x, double y, double w, double h, const std::string& fill, const Stroke& stroke = {});
  void line(double x1, double y1, double x2, double y2, const Stroke& stroke);
  // css_class and title (a tooltip, and the name tests look for) are optional.
  void polyline(const std::vector<Point>& points, const Stroke& stroke, const std::string& css_class = "",
                const std::string& title = "");
  void circle(double cx, double cy, double r, const std::string& fill, const Stroke& stroke = {});
  void ellipse(double cx, double cy, double rx, double ry, double rotate_deg, const std::string& fill,
               const Stroke& stroke);
  void polygon(const std::vector<Point>& points, const std::string& fill, const Stroke& stroke = {});
  void text(double x, double y, const std::string& content, const TextStyle& style);

  // A rectangular clip region usable by later groups as clip_id.
  void clipRect(const std::string& clip_id, double x, double y, double w, double h);
  void openGroup(const std::string& css_class = "", const std::string& clip_id = "");
  void closeGroup();

  std::string str() const;  // the whole document

  static std::string escape(const std::string& text);

 private:
  void strokeAttributes(const Stroke& stroke);
  int width_px_, height_px_;
  int open_groups_ = 0;
  std::ostringstream body_;
  std::ostringstream defs_;
};

}  // namespace plot
}  // namespace roam
