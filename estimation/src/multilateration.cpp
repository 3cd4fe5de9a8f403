#include "roam/estimation/multilateration.hpp"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <cmath>

namespace roam {
namespace estimation {
namespace {

constexpr double kCauchy95 = 2.385;

struct RangeError {
  RangeError(double x_m, double y_m, double range_m, double sigma_m)
      : x_m(x_m), y_m(y_m), range_m(range_m), sigma_m(sigma_m) {}
  template <typename T>
  bool operator()(const T* beacon, T* residual) const {
    using std::sqrt;
    const T dx = beacon[0] - x_m, dy = beacon[1] - y_m;
    residual[0] = (sqrt(dx * dx + dy * dy + T(1e-18)) - range_m) / sigma_m;
    return true;
  }
  double x_m, y_m, range_m, sigma_m;
};

}  // namespace

bool multilaterateLinear(const std::vector<std::array<double, 2>>& positions_m,
                         const std::vector<double>& ranges_m, std::array<double, 2>* beacon_m) {
  const Eigen::Index n = static_cast<Eigen::Index>(positions_m.size());
  if (n < 3 || ranges_m.size() != positions_m.size()) return false;
  Eigen::Vector2d centre_m = Eigen::Vector2d::Zero();
  for (const auto& p : positions_m) centre_m += Eigen::Vector2d(p[0], p[1]);
  centre_m /= static_cast<double>(n);
  Eigen::MatrixXd a(n, 3);
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector2d p_m = Eigen::Vector2d(positions_m[i][0], positions_m[i][1]) - centre_m;
    a.row(i) << -2.0 * p_m.x(), -2.0 * p_m.y(), 1.0;
    b(i) = ranges_m[i] * ranges_m[i] - p_m.squaredNorm();
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  qr.setThreshold(1e-9);
  if (qr.rank() < 3) return false;
  const Eigen::Vector3d u = qr.solve(b);
  (*beacon_m)[0] = u.x() + centre_m.x();
  (*beacon_m)[1] = u.y() + centre_m.y();
  return std::isfinite((*beacon_m)[0]) && std::isfinite((*beacon_m)[1]);
}

bool multilaterateRobust(const std::vector<std::array<double, 2>>& positions_m,
                         const std::vector<double>& ranges_m, double sigma_m,
                         RobustMultilateration* result) {
  if (!(sigma_m > 0.0)) return false;
  std::array<double, 2> beacon{0.0, 0.0};
  if (!multilaterateLinear(positions_m, ranges_m, &beacon)) return false;
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::LossFunctionWrapper loss(nullptr, ceres::TAKE_OWNERSHIP);
  std::vector<ceres::ResidualBlockId> blocks;
  for (size_t i = 0; i < positions_m.size(); ++i)
    blocks.push_back(problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<RangeError, 1, 2>(
            new RangeError(positions_m[i][0], positions_m[i][1], ranges_m[i], sigma_m)),
        &loss, beacon.data()));
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 100;
  options.logging_type = ceres::SILENT;
  options.num_threads = 1;
  for (const double factor : {16.0, 4.0, 1.0}) {
    loss.Reset(new ceres::CauchyLoss(kCauchy95 * factor), ceres::TAKE_OWNERSHIP);
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    if (!summary.IsSolutionUsable()) return false;
  }
  result->beacon_m = beacon;
  result->cost = 0.0;
  result->inliers = 0;
  for (ceres::ResidualBlockId id : blocks) {
    double cost = 0.0, residual = 0.0;
    problem.EvaluateResidualBlock(id, true, &cost, &residual, nullptr);
    double raw_cost = 0.0;
    problem.EvaluateResidualBlock(id, false, &raw_cost, &residual, nullptr);  // the residual itself
    result->cost += cost;
    if (std::abs(residual) <= 3.0 * kCauchy95) ++result->inliers;
  }
  return std::isfinite(beacon[0]) && std::isfinite(beacon[1]);
}

}  // namespace estimation
}  // namespace roam
