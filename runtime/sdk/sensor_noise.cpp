#include "roam/sensor_noise.hpp"

namespace roam {

void addSensorNoiseOptions(Options& o, SensorNoise* n, OdometryFloors floors) {
  o.add("odo_distance_sigma_rel", &n->odo_distance_sigma_rel, "odometry distance sigma per metre, forward and lateral").min(0.0);
  o.add("odo_distance_sigma_m", &n->odo_distance_sigma_m, "odometry distance sigma floor per step").min(0.0);
  o.add("odo_heading_sigma_rel", &n->odo_heading_sigma_rel, "heading sigma per radian turned").min(0.0);
  o.add("odo_heading_sigma_per_sqrt_m", &n->odo_heading_sigma_per_sqrt_m, "heading random walk per sqrt(metre)").min(0.0);
  o.add("odo_heading_sigma_rad", &n->odo_heading_sigma_rad, "heading sigma floor per step").min(0.0);
  o.add("range_sigma_m", &n->range_sigma_m, "range noise sigma where a range states none").min(0.0, false);
  o.add("bearing_sigma_rad", &n->bearing_sigma_rad, "bearing noise sigma, where a sensor gives bearings").min(0.0, false);
  if (floors == OdometryFloors::kPositive) {
    o.require([n] { return n->odo_distance_sigma_m > 0.0 && n->odo_heading_sigma_rad > 0.0; },
              {"odo_distance_sigma_m", "odo_heading_sigma_rad"}, "odo_distance_sigma_m > 0 and odo_heading_sigma_rad > 0");
  }
}

}  // namespace roam
