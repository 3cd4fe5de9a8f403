#include "roam/estimation/multilateration.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace roam {
namespace estimation {
namespace {

// Unknowns: (mx, my), (scale, offset) if estimated, then db if solved for: at most 5, so no heap
// allocation.
using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 5, 1>;
using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 5, 5>;

struct Fit {
  Vector theta;
  double chi2;
  Matrix information;  // J' W J (+ prior) at the solution
};

class Problem {
 public:
  Problem(const std::vector<Sighting>& s, const std::vector<double>& weight, const RangeBiasPrior& bias)
      : s_(s), weight_(weight), bias_(bias), with_bias_(bias.estimated()),
        with_db_(bias.heading_rate_bias_sigma_rad_s > 0.0), n_(2 + (with_bias_ ? 2 : 0) + (with_db_ ? 1 : 0)) {}

  int size() const { return n_; }
  Vector start(const Eigen::Vector2d& m) const {
    Vector theta = Vector::Zero(n_);
    theta.head<2>() = m;
    if (with_bias_) theta.segment<2>(2) << bias_.scale, bias_.offset_m;
    return theta;
  }
  double scale(const Vector& t) const { return with_bias_ ? t(2) : bias_.scale; }
  double offset(const Vector& t) const { return with_bias_ ? t(3) : bias_.offset_m; }
  double db(const Vector& t) const { return with_db_ ? t(n_ - 1) : 0.0; }

  // chi2 and, if asked, J' W J and J' W r (r = measured - predicted), priors included.
  double evaluate(const Vector& t, Matrix* JtWJ, Vector* JtWr) const {
    const double scale = this->scale(t), offset = this->offset(t), db = this->db(t);
    double chi2 = 0.0;
    if (JtWJ) {
      JtWJ->setZero(n_, n_);
      JtWr->setZero(n_);
    }
    // J' W J and J' W r summed in plain loops over the (at most 5) unknowns: Eigen's expressions at
    // a runtime size made this loop 40 % of a spectral solve's time (it places every beacon from
    // thousands of sightings). The same products in the same order: bit-identical.
    double J[5];
    double* const H = JtWJ ? JtWJ->data() : nullptr;  // n_ x n_, column-major
    double* const g = JtWJ ? JtWr->data() : nullptr;
    for (size_t i = 0; i < s_.size(); ++i) {
      const Eigen::Vector2d delta(t(0) - s_[i].x_m - s_[i].dx_db * db, t(1) - s_[i].y_m - s_[i].dy_db * db);
      const double distance_m = std::max(delta.norm(), 1e-9);
      const double r = s_[i].range_m - scale * distance_m - offset;
      chi2 += weight_[i] * r * r;
      if (!JtWJ) continue;
      J[0] = scale * delta.x() / distance_m;
      J[1] = scale * delta.y() / distance_m;
      if (with_bias_) {
        J[2] = distance_m;
        J[3] = 1.0;
      }
      if (with_db_) J[n_ - 1] = -scale * (delta.x() * s_[i].dx_db + delta.y() * s_[i].dy_db) / distance_m;
      double wJ[5];
      for (int a = 0; a < n_; ++a) wJ[a] = weight_[i] * J[a];
      for (int b = 0; b < n_; ++b)
        for (int a = 0; a < n_; ++a) H[a + b * n_] += wJ[a] * J[b];
      for (int a = 0; a < n_; ++a) g[a] += wJ[a] * r;
    }
    if (with_db_) {
      const double wb = 1.0 / (bias_.heading_rate_bias_sigma_rad_s * bias_.heading_rate_bias_sigma_rad_s);
      chi2 += wb * db * db;
      if (JtWJ) {
        (*JtWJ)(n_ - 1, n_ - 1) += wb;
        (*JtWr)(n_ - 1) -= wb * db;
      }
    }
    if (with_bias_) {
      const double ws = 1.0 / (bias_.scale_sigma * bias_.scale_sigma);
      const double wo = 1.0 / (bias_.offset_sigma_m * bias_.offset_sigma_m);
      chi2 += ws * std::pow(t(2) - bias_.scale, 2) + wo * std::pow(t(3) - bias_.offset_m, 2);
      if (JtWJ) {
        (*JtWJ)(2, 2) += ws;
        (*JtWJ)(3, 3) += wo;
        (*JtWr)(2) += ws * (bias_.scale - t(2));
        (*JtWr)(3) += wo * (bias_.offset_m - t(3));
      }
    }
    return chi2;
  }

  // Gauss-Newton with step halving.
  Fit solve(Vector t) const {
    constexpr int kMaxIterations = 100;
    constexpr double kStepTolerance = 1e-12;
    Matrix JtWJ;
    Vector JtWr;
    double chi2 = evaluate(t, &JtWJ, &JtWr);
    for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
      const Eigen::LDLT<Matrix> ldlt(JtWJ);
      if (ldlt.info() != Eigen::Success || ldlt.vectorD().minCoeff() <= 0.0) break;
      Vector step = ldlt.solve(JtWr);
      bool improved = false;
      for (int halving = 0; halving < 30; ++halving) {
        const double trial = evaluate(t + step, nullptr, nullptr);
        if (trial <= chi2) {
          t += step;
          improved = true;
          break;
        }
        step *= 0.5;
      }
      chi2 = evaluate(t, &JtWJ, &JtWr);
      if (!improved || step.norm() < kStepTolerance * std::max(1.0, t.norm())) break;
    }
    return {t, chi2, JtWJ};
  }

 private:
  const std::vector<Sighting>& s_;
  const std::vector<double>& weight_;
  RangeBiasPrior bias_;
  bool with_bias_, with_db_;
  int n_;
};

}  // namespace

MultilaterationResult multilaterate(const std::vector<Sighting>& s, const RangeBiasPrior& bias,
                                    const MultilaterationConfig& config) {
  const double scale = bias.scale, offset_m = bias.offset_m;
  MultilaterationResult result;
  result.rival_chi2 = std::numeric_limits<double>::infinity();
  if (static_cast<int>(s.size()) < std::max(config.min_ranges, 3)) return result;

  // Baseline: the diagonal of the sightings' bounding box.
  Eigen::Vector2d low(s[0].x_m, s[0].y_m), high = low, centroid = Eigen::Vector2d::Zero();
  double mean_distance_m = 0.0;
  std::vector<double> weight(s.size());
  for (size_t i = 0; i < s.size(); ++i) {
    const Eigen::Vector2d p(s[i].x_m, s[i].y_m);
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
    centroid += p / static_cast<double>(s.size());
    mean_distance_m += (s[i].range_m - offset_m) / scale / static_cast<double>(s.size());
    weight[i] = 1.0 / (s[i].sigma_m * s[i].sigma_m + scale * scale * s[i].position_var_m2);
  }
  if ((high - low).norm() < config.min_baseline_m) {
    result.status = MultilaterationResult::Status::kShortBaseline;
    return result;
  }

  // Starts: a ring at the mean distance around the centroid, plus the linear solution of
  // |m|^2 - 2 m.p_i + |p_i|^2 = d_i^2 differenced against the mean (exact for exact data when
  // the sightings are not collinear).
  std::vector<Eigen::Vector2d> starts;
  constexpr int kRingStarts = 8;
  for (int k = 0; k < kRingStarts; ++k) {
    const double angle_rad = 2.0 * M_PI * k / kRingStarts;
    starts.push_back(centroid + mean_distance_m * Eigen::Vector2d(std::cos(angle_rad), std::sin(angle_rad)));
  }
  {
    Eigen::MatrixXd A(s.size(), 2);
    Eigen::VectorXd b(s.size());
    double mean_rhs = 0.0;
    for (size_t i = 0; i < s.size(); ++i) {
      const double d = (s[i].range_m - offset_m) / scale;
      b(i) = s[i].x_m * s[i].x_m + s[i].y_m * s[i].y_m - d * d;
      mean_rhs += b(i) / static_cast<double>(s.size());
    }
    for (size_t i = 0; i < s.size(); ++i) {
      A(i, 0) = 2.0 * (s[i].x_m - centroid.x());
      A(i, 1) = 2.0 * (s[i].y_m - centroid.y());
      b(i) -= mean_rhs;
    }
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
    if (svd.singularValues()(1) > 1e-6 * svd.singularValues()(0)) starts.push_back(svd.solve(b));
  }

  const Problem problem(s, weight, bias);
  std::vector<Fit> fits;
  for (const auto& start : starts) fits.push_back(problem.solve(problem.start(start)));
  std::sort(fits.begin(), fits.end(), [](const Fit& a, const Fit& b) { return a.chi2 < b.chi2; });
  const Fit& best = fits.front();
  const Eigen::LDLT<Matrix> information(best.information);
  if (information.info() != Eigen::Success || information.vectorD().minCoeff() <= 0.0) {
    result.status = MultilaterationResult::Status::kNoSolution;
    return result;
  }
  const Matrix cov = information.solve(Matrix::Identity(problem.size(), problem.size()));
  result.world_m = best.theta.head<2>();
  // A fit worse than the noise model says (reduced chi2 > 1: biased or correlated errors, pose
  // errors) widens the covariance by the reduced chi2 (the Birge ratio squared).
  const double dof = std::max(1.0, static_cast<double>(s.size()) - 2.0);
  const double inflation = std::max(1.0, best.chi2 / dof);
  result.cov_m2 = inflation * 0.5 * (cov.topLeftCorner<2, 2>() + cov.topLeftCorner<2, 2>().transpose());
  result.scale = problem.scale(best.theta);
  result.offset_m = problem.offset(best.theta);
  result.heading_rate_bias_rad_s = problem.db(best.theta);
  result.chi2 = best.chi2;
  const double sigma_max_m = std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(result.cov_m2).eigenvalues()(1));

  // A rival is a minimum farther than max(1 m, 4 sigma) from the best one.
  const double distinct_m = std::max(1.0, 4.0 * sigma_max_m);
  for (const Fit& fit : fits) {
    if ((fit.theta.head<2>() - best.theta.head<2>()).norm() > distinct_m) {
      result.rival_chi2 = fit.chi2;
      break;
    }
  }
  // The angle the sightings span seen from the beacon: 2 pi minus the largest gap between bearings.
  std::vector<double> bearing_rad;
  const double db = result.heading_rate_bias_rad_s;
  for (const Sighting& sighting : s)
    bearing_rad.push_back(std::atan2(sighting.y_m + sighting.dy_db * db - result.world_m.y(),
                                     sighting.x_m + sighting.dx_db * db - result.world_m.x()));
  std::sort(bearing_rad.begin(), bearing_rad.end());
  double largest_gap_rad = 2.0 * M_PI - (bearing_rad.back() - bearing_rad.front());
  for (size_t i = 1; i < bearing_rad.size(); ++i)
    largest_gap_rad = std::max(largest_gap_rad, bearing_rad[i] - bearing_rad[i - 1]);
  result.angle_rad = 2.0 * M_PI - largest_gap_rad;

  if (result.rival_chi2 - result.chi2 < config.mirror_chi2) {
    result.status = MultilaterationResult::Status::kAmbiguous;
  } else if (result.angle_rad < config.min_angle_rad) {
    result.status = MultilaterationResult::Status::kNarrowAngle;
  } else if (sigma_max_m > config.max_sigma_m) {
    result.status = MultilaterationResult::Status::kPoorlyConstrained;
  } else {
    result.status = MultilaterationResult::Status::kReady;
  }
  return result;
}

}  // namespace estimation
}  // namespace roam
