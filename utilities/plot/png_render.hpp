// SVG to PNG with rsvg-convert (Debian: librsvg2-bin), found on PATH and run without a shell.
#pragma once

#include <string>

namespace roam {
namespace plot {

// The first executable `name` in the folders of $PATH, or "" if there is none.
std::string findOnPath(const std::string& name);

// Renders `svg_path` to `png_path` at exactly width x height pixels. Throws std::runtime_error
// with a clear message when rsvg-convert is missing or fails.
void renderPng(const std::string& svg_path, const std::string& png_path, int width_px, int height_px);

}  // namespace plot
}  // namespace roam
