#include "spectral_config.hpp"

namespace roam::spectral {

void addSpectralOptions(Options& o, SpectralConfig* c) {
  o.add("anchor", &c->anchor, {{"beacons", SpectralAnchor::kBeacons}, {"start_pose", SpectralAnchor::kStartPose}},
        "frame anchor: surveyed beacons or the start pose");
  o.add("rank", &c->rank, "4: positions; 7: positions and headings").oneOf({4, 7});
  o.add("mode", &c->mode, {{"batch", SpectralMode::kBatch}, {"online", SpectralMode::kOnline}},
        "batch (all at the end) or online (incremental SVD)");
  o.add("window_s", &c->window_s, "interpolation window length (s); online latency")
      .min(0.0, false);
  o.add("smooth_with_odometry", &c->smooth_with_odometry,
        "fuse the solved positions with the calibrated odometry's step displacements (frame kept)");
  o.add("calibrate_odometry", &c->calibrate_odometry,
        "estimate the odometry distance scale and gyro bias against the solution, then solve again");
  addSensorNoiseOptions(o, c, OdometryFloors::kPositive);  // its smoother weighs each step by its noise
}

}  // namespace roam::spectral
