#include "ekf_joint_bias.hpp"

#include <algorithm>
#include <cmath>

namespace roam {
namespace ekf {
namespace {

using estimation::RangeBiasPrior;
using estimation::Sighting;

struct Item {
  const Sighting* s;
  int beacon;     // index 0..K-1
  double weight;  // 1 / (sigma^2 + position_var)
};

class JointProblem {
 public:
  JointProblem(int beacons, const RangeBiasPrior& bias)
      : k_(beacons), with_bias_(bias.estimated()), bias_(bias), n_(2 * beacons + (with_bias_ ? 2 : 0) + 1) {}
  int size() const { return n_; }
  int dbIndex() const { return n_ - 1; }
  double scale(const Eigen::VectorXd& t) const { return with_bias_ ? t(2 * k_) : bias_.scale; }
  double offset(const Eigen::VectorXd& t) const { return with_bias_ ? t(2 * k_ + 1) : bias_.offset_m; }

  double residual(const Eigen::VectorXd& t, const Item& it) const {
    const double db = t(dbIndex());
    const Eigen::Vector2d delta(t(2 * it.beacon) - it.s->x_m - it.s->dx_db * db,
                                t(2 * it.beacon + 1) - it.s->y_m - it.s->dy_db * db);
    return it.s->range_m - scale(t) * std::max(delta.norm(), 1e-9) - offset(t);
  }

  double evaluate(const std::vector<Item>& items, const Eigen::VectorXd& t, Eigen::MatrixXd* H, Eigen::VectorXd* g) const {
    const double s = scale(t), o = offset(t), db = t(dbIndex());
    double chi2 = 0.0;
    if (H) {
      H->setZero(n_, n_);
      g->setZero(n_);
    }
    for (const Item& it : items) {
      const Eigen::Vector2d delta(t(2 * it.beacon) - it.s->x_m - it.s->dx_db * db,
                                  t(2 * it.beacon + 1) - it.s->y_m - it.s->dy_db * db);
      const double d = std::max(delta.norm(), 1e-9);
      const double r = it.s->range_m - s * d - o;
      chi2 += it.weight * r * r;
      if (!H) continue;
      // A range's Jacobian has at most five non-zeros (its beacon, the range scale and offset,
      // the bias): H and g gain only their products, O(1) per range instead of O(n^2) (n = 2K + 3).
      const Eigen::Vector2d u = s * delta / d;
      int index[5] = {2 * it.beacon, 2 * it.beacon + 1, dbIndex(), 0, 0};
      double j[5] = {u.x(), u.y(), -s * (delta.x() * it.s->dx_db + delta.y() * it.s->dy_db) / d, 0.0, 0.0};
      int m = 3;
      if (with_bias_) {
        index[m] = 2 * k_;
        j[m++] = d;
        index[m] = 2 * k_ + 1;
        j[m++] = 1.0;
      }
      for (int a = 0; a < m; ++a) {
        const double wj = it.weight * j[a];
        for (int b = 0; b < m; ++b) (*H)(index[a], index[b]) += wj * j[b];
        (*g)(index[a]) += wj * r;
      }
    }
    const double wb = 1.0 / (bias_.heading_rate_bias_sigma_rad_s * bias_.heading_rate_bias_sigma_rad_s);
    chi2 += wb * db * db;
    if (H) {
      (*H)(dbIndex(), dbIndex()) += wb;
      (*g)(dbIndex()) -= wb * db;
    }
    if (with_bias_) {
      const double ws = 1.0 / (bias_.scale_sigma * bias_.scale_sigma);
      const double wo = 1.0 / (bias_.offset_sigma_m * bias_.offset_sigma_m);
      chi2 += ws * std::pow(s - bias_.scale, 2) + wo * std::pow(o - bias_.offset_m, 2);
      if (H) {
        (*H)(2 * k_, 2 * k_) += ws;
        (*H)(2 * k_ + 1, 2 * k_ + 1) += wo;
        (*g)(2 * k_) += ws * (bias_.scale - s);
        (*g)(2 * k_ + 1) += wo * (bias_.offset_m - o);
      }
    }
    return chi2;
  }

  // Gauss-Newton with step halving; false if the normal equations are singular.
  bool solve(const std::vector<Item>& items, Eigen::VectorXd* t, Eigen::MatrixXd* H, double* chi2) const {
    Eigen::VectorXd g;
    double cost = evaluate(items, *t, H, &g);
    for (int iteration = 0; iteration < 30; ++iteration) {
      Eigen::LDLT<Eigen::MatrixXd> ldlt(*H);
      if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return false;
      const Eigen::VectorXd step = ldlt.solve(g);
      double alpha = 1.0;
      bool improved = false;
      for (int half = 0; half < 10; ++half, alpha *= 0.5) {
        const Eigen::VectorXd candidate = *t + alpha * step;
        const double c = evaluate(items, candidate, nullptr, nullptr);
        if (c < cost) {
          const double gain = cost - c;
          *t = candidate;
          cost = evaluate(items, *t, H, &g);
          improved = gain > 1e-9 * std::max(1.0, cost);
          break;
        }
      }
      if (!improved) break;
    }
    *chi2 = cost;
    return true;
  }

 private:
  int k_;
  bool with_bias_;
  RangeBiasPrior bias_;
  int n_;
};

}  // namespace

JointBiasResult solveJointHeadingBias(const std::map<int, std::vector<Sighting>>& sightings,
                                      const std::map<int, estimation::MultilaterationResult>& start_solves, const RangeBiasPrior& bias,
                                      double gate, int min_ranges) {
  JointBiasResult result;
  if (bias.heading_rate_bias_sigma_rad_s <= 0.0) return result;
  std::vector<Item> all;
  std::vector<const estimation::MultilaterationResult*> starts;
  for (const auto& [id, buffer] : sightings) {
    const auto start = start_solves.find(id);
    if (start == start_solves.end() || static_cast<int>(buffer.size()) < min_ranges) continue;
    const int k = static_cast<int>(starts.size());
    starts.push_back(&start->second);
    for (const Sighting& s : buffer) all.push_back({&s, k, 1.0 / (s.sigma_m * s.sigma_m + s.position_var_m2)});
  }
  const int beacons = static_cast<int>(starts.size());
  if (beacons < 2) return result;
  const JointProblem problem(beacons, bias);
  Eigen::VectorXd t = Eigen::VectorXd::Zero(problem.size());
  for (int k = 0; k < beacons; ++k) t.segment<2>(2 * k) = starts[k]->world_m;
  if (bias.estimated()) t.segment<2>(2 * beacons) << bias.scale, bias.offset_m;
  std::vector<bool> keep(all.size(), true);
  Eigen::MatrixXd H;
  double chi2 = 0.0;
  bool solved = false;
  for (int iteration = 0; iteration < 6; ++iteration) {
    // Select by residual against the current solution, each beacon with its own robust scale.
    // First: against each beacon's own solve (its own range bias and db), so the outliers that
    // solve left out do not pull the joint one; then against the joint solution.
    std::vector<bool> selected(all.size(), false);
    const auto residual = [&](const Item& it) {
      if (solved) return problem.residual(t, it);
      const estimation::MultilaterationResult& own = *starts[it.beacon];
      const double db = own.heading_rate_bias_rad_s;
      return it.s->range_m -
             own.scale * std::hypot(own.world_m.x() - it.s->x_m - it.s->dx_db * db, own.world_m.y() - it.s->y_m - it.s->dy_db * db) -
             own.offset_m;
    };
    for (int k = 0; k < beacons; ++k) {
      std::vector<double> magnitude;
      for (const Item& it : all)
        if (it.beacon == k) magnitude.push_back(std::abs(residual(it)));
      std::nth_element(magnitude.begin(), magnitude.begin() + magnitude.size() / 2, magnitude.end());
      const double robust_sigma_m = 1.4826 * magnitude[magnitude.size() / 2];
      for (size_t i = 0; i < all.size(); ++i)
        if (all[i].beacon == k)
          selected[i] = std::abs(residual(all[i])) <= gate * std::max(robust_sigma_m, all[i].s->sigma_m);
    }
    if (solved && selected == keep) break;
    keep = selected;
    std::vector<Item> items;
    std::vector<int> per_beacon(beacons, 0);
    for (size_t i = 0; i < all.size(); ++i)
      if (keep[i]) {
        items.push_back(all[i]);
        ++per_beacon[all[i].beacon];
      }
    if (*std::min_element(per_beacon.begin(), per_beacon.end()) < min_ranges) return result;
    if (!problem.solve(items, &t, &H, &chi2)) return result;
    solved = true;
    result.sightings_used = static_cast<int>(items.size());
  }
  if (!solved) return result;
  Eigen::LDLT<Eigen::MatrixXd> ldlt(H);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return result;
  const Eigen::MatrixXd cov = ldlt.solve(Eigen::MatrixXd::Identity(problem.size(), problem.size()));
  // Widened by the reduced chi2 when the fit is worse than its noise model.
  const int dof = std::max(1, result.sightings_used - problem.size());
  const double widen = std::max(1.0, chi2 / dof);
  result.ok = true;
  result.db_rad_s = t(problem.dbIndex());
  result.db_sigma_rad_s = std::sqrt(cov(problem.dbIndex(), problem.dbIndex()) * widen);
  result.scale = problem.scale(t);
  result.offset_m = problem.offset(t);
  result.beacons = beacons;
  result.chi2 = chi2;
  result.dof = dof;
  return result;
}

}  // namespace ekf
}  // namespace roam
