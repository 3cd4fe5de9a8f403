#include "roam/estimation/rotation_about_start.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace roam {
namespace estimation {

StartRotation fitRotationAboutStart(const std::vector<std::array<double, 2>>& solved_m,
                                    const std::vector<std::array<double, 2>>& reference_m,
                                    const std::vector<double>& step_m, double window_m) {
  const size_t n = solved_m.size();
  if (reference_m.size() != n || (n > 0 && step_m.size() + 1 != n))
    throw std::invalid_argument("fitRotationAboutStart: " + std::to_string(n) + " solved positions, " +
                                std::to_string(reference_m.size()) + " reference positions and " +
                                std::to_string(step_m.size()) + " steps (want n, n, n - 1)");
  StartRotation out;
  double dot = 0.0, cross = 0.0;
  for (size_t k = 1; k < n && out.travelled_m <= window_m; ++k) {
    out.travelled_m += step_m[k - 1];
    const double px = solved_m[k][0] - solved_m[0][0], py = solved_m[k][1] - solved_m[0][1];
    const double dx = reference_m[k][0] - reference_m[0][0], dy = reference_m[k][1] - reference_m[0][1];
    dot += px * dx + py * dy;
    cross += px * dy - py * dx;
  }
  out.defined = dot != 0.0 || cross != 0.0;
  if (out.defined) out.angle_rad = std::atan2(cross, dot);
  return out;
}

}  // namespace estimation
}  // namespace roam
