#include "batch_redundancy.hpp"

#include <ceres/crs_matrix.h>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <random>

namespace roam {
namespace spectral_batch {
namespace {

// Probes of the Hutchinson trace estimate: the variance of one probe of a group's trace is at most
// twice the group's redundancy (a block of a projector), so 32 probes give ~sqrt(2 r / 32): 2.5
// on a redundancy of 100, 2.5 %.
constexpr int kRedundancyProbes = 32;

}  // namespace

Redundancy redundancyNumbers(ceres::Problem& ceres_problem, const RedundancyGroups& groups) {
  Redundancy out;
  out.squares.assign(groups.num_groups, 0.0);
  out.redundancy.assign(groups.num_groups, 0.0);
  out.rows.assign(groups.num_groups, 0);
  // Rows: the sets' blocks first, in order, then every other block.
  std::vector<ceres::ResidualBlockId> all, ordered, grouped;
  std::vector<int> group_of;  // per grouped row
  for (size_t s = 0; s < groups.block_sets.size(); ++s) {
    for (ceres::ResidualBlockId id : groups.block_sets[s]) {
      ordered.push_back(id);
      for (int g : groups.group_of_row[s]) {
        group_of.push_back(g);
        ++out.rows[g];
      }
    }
  }
  grouped = ordered;
  std::sort(grouped.begin(), grouped.end());
  ceres_problem.GetResidualBlocks(&all);
  for (ceres::ResidualBlockId id : all)
    if (!std::binary_search(grouped.begin(), grouped.end(), id)) ordered.push_back(id);
  ceres::Problem::EvaluateOptions options;
  options.residual_blocks = ordered;
  std::vector<double> residuals;
  ceres::CRSMatrix crs;
  if (!ceres_problem.Evaluate(options, nullptr, &residuals, nullptr, &crs)) return out;
  const int grouped_rows = static_cast<int>(group_of.size());
  for (int i = 0; i < grouped_rows; ++i) out.squares[group_of[i]] += residuals[i] * residuals[i];
  const Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>> jacobian(
      crs.num_rows, crs.num_cols, static_cast<Eigen::Index>(crs.values.size()), crs.rows.data(), crs.cols.data(),
      crs.values.data());
  Eigen::SparseMatrix<double> normal = Eigen::SparseMatrix<double>(jacobian.transpose()) * jacobian;
  // Constant blocks give empty columns: a unit diagonal there leaves them decoupled.
  for (int j = 0; j < normal.cols(); ++j)
    if (normal.coeff(j, j) == 0.0) normal.coeffRef(j, j) = 1.0;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(normal);
  if (ldlt.info() != Eigen::Success) return out;
  std::mt19937 rng(20261124u);
  std::bernoulli_distribution coin(0.5);
  std::vector<double> trace(groups.num_groups, 0.0);
  Eigen::VectorXd z(crs.num_rows);
  for (int probe = 0; probe < kRedundancyProbes; ++probe) {
    for (int i = 0; i < z.size(); ++i) z[i] = coin(rng) ? 1.0 : -1.0;
    const Eigen::VectorXd y = jacobian * ldlt.solve(jacobian.transpose() * z);
    for (int i = 0; i < grouped_rows; ++i) trace[group_of[i]] += z[i] * y[i];
  }
  for (int g = 0; g < groups.num_groups; ++g)
    out.redundancy[g] = static_cast<double>(out.rows[g]) - trace[g] / kRedundancyProbes;
  out.ok = ldlt.info() == Eigen::Success;
  return out;
}

}  // namespace spectral_batch
}  // namespace roam
