// The priors every estimator puts on the sensors' calibration (the one-model issue: one
// calibration state with one prior set). The numbers, and why they are what they are, are in the
// SDK's roam/calibration_priors.hpp, which the self-check uses too; here they are in the
// estimation namespace, with what the estimators build from them.
#pragma once

#include <cmath>

#include "roam/calibration_priors.hpp"
#include "roam/estimation/multilateration.hpp"

namespace roam {
namespace estimation {

using roam::kBeaconOffsetPriorSigma_m;
using roam::kDistanceScalePriorSigma;
using roam::kHeadingRateBiasMaxDrift_rad;
using roam::kHeadingRateBiasPriorSigma_rad_s;
using roam::kRangeOffsetPriorSigma_m;
using roam::kRangeScalePriorSigma;

// The bias prior of a beacon's placement from a known path (multilaterate): the shared scale
// and offset, each beacon's own offset folded into the offset's sigma.
inline RangeBiasPrior rangeBiasPrior() {
  RangeBiasPrior prior;
  prior.scale = 1.0;
  prior.scale_sigma = kRangeScalePriorSigma;
  prior.offset_m = 0.0;
  prior.offset_sigma_m = std::sqrt(kRangeOffsetPriorSigma_m * kRangeOffsetPriorSigma_m +
                                   kBeaconOffsetPriorSigma_m * kBeaconOffsetPriorSigma_m);
  return prior;
}

}  // namespace estimation
}  // namespace roam
