#include "measurement_model_study.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>

#include "thin_svd.hpp"

namespace roam {
namespace {
using namespace roam::spectral;

// The q-quantile of values by linear interpolation between order statistics.
double quantile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  const double at = q * static_cast<double>(values.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(at));
  const size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (at - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

}  // namespace

double subspaceError(const sim::SimRun& run) {
  std::map<int, int> row_of;  // beacon id -> row
  for (const Beacon& b : run.beacons) row_of.emplace(b.id, static_cast<int>(row_of.size()));
  std::map<int64_t, int> column_of;  // pose utime -> column
  for (const Pose& p : run.ground_truth) column_of.emplace(p.utime, static_cast<int>(column_of.size()));
  const Eigen::Index N = static_cast<Eigen::Index>(row_of.size());
  if (N < 4) throw std::invalid_argument("subspaceError: needs >= 4 beacons");
  Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(N, static_cast<Eigen::Index>(column_of.size()));
  Eigen::MatrixXi seen = Eigen::MatrixXi::Zero(Y.rows(), Y.cols());
  for (const Range& r : run.ranges) {
    const auto column = column_of.find(r.utime);
    if (column == column_of.end()) continue;
    Y(row_of.at(r.beacon_id), column->second) = 0.5 * r.range_m * r.range_m;
    seen(row_of.at(r.beacon_id), column->second) = 1;
  }
  if (seen.minCoeff() != 1)
    throw std::invalid_argument("subspaceError: every beacon must be ranged at every pose");
  Eigen::MatrixXd C(N, 4);
  for (const Beacon& b : run.beacons)
    C.row(row_of.at(b.id)) << 0.5 * (b.x_m * b.x_m + b.y_m * b.y_m), b.x_m, b.y_m, 1.0;
  const Eigen::MatrixXd Q =
      Eigen::HouseholderQR<Eigen::MatrixXd>(C).householderQ() * Eigen::MatrixXd::Identity(N, 4);
  const Eigen::MatrixXd U = topLeftSvd(Y, 4).U;
  const Eigen::MatrixXd residual = Q - U * (U.transpose() * Q);
  return Eigen::JacobiSVD<Eigen::MatrixXd>(residual).singularValues()(0);
}

std::vector<MeasurementModelRow> runMeasurementModelStudy(const MeasurementModelStudy& study) {
  if (study.worlds < 1) throw std::invalid_argument("measurement model study: worlds must be >= 1");
  if (study.beacons < 4) throw std::invalid_argument("measurement model study: beacons must be >= 4");
  std::vector<MeasurementModelRow> rows;
  for (int steps : study.steps) {
    if (steps < 10) throw std::invalid_argument("measurement model study: steps must be >= 10, got " +
                                                std::to_string(steps));
    std::vector<double> errors;
    for (int world = 0; world < study.worlds; ++world) {
      sim::SimConfig c;
      c.seed = static_cast<uint64_t>(world + 1);  // the same worlds at every length (paired)
      c.num_steps = steps;
      c.path = sim::PathKind::kRandomWalk;
      c.area_width_m = study.area_m;
      c.area_height_m = study.area_m;
      c.num_beacons = study.beacons;
      c.schedule = sim::RangeSchedule::kEveryStepAllBeacons;
      c.range_sigma_m = study.range_sigma_m;
      errors.push_back(subspaceError(sim::simulate(c)));
    }
    MeasurementModelRow row;
    row.steps = steps;
    row.readings = static_cast<double>(study.beacons) * (steps + 1);
    double sum = 0.0;
    for (double e : errors) sum += e;
    row.mean = sum / static_cast<double>(errors.size());
    row.median = quantile(errors, 0.5);
    row.p25 = quantile(errors, 0.25);
    row.p75 = quantile(errors, 0.75);
    rows.push_back(row);
  }
  return rows;
}

double logLogSlopeOfMedian(const std::vector<MeasurementModelRow>& rows) {
  if (rows.size() < 2) throw std::invalid_argument("logLogSlopeOfMedian: needs >= 2 rows");
  Eigen::VectorXd x(rows.size()), y(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    x(static_cast<Eigen::Index>(i)) = std::log(rows[i].readings);
    // The median over worlds: a few worlds whose path is still nearly degenerate (small gamma)
    // dominate the mean at every length and hide the rate.
    y(static_cast<Eigen::Index>(i)) = std::log(rows[i].median);
  }
  const Eigen::VectorXd xc = x.array() - x.mean(), yc = y.array() - y.mean();
  return xc.dot(yc) / xc.dot(xc);
}

}  // namespace roam
