#include "svg_writer.hpp"

#include <cstdio>
#include <stdexcept>

namespace roam {
namespace plot {
namespace {

std::string num(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2f", value);
  std::string text = buffer;
  while (text.back() == '0') text.pop_back();  // "12.50" -> "12.5", "3.00" -> "3"
  if (text.back() == '.') text.pop_back();
  return text == "-0" ? "0" : text;
}

}  // namespace

SvgWriter::SvgWriter(int width_px, int height_px) : width_px_(width_px), height_px_(height_px) {}

std::string SvgWriter::escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

void SvgWriter::strokeAttributes(const Stroke& stroke) {
  body_ << " stroke=\"" << escape(stroke.colour) << "\"";
  if (stroke.colour == "none") return;
  body_ << " stroke-width=\"" << num(stroke.width_px) << "\"";
  if (!stroke.dash.empty()) body_ << " stroke-dasharray=\"" << escape(stroke.dash) << "\"";
  if (stroke.opacity < 1.0) body_ << " stroke-opacity=\"" << num(stroke.opacity) << "\"";
}

void SvgWriter::rect(double x, double y, double w, double h, const std::string& fill, const Stroke& stroke) {
  body_ << "<rect x=\"" << num(x) << "\" y=\"" << num(y) << "\" width=\"" << num(w) << "\" height=\"" << num(h)
        << "\" fill=\"" << escape(fill) << "\"";
  strokeAttributes(stroke);
  body_ << "/>\n";
}

void SvgWriter::line(double x1, double y1, double x2, double y2, const Stroke& stroke) {
  body_ << "<line x1=\"" << num(x1) << "\" y1=\"" << num(y1) << "\" x2=\"" << num(x2) << "\" y2=\"" << num(y2)
        << "\"";
  strokeAttributes(stroke);
  body_ << "/>\n";
}

void SvgWriter::polyline(const std::vector<Point>& points, const Stroke& stroke, const std::string& css_class,
                         const std::string& title) {
  body_ << "<polyline";
  if (!css_class.empty()) body_ << " class=\"" << escape(css_class) << "\"";
  body_ << " fill=\"none\" stroke-linejoin=\"round\" stroke-linecap=\"round\"";
  strokeAttributes(stroke);
  body_ << " points=\"";
  for (size_t i = 0; i < points.size(); ++i) body_ << (i ? " " : "") << num(points[i].x) << "," << num(points[i].y);
  body_ << "\"";
  if (title.empty()) {
    body_ << "/>\n";
  } else {
    body_ << "><title>" << escape(title) << "</title></polyline>\n";
  }
}

void SvgWriter::circle(double cx, double cy, double r, const std::string& fill, const Stroke& stroke) {
  body_ << "<circle cx=\"" << num(cx) << "\" cy=\"" << num(cy) << "\" r=\"" << num(r) << "\" fill=\""
        << escape(fill) << "\"";
  strokeAttributes(stroke);
  body_ << "/>\n";
}

void SvgWriter::ellipse(double cx, double cy, double rx, double ry, double rotate_deg, const std::string& fill,
                        const Stroke& stroke) {
  body_ << "<ellipse cx=\"0\" cy=\"0\" rx=\"" << num(rx) << "\" ry=\"" << num(ry) << "\" transform=\"translate("
        << num(cx) << " " << num(cy) << ") rotate(" << num(rotate_deg) << ")\" fill=\"" << escape(fill) << "\"";
  strokeAttributes(stroke);
  body_ << "/>\n";
}

void SvgWriter::polygon(const std::vector<Point>& points, const std::string& fill, const Stroke& stroke) {
  body_ << "<polygon points=\"";
  for (size_t i = 0; i < points.size(); ++i) body_ << (i ? " " : "") << num(points[i].x) << "," << num(points[i].y);
  body_ << "\" fill=\"" << escape(fill) << "\"";
  strokeAttributes(stroke);
  body_ << "/>\n";
}

void SvgWriter::text(double x, double y, const std::string& content, const TextStyle& style) {
  body_ << "<text x=\"" << num(x) << "\" y=\"" << num(y) << "\" font-size=\"" << num(style.size_px)
        << "\" fill=\"" << escape(style.colour) << "\"";
  if (style.anchor != "start") body_ << " text-anchor=\"" << escape(style.anchor) << "\"";
  if (style.bold) body_ << " font-weight=\"bold\"";
  if (style.rotate_deg != 0.0)
    body_ << " transform=\"rotate(" << num(style.rotate_deg) << " " << num(x) << " " << num(y) << ")\"";
  body_ << ">" << escape(content) << "</text>\n";
}

void SvgWriter::clipRect(const std::string& clip_id, double x, double y, double w, double h) {
  defs_ << "<clipPath id=\"" << escape(clip_id) << "\"><rect x=\"" << num(x) << "\" y=\"" << num(y)
        << "\" width=\"" << num(w) << "\" height=\"" << num(h) << "\"/></clipPath>\n";
}

void SvgWriter::openGroup(const std::string& css_class, const std::string& clip_id) {
  body_ << "<g";
  if (!css_class.empty()) body_ << " class=\"" << escape(css_class) << "\"";
  if (!clip_id.empty()) body_ << " clip-path=\"url(#" << escape(clip_id) << ")\"";
  body_ << ">\n";
  ++open_groups_;
}

void SvgWriter::closeGroup() {
  if (open_groups_ == 0) throw std::logic_error("SvgWriter::closeGroup without openGroup");
  body_ << "</g>\n";
  --open_groups_;
}

std::string SvgWriter::str() const {
  if (open_groups_ != 0) throw std::logic_error("SvgWriter::str with an open group");
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" << width_px_ << "\" height=\""
      << height_px_ << "\" viewBox=\"0 0 " << width_px_ << " " << height_px_
      << "\" font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\">\n";
  const std::string defs = defs_.str();
  if (!defs.empty()) out << "<defs>\n" << defs << "</defs>\n";
  out << body_.str() << "</svg>\n";
  return out.str();
}

}  // namespace plot
}  // namespace roam
