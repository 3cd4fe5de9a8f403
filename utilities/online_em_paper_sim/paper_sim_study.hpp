// The Monte-Carlo study of Le Corff, Fort & Moulines 2011, Sec. 4.1 (paper_sim_world.hpp): runs the
// online EM SLAM (N = 100 particles, prior kernel, multinomial ancestors, sampled mixture
// indicators, gamma = t^-0.8, the bicycle model and the paper's noise) on independent draws of
// odometry and observations along one true path, and collects per run the error of the estimated
// path (the weighted particle mean) and map at chosen times: the data of the paper's Fig. 2
// boxplots, and the mean estimated path and map of its Fig. 1.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "online_em_config.hpp"
#include "paper_sim_world.hpp"

namespace roam {
namespace paper_sim {

// The online EM core (plugins/online_em) lives in roam::online_em.
using online_em::OnlineEmConfig;

struct StudyOptions {
  int runs = 50;
  int steps = kPaperSteps;
  int particles = 100;
  uint64_t seed = 1;                              // run r uses data seed `seed + r` and filter seed too
  std::vector<int> times = {100, 250, 500, 1000, kPaperSteps};  // steps at which errors are taken
  // A run has diverged (lost track) if its position error ever exceeds this: a third of the
  // route's 72 m width. Frame drift alone (a rotated map, the path following it) stays below.
  double diverged_m = 20.0;
  // Mixture indicators: "sampled" (Algorithm 1: drawn per particle from the prior) or "marginal"
  // (Rao-Blackwellised: summed out in the weight, posterior probabilities in the statistic).
  std::string indicators = "sampled";
  std::FILE* progress = nullptr;                  // one line per run when set
};

// The estimator's configuration for the paper's setting.
OnlineEmConfig paperConfig(int particles, uint64_t seed, const std::string& indicators = "sampled");

struct RunResult {
  std::vector<double> x_error_m, y_error_m;  // true - estimated, at each of StudyOptions::times
  std::vector<double> map_error_m;           // mean |estimated - true| over initialised landmarks
  std::vector<double> aligned_map_error_m;   // the same after the best rigid fit (the map's shape)
  double max_position_error_m = 0.0;         // over the whole run
  bool diverged = false;
  Path path;  // the estimated path (steps + 1 poses)
  Map map;    // the final map
};

struct Study {
  StudyOptions options;
  Path truth;
  Map true_map;
  std::vector<RunResult> runs;
  Path mean_path;  // over the runs, per step
  Map mean_map;    // over the runs that initialised each landmark
};

Study runStudy(const StudyOptions& options);

// Linear-interpolation quantile (q in [0, 1]) of values (not empty).
double quantile(std::vector<double> values, double q);

struct Quantiles {
  double min = 0, q25 = 0, median = 0, q75 = 0, max = 0;
};
Quantiles quantiles(const std::vector<double>& values);

// Column `time_index` of a per-run series over all runs.
std::vector<double> column(const Study& study, std::vector<double> RunResult::*series, size_t time_index);

}  // namespace paper_sim
}  // namespace roam
