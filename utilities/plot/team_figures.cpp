#include "team_figures.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "paths_figure.hpp"
#include "plot_axes.hpp"
#include "plot_marks.hpp"
#include "plot_series.hpp"
#include "svg_writer.hpp"
#include "team_score.hpp"

namespace roam {
namespace plot {
namespace {

const char* const kMapColour = "#333333";  // the team's map is the team's, not one robot's

// paths_figure.hpp's window over every robot's ground truth.
Box window(const ResultLog& log, const std::vector<TeamSeries>& series) {
  Box core;
  for (const auto& [robot, truth] : log.team_ground_truth)
    for (const Pose& p : truth) core.add(p.x_m, p.y_m);
  if (log.beacons)
    for (const Beacon& b : *log.beacons) core.add(b.x_m, b.y_m);
  if (core.empty()) core.add(0, 0);
  const double size = std::max({core.x_hi - core.x_lo, core.y_hi - core.y_lo, 1.0});
  const double cap = 0.5 * size;
  Box box = core;
  auto widen = [&](double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    box.add(std::clamp(x, core.x_lo - cap, core.x_hi + cap), std::clamp(y, core.y_lo - cap, core.y_hi + cap));
  };
  for (const TeamSeries& s : series) {
    for (const RobotSeries& r : s.robots)
      for (const Pose& p : r.path) widen(p.x_m, p.y_m);
    if (s.map)
      for (const Beacon& b : *s.map) widen(b.x_m, b.y_m);
  }
  const double pad = 0.04 * std::max({box.x_hi - box.x_lo, box.y_hi - box.y_lo, 1.0});
  box.x_lo -= pad; box.x_hi += pad; box.y_lo -= pad; box.y_hi += pad;
  return box;
}

std::string teamMeanLabel(double mean_m) {
  if (!std::isfinite(mean_m)) return "no matched poses";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "team mean error %.2f m", mean_m);
  return buffer;
}

// Robots by colour, then the estimators by style (with their team means when `with_means`).
std::vector<LegendItem> robotsAndStyles(const ResultLog& log, const std::vector<TeamSeries>& series, bool with_means) {
  std::vector<LegendItem> legend;
  size_t i = 0;
  for (const std::string& robot : log.robotNames()) legend.push_back({Mark::kStyledLine, seriesColour(i++), "robot " + robot, ""});
  for (size_t e = 0; e < series.size(); ++e) {
    std::string label = series[e].name + " (" + teamDashName(e);
    if (with_means) label += ", " + teamMeanLabel(series[e].mean_error_m);
    legend.push_back({Mark::kStyledLine, "#222222", label + ")", series[e].dash});
  }
  return legend;
}

void drawTeamSeries(SvgWriter& svg, const Frame& frame, const TeamSeries& s) {
  for (const RobotSeries& r : s.robots) {
    std::vector<double> xs, ys;
    for (const Pose& p : r.path) { xs.push_back(p.x_m); ys.push_back(p.y_m); }
    if (!xs.empty()) svg.polyline(toPixels(frame, xs, ys), teamPathStroke(r.colour, s.dash), "estimate", s.name + " " + r.robot);
  }
  if (!s.map) return;
  for (const Beacon& b : *s.map) {
    if (!std::isfinite(b.x_m) || !std::isfinite(b.y_m)) continue;
    const Point c = frame.toPixel(b.x_m, b.y_m);
    Ellipse e;
    if (twoSigmaEllipse(b.covariance[0], b.covariance[1], b.covariance[3], &e)) {
      const double px = frame.pixelsPerUnitX();
      svg.ellipse(c.x, c.y, std::max(e.major_m * px, 0.5), std::max(e.minor_m * px, 0.5),
                  -e.angle_rad * 180.0 / M_PI, "none", Stroke{kMapColour, 1.0, "3 2"});
    }
    drawEstimatedBeacon(svg, c.x, c.y, kMapColour);
  }
}

void drawTeamTruth(SvgWriter& svg, const Frame& frame, const ResultLog& log) {
  size_t i = 0;
  for (const auto& [robot, truth] : log.team_ground_truth) {
    std::vector<double> xs, ys;
    for (const Pose& p : truth) { xs.push_back(p.x_m); ys.push_back(p.y_m); }
    if (!xs.empty()) svg.polyline(toPixels(frame, xs, ys), teamTruthStroke(seriesColour(i)), "truth", "ground truth " + robot);
    ++i;
  }
}

void drawTeamTruthMarks(SvgWriter& svg, const Frame& frame, const ResultLog& log) {
  for (const auto& [robot, truth] : log.team_ground_truth) {
    if (truth.empty()) continue;
    const Point s = frame.toPixel(truth.front().x_m, truth.front().y_m);
    drawStart(svg, s.x, s.y);
  }
  if (!log.beacons) return;
  TextStyle id;
  id.size_px = 11;
  id.colour = "#222222";
  const double right = frame.left_px + frame.width_px, bottom = frame.top_px + frame.height_px;
  for (const Beacon& b : *log.beacons) {
    const Point c = frame.toPixel(b.x_m, b.y_m);
    if (c.x < frame.left_px || c.x > right || c.y < frame.top_px || c.y > bottom) continue;
    drawTrueBeacon(svg, c.x, c.y);
    const bool near_right = c.x > right - 24;
    id.anchor = near_right ? "end" : "start";
    svg.text(near_right ? c.x - 8 : c.x + 8, c.y - 6, std::to_string(b.id), id);
  }
}

}  // namespace

std::string teamDash(size_t index) {
  static const char* const kDashes[] = {"", "7 4", "1.5 3", "9 3 1.5 3"};
  return kDashes[index % 4];
}

const char* teamDashName(size_t index) {
  static const char* const kNames[] = {"solid", "dashed", "dotted", "dash-dot"};
  return kNames[index % 4];
}

std::vector<TeamSeries> collectTeamSeries(const ResultLog& log, const std::vector<std::string>& only) {
  std::vector<const EstimatorOutputs*> chosen;
  if (only.empty()) {
    for (const EstimatorOutputs& out : log.estimators) chosen.push_back(&out);
  }
  for (const std::string& wanted : only) {
    const EstimatorOutputs* out = log.find(wanted);
    if (!out) {
      std::string names;
      for (const EstimatorOutputs& e : log.estimators) names += (names.empty() ? "" : ", ") + e.name;
      throw std::runtime_error("--estimators: no estimator '" + wanted + "' in " + log.path +
                               " (there are: " + (names.empty() ? "none" : names) + ")");
    }
    chosen.push_back(out);
  }
  const std::vector<std::string> robots = log.robotNames();
  std::vector<TeamSeries> all;
  for (const EstimatorOutputs* out : chosen) {
    TeamSeries s;
    s.name = out->name;
    s.dash = teamDash(all.size());
    s.map = out->map;
    s.mean_error_m = scoreTeam(*out, log.team_ground_truth, false, log.beacons).unaligned.mean_m;
    for (size_t i = 0; i < robots.size(); ++i) {
      RobotSeries r;
      r.robot = robots[i];
      r.colour = seriesColour(i);
      if (const Path* path = out->robotPath(robots[i])) r.path = *path;
      r.matched = matchToGroundTruth(r.path, log.team_ground_truth.at(robots[i]));
      s.robots.push_back(std::move(r));
    }
    all.push_back(std::move(s));
  }
  return all;
}

std::string teamPathsFigureSvg(const ResultLog& log, const std::vector<TeamSeries>& series,
                               const FigureOptions& options) {
  const double width = options.width_px, height = options.height_px;
  SvgWriter svg(options.width_px, options.height_px);
  svg.rect(0, 0, width, height, "#ffffff");
  TextStyle title;
  title.size_px = 17;
  title.bold = true;
  const std::string team = "team of " + std::to_string(log.team_ground_truth.size()) + " robots";
  svg.text(kOuterPx + 6, 24, (options.title.empty() ? "" : options.title + ": ") + "paths (" + team + ")", title);

  const bool overlay = options.layout == Layout::kOverlay || series.size() <= 1;
  std::vector<LegendItem> legend = robotsAndStyles(log, series, overlay);
  legend.push_back({Mark::kBand, "#444444", "ground truth (wide band, robot's colour)", ""});
  legend.push_back({Mark::kStart, "", "start", ""});
  legend.push_back({Mark::kTrueBeacon, "", "true beacon", ""});
  legend.push_back({Mark::kEstimatedBeacon, kMapColour, "estimated beacon", ""});
  legend.push_back({Mark::kEllipse, kMapColour, "2\u03C3 ellipse", ""});
  const double header = drawLegend(&svg, legend, kOuterPx + 6, 46, width - kOuterPx);

  const Box world = window(log, series);
  const size_t panels = overlay ? 1 : series.size();
  const PanelGrid grid = panelGrid(world.x_lo, world.x_hi, world.y_lo, world.y_hi, panels, width, height, header, kOuterPx);
  const AxisLabels& labels = grid.labels;

  for (size_t i = 0; i < panels; ++i) {
    const Frame& frame = grid.frames[i];
    drawAxes(svg, frame, labels);
    const std::string clip = "panel" + std::to_string(i);
    svg.clipRect(clip, frame.left_px, frame.top_px, frame.width_px, frame.height_px);
    svg.openGroup(overlay ? "overlay" : "panel", clip);
    drawTeamTruth(svg, frame, log);
    if (overlay) {
      for (const TeamSeries& s : series) drawTeamSeries(svg, frame, s);
    } else {
      drawTeamSeries(svg, frame, series[i]);
    }
    svg.closeGroup();
    drawTeamTruthMarks(svg, frame, log);
    drawScaleBar(svg, frame);
    if (!overlay) {
      TextStyle name;
      name.size_px = 14;
      name.bold = true;
      svg.text(frame.left_px, frame.top_px - 22, series[i].name + " (" + teamDashName(i) + ")", name);
      TextStyle detail;
      detail.size_px = 12;
      detail.colour = "#444444";
      svg.text(frame.left_px, frame.top_px - 6, teamMeanLabel(series[i].mean_error_m), detail);
    }
  }
  return svg.str();
}

std::string teamErrorFigureSvg(const ResultLog& log, const std::vector<TeamSeries>& series,
                               const FigureOptions& options) {
  const double width = options.width_px, height = options.height_px;
  SvgWriter svg(options.width_px, options.height_px);
  svg.rect(0, 0, width, height, "#ffffff");
  TextStyle title;
  title.size_px = 17;
  title.bold = true;
  svg.text(kOuterPx + 6, 24,
           (options.title.empty() ? "" : options.title + ": ") + "each robot's position error against its ground truth",
           title);

  int64_t t0 = std::numeric_limits<int64_t>::max();
  for (const auto& [robot, truth] : log.team_ground_truth)
    if (!truth.empty()) t0 = std::min(t0, truth.front().utime);
  if (t0 == std::numeric_limits<int64_t>::max()) t0 = 0;
  double t_end = 1.0;
  for (const auto& [robot, truth] : log.team_ground_truth)
    for (const Pose& p : truth) t_end = std::max(t_end, 1e-6 * static_cast<double>(p.utime - t0));

  // error_figure.hpp's axis, per estimator over all its robots' curves.
  std::vector<double> top_of(series.size(), 0.0), max_error(series.size(), 0.0), means;
  for (size_t i = 0; i < series.size(); ++i) {
    for (const RobotSeries& r : series[i].robots) {
      std::vector<double> errors;
      for (const MatchedPosition& m : r.matched) errors.push_back(m.error_m());
      if (errors.empty()) continue;
      max_error[i] = std::max(max_error[i], *std::max_element(errors.begin(), errors.end()));
      top_of[i] = std::max(top_of[i], curveTop(errors));
    }
    means.push_back(series[i].mean_error_m);
  }
  double y_step = 1.0;
  const double y_top = errorAxisTop(top_of, means, height, &y_step);

  std::vector<LegendItem> legend = robotsAndStyles(log, series, true);
  for (size_t i = 0; i < series.size(); ++i)
    if (max_error[i] > y_top) legend[log.team_ground_truth.size() + i].label.insert(legend[log.team_ground_truth.size() + i].label.size() - 1, ", off the top");
  const double header = drawLegend(&svg, legend, kOuterPx + 6, 46, width - kOuterPx);

  const Frame frame = errorFrame(width, height, header, t_end, y_top);
  AxisLabels labels{"time since the team's start (s)", "position error (m)", 1, y_step};
  labels.x_step = niceStep(t_end, std::max(2, static_cast<int>(frame.width_px / 90)));
  drawAxes(svg, frame, labels);

  svg.clipRect("plot", frame.left_px, frame.top_px, frame.width_px, frame.height_px);
  svg.openGroup("curves", "plot");
  for (const TeamSeries& s : series) {
    for (const RobotSeries& r : s.robots) {
      std::vector<double> ts, es;
      for (const MatchedPosition& m : r.matched) {
        ts.push_back(1e-6 * static_cast<double>(m.utime - t0));
        es.push_back(m.error_m());
      }
      if (!ts.empty()) svg.polyline(toPixels(frame, ts, es, 0.5), teamPathStroke(r.colour, s.dash), "error", s.name + " " + r.robot);
    }
  }
  svg.closeGroup();
  return svg.str();
}

}  // namespace plot
}  // namespace roam
