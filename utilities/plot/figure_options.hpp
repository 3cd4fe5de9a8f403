// Options shared by roam-plot's figures.
#pragma once

#include <string>

namespace roam {
namespace plot {

enum class Layout { kPanels, kOverlay };

struct FigureOptions {
  int width_px = 1200;
  int height_px = 800;
  Layout layout = Layout::kPanels;
  std::string title;  // the run, e.g. "plaza1-compare"
};

}  // namespace plot
}  // namespace roam
