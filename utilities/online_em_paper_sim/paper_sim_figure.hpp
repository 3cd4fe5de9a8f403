// The paper's Fig. 1 for roam-online-em-paper-sim: the true path and landmarks, and the mean over
// the Monte-Carlo runs of the estimated path and of the estimated map, drawn with roam-plot's
// paths figure (one overlay panel, metres, equal scales).
#pragma once

#include <string>

#include "paper_sim_study.hpp"

namespace roam {
namespace paper_sim {

constexpr int kFigureWidthPx = 1000, kFigureHeightPx = 820;

std::string figureSvg(const Study& study);

}  // namespace paper_sim
}  // namespace roam
