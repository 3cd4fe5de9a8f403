// Metric upgrade of the spectral factors (Boots & Gordon 2013, Sec. 3.1 and Appendix A).
//
// The rank-k factorisation Y = U (U^T Y) only fixes C and X up to an invertible S:
// Y = (C S^-1)(S X). Inputs here are the rank-k reconstruction of the half squared ranges
// H = (U U^T Y)[first N rows] (N beacons x T columns), H[n,t] = C_n . X_t with
//   C_n = [|m_n|^2/2, m_nx, m_ny, 1],  X_t = [1, -x_t, -y_t, |p_t|^2/2].
//
// (a) Surveyed beacons (>= 4). Fixing X_t[0] to one global value s, the rest of X_t solves the
//     linear system C_K[:,1:3] X_t[1:3] = H_K,t - s C_K[:,0] over the surveyed rows K. This is
//     well posed even when the beacons lie on a circle: then |m|^2/2 is affine in m, C_K[:,0]
//     is a combination of the other columns, and the null direction of C_K (first entry non-zero)
//     is exactly what fixing X[0] removes. Ranges scaled by kappa (UWB scale error) scale every
//     X_t by kappa^2; s is the value for which the learned states best satisfy the structure
//     s X_t[3] = (X_t[1]^2 + X_t[2]^2)/2 (a quartic in s, minimised via the roots of its
//     derivative), and positions are p_t = -X_t[1:2]/s: one global scale, not one per column.
// (b) No surveyed beacons. Find t0 with t0^T W = 1^T (W = a basis of H's row space), so that
//     X = [1; A z_t + a] with z_t = N^T W_t in R^3 (N spans t0's complement). The structure
//     X[3] = |X[1:2]|^2/2 says the points z_t lie on the quadric z^T Q z + b^T z + c = 0 with
//     Q = R^T R / 2 (R = the 2x3 block of A): lifting the quadratic term makes it linear, so
//     (Q, b, c) is the null vector of the T x 10 monomial matrix (least squares), and the rank-2
//     factorisation of Q gives R up to a 2-D orthogonal matrix and a scale. The path
//     p_t = -R z_t is then known up to a similarity (rotation, reflection, scale, translation),
//     which a least-squares fit to dead reckoning from the start pose over an early stretch fixes.
//     (Scale from odometry rather than from C's structure: ranges with a scale error would
//     otherwise scale the whole map.)
#pragma once

#include <optional>
#include <stdexcept>
#include <vector>

#include <Eigen/Dense>

namespace roam::spectral {

// The data hold too little to solve (fewer than 4 beacons ranged, no odometry, too few poses
// with every beacon interpolated) or a geometry that does not determine the solution (a path on
// one circle or line with anchor = start_pose): a property of the input, not an error of the
// estimator.
struct InsufficientData : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct BeaconUpgrade {
  Eigen::Matrix2Xd xy_m;  // 2 x T positions
  double state_scale = 1.0;  // s: the learned X[0] (= kappa^2 for ranges scaled by kappa)
};

// (a). surveyed[n] is beacon n's surveyed position, or nullopt. Throws std::runtime_error if
// fewer than 4 surveyed beacons or if they are (nearly) collinear (the configuration), and
// InsufficientData if no positive state scale fits them (the data).
BeaconUpgrade upgradeWithBeacons(const Eigen::MatrixXd& half_sq,
                                 const std::vector<std::optional<Eigen::Vector2d>>& surveyed);

// (b), first part: positions up to a similarity. Throws if the path is degenerate.
Eigen::Matrix2Xd pathUpToSimilarity(const Eigen::MatrixXd& half_sq);
// The same from every paraboloid of the pencil through the two smallest eigenvectors of the
// quadric fit (a path on two circles, a figure-8, leaves a pencil of quadrics through the learned
// states); the least-squares quadric's shape first if it is a paraboloid. Throws if none is.
std::vector<Eigen::Matrix2Xd> pathCandidatesUpToSimilarity(const Eigen::MatrixXd& half_sq);
// How far a shape is from a similarity of dead reckoning locally: in consecutive chunks of chunk_s
// the residual of a rotation-and-scale fit (best reflection) over the dead-reckoned variance,
// summed over chunks. A wrong upgrade is an affine or worse distortion of the path, which no
// local similarity undoes; the right one leaves noise only.
double localShapeMisfit(const Eigen::Matrix2Xd& shape, const Eigen::Matrix2Xd& dead_reckoned,
                        const std::vector<int64_t>& utime, double chunk_s);

// Best similarity (rotation or reflection, scale, translation) taking src onto dst.
struct Similarity {
  Eigen::Matrix2d linear = Eigen::Matrix2d::Identity();  // scale * orthogonal (det may be < 0)
  Eigen::Vector2d translation = Eigen::Vector2d::Zero();
  Eigen::Matrix2Xd apply(const Eigen::Matrix2Xd& points) const;
};
Similarity fitSimilarity(const Eigen::Matrix2Xd& src, const Eigen::Matrix2Xd& dst);

// anchor = start_pose: the similarity taking the learned shape onto dead reckoning from the start
// pose. Dead reckoning is only locally right (its heading drifts), so the scale and the
// reflection come from local rotation-and-scale fits in consecutive chunks of chunk_s along the
// whole path (drift-free: each chunk has its own rotation), and the rotation and translation
// from the first align_m of travel (distance, not time: a robot that waits at the start holds no
// direction), where dead reckoning from the start pose has not drifted yet. travelled_m[j] is
// the odometry distance from the start to column j.
Similarity alignToDeadReckoning(const Eigen::Matrix2Xd& shape, const Eigen::Matrix2Xd& dead_reckoned,
                                const std::vector<int64_t>& utime, const std::vector<double>& travelled_m,
                                double chunk_s, double align_m);

// Learned beacons: H[n,:] regressed onto [1, -x, -y, |p|^2/2]; m_n = theta[1:2] / theta[3]
// (dividing by theta[3] removes a range scale). Returns 2 x N.
Eigen::Matrix2Xd learnBeacons(const Eigen::MatrixXd& half_sq, const Eigen::Matrix2Xd& xy_m);

// Rank 7: the rows r[n,t] = (p_t - m_n) . u_t = [m_nx, m_ny, 1] . [-cos, -sin, p.u] are solved for
// per column by least squares (>= 3 non-collinear beacons); heading = atan2(sin, cos).
Eigen::VectorXd headingsFromRangeRates(const Eigen::MatrixXd& range_rate,
                                       const Eigen::Matrix2Xd& beacons_m);

}  // namespace roam::spectral
