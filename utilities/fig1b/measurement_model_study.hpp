// The spectral paper's Fig. 1B (Boots & Gordon 2013): the learned observation model converges as
// range readings accumulate, at the rate of its bound (Eq. 13),
//   ||sin Psi||_2 <= N c sqrt(2 log(T) / T) / gamma.
//
// Psi are the principal angles between the true observation subspace, range(C) with
// C_n = [|m_n|^2/2, m_nx, m_ny, 1], and the learned one, range(U) of the top-4 left singular
// vectors of Y (Y_nt = r_nt^2 / 2 from noisy ranges). ||sin Psi||_2 = ||(I - U U^T) Q||_2 with Q an
// orthonormal basis of range(C). Range noise adds sigma^2/2 to every entry of Y on average: a
// constant, which lies in range(C) (its last column is all ones), so the estimate is unbiased and
// the error falls as 1/sqrt(T) up to the log factor: slope about -1/2 on log-log.
//
// Worlds: random walks in a box with beacons placed at random around it (roam::sim), every beacon
// ranged at every step, the same seeds at every path length (paired comparison).
#pragma once

#include <vector>

#include "sim.hpp"

namespace roam {

struct MeasurementModelStudy {
  int worlds = 200;        // random worlds per path length (the paper: 1000)
  int beacons = 6;         // as the paper's Fig. 1A
  // Range noise enters Y as d e + e^2/2: its mean lies in range(C), but its variance d_n^2 sigma^2
  // differs per beacon, so the top eigenvectors of Y Y^T carry an O(sigma^2) bias that the
  // 1/sqrt(T) term meets after enough readings (sigma = 0.5 m levels off near 0.02 after ~10^4
  // readings). 0.1 m keeps that floor 25x lower, so the lengths below show the rate of the bound.
  double range_sigma_m = 0.1;
  double area_m = 30.0;    // the random walk's box side
  // From 400 steps on: shorter random walks barely span the plane, so the bound's eigen-gap gamma
  // is still growing with T and the error falls faster than the asymptotic rate.
  std::vector<int> steps = {400, 800, 1600, 3200, 6400};
};

struct MeasurementModelRow {
  int steps = 0;
  double readings = 0.0;  // beacons x poses
  double mean = 0.0, median = 0.0, p25 = 0.0, p75 = 0.0;  // of ||sin Psi||_2 over the worlds
};

// ||sin Psi||_2 for one run with every beacon ranged at every pose.
double subspaceError(const sim::SimRun& run);

std::vector<MeasurementModelRow> runMeasurementModelStudy(const MeasurementModelStudy& study);

// Least-squares slope of log(median) on log(readings): about -1/2 if the rate of the bound holds.
double logLogSlopeOfMedian(const std::vector<MeasurementModelRow>& rows);

}  // namespace roam
