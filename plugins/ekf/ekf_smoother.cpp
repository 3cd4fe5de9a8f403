#include "ekf_smoother.hpp"

#include <stdexcept>
#include <string>

#include "roam/estimation/motion_model.hpp"

namespace roam {
namespace ekf {
namespace {

// Backwards, the state can only shrink (states are appended going forwards): the adjoint of the
// appended states is dropped. (Grown with zeros only from the empty start of the pass.)
void fitTo(int n, Eigen::VectorXd* lambda, Eigen::MatrixXd* Lambda) {
  const int old = static_cast<int>(lambda->size());
  if (old == n) return;
  const int kept = std::min(old, n);
  Eigen::VectorXd l = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(n, n);
  l.head(kept) = lambda->head(kept);
  L.topLeftCorner(kept, kept) = Lambda->topLeftCorner(kept, kept);
  *lambda = std::move(l);
  *Lambda = std::move(L);
}

void backwards(const SmootherOperation& op, Eigen::VectorXd* lambda, Eigen::MatrixXd* Lambda) {
  if (op.kind == SmootherOperation::Kind::kRemove) {
    fitTo(static_cast<int>(op.kept.size()), lambda, Lambda);
    Eigen::VectorXd l = Eigen::VectorXd::Zero(op.size_before);
    Eigen::MatrixXd L = Eigen::MatrixXd::Zero(op.size_before, op.size_before);
    l(op.kept) = *lambda;
    L(op.kept, op.kept) = *Lambda;
    *lambda = std::move(l);
    *Lambda = std::move(L);
    return;
  }
  if (op.kind == SmootherOperation::Kind::kUpdate) {
    fitTo(static_cast<int>(op.H.cols()), lambda, Lambda);
    // lambda- = lambda+ + H' (S^-1 v - K' lambda+);
    // Lambda- = H' S^-1 H + (I - K H)' Lambda+ (I - K H)
    //         = Lambda+ - H' K' Lambda+ - Lambda+ K H + H' (K' Lambda+ K + S^-1) H.
    const Eigen::VectorXd r = op.y - op.K.transpose() * (*lambda);
    const Eigen::MatrixXd LK = (*Lambda) * op.K;
    const Eigen::MatrixXd HtKtL = op.H.transpose() * LK.transpose();
    const Eigen::MatrixXd inner = op.K.transpose() * LK + op.S_inverse;
    *Lambda += op.H.transpose() * inner * op.H - HtKtL - HtKtL.transpose();
    *lambda += op.H.transpose() * r;
  } else {
    fitTo(static_cast<int>(op.A.cols()), lambda, Lambda);
    // F = I + E D with E selecting the pose rows and D = A - [I 0]:
    // F' lambda = lambda + D' lambda_p; F' Lambda F = Lambda + Lambda_:p D + D' Lambda_p: + D' Lambda_pp D.
    Eigen::MatrixXd D = op.A;
    D.leftCols(3) -= Eigen::Matrix3d::Identity();
    const Eigen::Vector3d lambda_p = lambda->head(3);
    const Eigen::MatrixXd Dt_L = D.transpose() * Lambda->topRows(3);
    const Eigen::Matrix3d Lambda_pp = Lambda->topLeftCorner(3, 3);
    *Lambda += Dt_L + Dt_L.transpose() + D.transpose() * Lambda_pp * D;
    *lambda += D.transpose() * lambda_p;
  }
  *Lambda = 0.5 * (*Lambda + Lambda->transpose());
}

}  // namespace

size_t memoryBytes(const SmootherNode& node) {
  size_t values = static_cast<size_t>(node.pose_rows.size());
  for (const SmootherOperation& op : node.before)
    values += static_cast<size_t>(op.A.size() + op.H.size() + op.K.size() + op.S_inverse.size() + op.y.size()) +
              op.kept.size() / 2;  // ints: half a double each
  return values * sizeof(double) + node.before.size() * sizeof(SmootherOperation);
}

Path smoothPath(const Path& path, const std::vector<SmootherNode>& nodes,
                const std::vector<SmootherOperation>& trailing, size_t first) {
  if (nodes.size() != path.size())
    throw std::logic_error("ekf smoother: " + std::to_string(nodes.size()) + " nodes for " +
                           std::to_string(path.size()) + " poses");
  Path smoothed = path;
  Eigen::VectorXd lambda;
  Eigen::MatrixXd Lambda;
  for (auto op = trailing.rbegin(); op != trailing.rend(); ++op) backwards(*op, &lambda, &Lambda);
  for (size_t k = nodes.size(); k-- > first;) {
    const SmootherNode& node = nodes[k];
    fitTo(static_cast<int>(node.pose_rows.cols()), &lambda, &Lambda);
    const Eigen::Vector3d pose = node.pose + node.pose_rows * lambda;
    Eigen::Matrix3d cov = node.pose_rows.leftCols(3) - node.pose_rows * Lambda * node.pose_rows.transpose();
    cov = 0.5 * (cov + cov.transpose());
    Pose& out = smoothed[k];
    out.x_m = pose.x();
    out.y_m = pose.y();
    out.heading_rad = wrapAngle(pose.z());
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) out.covariance[3 * r + c] = cov(r, c);
    for (auto op = node.before.rbegin(); op != node.before.rend(); ++op) backwards(*op, &lambda, &Lambda);
  }
  return smoothed;
}

}  // namespace ekf
}  // namespace roam
