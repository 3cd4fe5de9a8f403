#include "roam/range_fit.hpp"

#include "roam/calibration_priors.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace roam {
namespace {

struct Point {
  double x_m = 0.0, y_m = 0.0;
};

// p(t): linear in time between the poses either side of t (clamped at the ends).
Point positionAt(const Path& path, int64_t utime) {
  const auto after = std::lower_bound(path.begin(), path.end(), utime,
                                      [](const Pose& pose, int64_t t) { return pose.utime < t; });
  if (after == path.begin()) return {path.front().x_m, path.front().y_m};
  if (after == path.end()) return {path.back().x_m, path.back().y_m};
  const Pose& b = *after;
  const Pose& a = *(after - 1);
  const double span = static_cast<double>(b.utime - a.utime);
  const double f = span > 0.0 ? static_cast<double>(utime - a.utime) / span : 1.0;
  return {a.x_m + f * (b.x_m - a.x_m), a.y_m + f * (b.y_m - a.y_m)};
}

struct Observation {
  size_t index;  // in the ranges scored
  Point from;
  double range_m;
};

// The range model's calibration: r = scale |m - p| + offset_m.
struct Calibration {
  double scale = 1.0, offset_m = 0.0;
};

double distance_m(const Point& beacon, const Point& from) {
  return std::hypot(beacon.x_m - from.x_m, beacon.y_m - from.y_m);
}

double absCost(const std::vector<Observation>& obs, const Point& beacon, const Calibration& c) {
  double cost = 0.0;
  for (const auto& o : obs) cost += std::abs(c.scale * distance_m(beacon, o.from) + c.offset_m - o.range_m);
  return cost;
}

// IRLS weight of least absolute deviations: 1 / max(|e|, 1 mm).
double l1Weight(double e) { return 1.0 / std::max(std::abs(e), 1e-3); }

// A beacon's position by iteratively reweighted Gauss-Newton under least absolute deviations.
Point refine(const std::vector<Observation>& obs, Point beacon, const Calibration& c) {
  double cost = absCost(obs, beacon, c);
  for (int iteration = 0; iteration < 20; ++iteration) {
    double a00 = 0, a01 = 0, a11 = 0, g0 = 0, g1 = 0;
    for (const auto& o : obs) {
      const double dx = beacon.x_m - o.from.x_m, dy = beacon.y_m - o.from.y_m;
      const double d = std::max(std::hypot(dx, dy), 1e-9);
      const double e = c.scale * d + c.offset_m - o.range_m;
      const double w = l1Weight(e);
      const double jx = c.scale * dx / d, jy = c.scale * dy / d;
      a00 += w * jx * jx;
      a01 += w * jx * jy;
      a11 += w * jy * jy;
      g0 += w * jx * e;
      g1 += w * jy * e;
    }
    const double det = a00 * a11 - a01 * a01;
    if (!(std::abs(det) > 1e-12 * (a00 * a11 + 1e-300))) break;
    Point next{beacon.x_m - (a11 * g0 - a01 * g1) / det, beacon.y_m - (a00 * g1 - a01 * g0) / det};
    const double next_cost = absCost(obs, next, c);
    if (!(next_cost < cost)) break;
    const double moved = std::hypot(next.x_m - beacon.x_m, next.y_m - beacon.y_m);
    beacon = next;
    cost = next_cost;
    if (moved < 1e-6) break;
  }
  return beacon;
}

// Starting points: the linear least-squares solution of |m|^2 - 2 m.p = r^2 - |p|^2 where the
// positions are spread, and either side of their mean along the normal of their main axis (a
// straight run leaves the side ambiguous; both are tried).
std::vector<Point> startingPoints(const std::vector<Observation>& obs) {
  double mx = 0, my = 0, mr = 0;
  for (const auto& o : obs) {
    mx += o.from.x_m;
    my += o.from.y_m;
    mr += o.range_m;
  }
  const double n = static_cast<double>(obs.size());
  mx /= n;
  my /= n;
  mr /= n;
  double sxx = 0, sxy = 0, syy = 0, sxb = 0, syb = 0;
  for (const auto& o : obs) {
    const double x = o.from.x_m - mx, y = o.from.y_m - my;
    // Centred: 2 m.(p - mean p) = (|p|^2 - r^2) - mean(|p|^2 - r^2), with m relative to the mean.
    const double b = (x * x + y * y - o.range_m * o.range_m);
    sxx += x * x;
    sxy += x * y;
    syy += y * y;
    sxb += x * b;
    syb += y * b;
  }
  std::vector<Point> starts;
  const double det = sxx * syy - sxy * sxy;
  if (det > 1e-9 * (sxx + syy) * (sxx + syy) && det > 0.0)
    starts.push_back({mx + 0.5 * (syy * sxb - sxy * syb) / det, my + 0.5 * (sxx * syb - sxy * sxb) / det});
  // The main axis of the positions, and its normal.
  const double angle = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
  const double nx = -std::sin(angle), ny = std::cos(angle);
  starts.push_back({mx + mr * nx, my + mr * ny});
  starts.push_back({mx - mr * nx, my - mr * ny});
  return starts;
}

}  // namespace

std::vector<RangeRecord> rangesToScore(const std::vector<RangeRecord>& ranges, int64_t begin_utime,
                                       int64_t end_utime) {
  std::map<int, int> count;
  for (const auto& r : ranges)
    if (r.utime >= begin_utime && r.utime <= end_utime) ++count[r.beacon_id];
  std::vector<RangeRecord> out;
  for (const auto& r : ranges)
    if (r.utime >= begin_utime && r.utime <= end_utime && count[r.beacon_id] >= 3) out.push_back(r);
  return out;
}

namespace {

// 2x2 symmetric-or-not matrices, row-major, and what the joint step needs of them.
struct M2 {
  double a = 0, b = 0, c = 0, d = 0;  // [a b; c d]
};
M2 inverse(const M2& m) {
  const double det = m.a * m.d - m.b * m.c;
  return {m.d / det, -m.b / det, -m.c / det, m.a / det};
}
M2 times(const M2& x, const M2& y) {
  return {x.a * y.a + x.b * y.c, x.a * y.b + x.b * y.d, x.c * y.a + x.d * y.c, x.c * y.b + x.d * y.d};
}
M2 transpose(const M2& m) { return {m.a, m.c, m.b, m.d}; }
void apply(const M2& m, const double* v, double* out) {
  out[0] = m.a * v[0] + m.b * v[1];
  out[1] = m.c * v[0] + m.d * v[1];
}

// The calibration held within three sigmas of roam's priors (roam/calibration_priors.hpp; the
// offset's sigma the shared and a beacon's own together): ranges that only a scale near 0 and an
// offset near their median would explain (half of them NLOS) are not explained away.
Calibration withinPrior(Calibration c) {
  const double scale_bound = 3.0 * kRangeScalePriorSigma;
  const double offset_bound_m = 3.0 * std::hypot(kRangeOffsetPriorSigma_m, kBeaconOffsetPriorSigma_m);
  c.scale = std::clamp(c.scale, 1.0 - scale_bound, 1.0 + scale_bound);
  c.offset_m = std::clamp(c.offset_m, -offset_bound_m, offset_bound_m);
  return c;
}

double totalCost(const std::map<int, std::vector<Observation>>& by_beacon, const std::map<int, Point>& beacons,
                 const Calibration& c) {
  double cost = 0.0;
  for (const auto& [id, obs] : by_beacon) cost += absCost(obs, beacons.at(id), c);
  return cost;
}

// The range calibration and every free beacon together: IRLS Gauss-Newton on least absolute
// deviations, the beacons eliminated block by block (each couples to the calibration alone), a
// halved step where a full one does not lower the cost.
void fitTogether(const std::map<int, std::vector<Observation>>& by_beacon, const std::vector<int>& free,
                 std::map<int, Point>* beacons, Calibration* c) {
  double cost = totalCost(by_beacon, *beacons, *c);
  for (int iteration = 0; iteration < 50; ++iteration) {
    M2 s_matrix;  // the calibration's normal matrix, then its Schur complement
    double s_rhs[2] = {0, 0};
    std::map<int, M2> a_inv, coupling;
    std::map<int, std::array<double, 2>> beacon_rhs;
    for (const auto& [id, obs] : by_beacon) {
      const bool is_free = std::find(free.begin(), free.end(), id) != free.end();
      const Point& m = beacons->at(id);
      M2 a, b;
      double g[2] = {0, 0};
      for (const auto& o : obs) {
        const double dx = m.x_m - o.from.x_m, dy = m.y_m - o.from.y_m;
        const double d = std::max(std::hypot(dx, dy), 1e-9);
        const double e = c->scale * d + c->offset_m - o.range_m;
        const double w = l1Weight(e);
        const double jb[2] = {c->scale * dx / d, c->scale * dy / d}, jc[2] = {d, 1.0};
        s_matrix.a += w * jc[0] * jc[0];
        s_matrix.b += w * jc[0] * jc[1];
        s_matrix.c += w * jc[1] * jc[0];
        s_matrix.d += w * jc[1] * jc[1];
        s_rhs[0] += w * jc[0] * e;
        s_rhs[1] += w * jc[1] * e;
        if (!is_free) continue;
        a.a += w * jb[0] * jb[0];
        a.b += w * jb[0] * jb[1];
        a.c += w * jb[1] * jb[0];
        a.d += w * jb[1] * jb[1];
        b.a += w * jb[0] * jc[0];
        b.b += w * jb[0] * jc[1];
        b.c += w * jb[1] * jc[0];
        b.d += w * jb[1] * jc[1];
        g[0] += w * jb[0] * e;
        g[1] += w * jb[1] * e;
      }
      if (!is_free) continue;
      // A beacon seen along one line only: a little damping keeps its block invertible.
      const double damping = 1e-9 * (a.a + a.d) + 1e-12;
      a.a += damping;
      a.d += damping;
      const M2 ai = inverse(a);
      const M2 bt_ai = times(transpose(b), ai);
      const M2 schur = times(bt_ai, b);
      s_matrix.a -= schur.a;
      s_matrix.b -= schur.b;
      s_matrix.c -= schur.c;
      s_matrix.d -= schur.d;
      double t[2];
      apply(bt_ai, g, t);
      s_rhs[0] -= t[0];
      s_rhs[1] -= t[1];
      a_inv[id] = ai;
      coupling[id] = b;
      beacon_rhs[id] = {g[0], g[1]};
    }
    // Distances all alike do not tell scale from offset: damping holds what they cannot fix.
    const double damping = 1e-9 * (s_matrix.a + s_matrix.d) + 1e-12;
    s_matrix.a += damping;
    s_matrix.d += damping;
    double step_c[2];
    apply(inverse(s_matrix), s_rhs, step_c);
    step_c[0] = -step_c[0];
    step_c[1] = -step_c[1];
    std::map<int, Point> step_b;
    for (int id : free) {
      double bc[2], rhs[2], out[2];
      apply(coupling[id], step_c, bc);
      rhs[0] = beacon_rhs[id][0] + bc[0];
      rhs[1] = beacon_rhs[id][1] + bc[1];
      apply(a_inv[id], rhs, out);
      step_b[id] = {-out[0], -out[1]};
    }
    bool lowered = false;
    for (double f = 1.0; f > 1e-3 && !lowered; f *= 0.5) {
      const Calibration next_c = withinPrior({c->scale + f * step_c[0], c->offset_m + f * step_c[1]});
      std::map<int, Point> next_b = *beacons;
      for (int id : free) next_b[id] = {next_b[id].x_m + f * step_b[id].x_m, next_b[id].y_m + f * step_b[id].y_m};
      const double next_cost = totalCost(by_beacon, next_b, next_c);
      if (next_cost < cost) {
        const bool settled = cost - next_cost <= 1e-12 * cost + 1e-15;
        *c = next_c;
        *beacons = std::move(next_b);
        cost = next_cost;
        lowered = true;
        if (settled) return;
      }
    }
    if (!lowered) return;
  }
}

}  // namespace

namespace {

// Each range's |residual| under calibration `c`, the beacons where `beacons` puts them.
RangeFit scored(const std::map<int, std::vector<Observation>>& by_beacon, const std::map<int, Point>& beacons,
                const Calibration& c, size_t num_ranges) {
  RangeFit fit;
  double total = 0.0;
  fit.residuals_m.assign(num_ranges, 0.0);
  for (const auto& [id, obs] : by_beacon) {
    const Point& m = beacons.at(id);
    for (const auto& o : obs) {
      const double residual = std::abs(c.scale * distance_m(m, o.from) + c.offset_m - o.range_m);
      fit.residuals_m[o.index] = residual;
      total += residual;
    }
    fit.ranges += static_cast<int64_t>(obs.size());
  }
  if (fit.ranges > 0) fit.mean_abs_residual_m = total / static_cast<double>(fit.ranges);
  fit.scale = c.scale;
  fit.offset_m = c.offset_m;
  return fit;
}

}  // namespace

RangeFit rangeFit(const Path& path, const std::vector<RangeRecord>& ranges, const Map& surveyed,
                  bool fit_calibration) {
  RangeFit fit;
  if (path.empty()) return fit;
  std::map<int, std::vector<Observation>> by_beacon;
  for (size_t k = 0; k < ranges.size(); ++k) {
    const RangeRecord& r = ranges[k];
    by_beacon[r.beacon_id].push_back({k, positionAt(path, r.utime), r.range_m});
  }
  if (by_beacon.empty()) return fit;
  std::map<int, Point> beacons;
  for (const Beacon& b : surveyed)
    if (by_beacon.count(b.id)) beacons[b.id] = {b.x_m, b.y_m};
  std::vector<int> free;
  Calibration c;
  for (const auto& [id, obs] : by_beacon) {
    if (beacons.count(id)) continue;
    free.push_back(id);
    double best = -1.0;
    for (const Point& start : startingPoints(obs)) {
      const Point placed = refine(obs, start, c);
      const double cost = absCost(obs, placed, c);
      if (best < 0.0 || cost < best) {
        best = cost;
        beacons[id] = placed;
      }
    }
  }
  if (fit_calibration) fitTogether(by_beacon, free, &beacons, &c);
  return scored(by_beacon, beacons, c, ranges.size());
}

RangeFit robotRangeFit(const std::vector<Path>& paths, const std::vector<RobotRangeRecord>& ranges,
                       bool fit_calibration) {
  // Each range its own "beacon", held (never free) where the other robot is at its time.
  std::map<int, std::vector<Observation>> by_beacon;
  std::map<int, Point> beacons;
  for (size_t k = 0; k < ranges.size(); ++k) {
    const RobotRangeRecord& r = ranges[k];
    const Path& from = paths.at(static_cast<size_t>(r.robot));
    const Path& to = paths.at(static_cast<size_t>(r.other_robot));
    if (from.empty() || to.empty()) continue;
    const int id = static_cast<int>(k);
    by_beacon[id].push_back({k, positionAt(from, r.utime), r.range_m});
    beacons[id] = positionAt(to, r.utime);
  }
  Calibration c;
  if (by_beacon.empty()) return RangeFit{};
  if (fit_calibration) fitTogether(by_beacon, {}, &beacons, &c);
  return scored(by_beacon, beacons, c, ranges.size());
}

}  // namespace roam
