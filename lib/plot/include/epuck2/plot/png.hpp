// PNG figures drawn by gnuplot (gnuplot-iostream, pngcairo terminal), staged with the run's other
// outputs: gnuplot draws into the stage's temporary file, which the stage renames onto the target
// only when the whole run succeeds (epuck2/logs/output.hpp).
#pragma once

#include <gnuplot-iostream.h>

#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>

#include "epuck2/logs/output.hpp"

namespace epuck2::plot {

/// Calls `draw` with a gnuplot whose terminal and output are set; `draw` sets up and plots. The
/// figure is staged in `stage` (in place once the stage commits). Throws std::runtime_error when
/// the folder does not exist or gnuplot produced no image.
inline void render_png(logs::OutputStage& stage, const std::string& path,
                       const std::function<void(gnuplotio::Gnuplot&)>& draw, int width_px = 1400,
                       int height_px = 900) {
  namespace fs = std::filesystem;
  const std::string tmp = stage.reserve(path);
  std::string quoted;  // a gnuplot single-quoted string: '' stands for '
  for (char c : tmp) quoted += c == '\'' ? std::string("''") : std::string(1, c);
  {
    gnuplotio::Gnuplot gp("gnuplot -persist 2>/dev/null");
    gp << "set terminal pngcairo size " << width_px << "," << height_px << " enhanced font 'DejaVu Sans,11'\n";
    gp << "set output '" << quoted << "'\n";
    draw(gp);
    gp << "unset output\n";
    gp << "exit\n";
  }  // the destructor closes the pipe and waits for gnuplot
  std::error_code ec;
  if (!fs::exists(tmp, ec) || fs::file_size(tmp, ec) == 0)
    throw std::runtime_error(path + ": gnuplot did not draw the figure (is gnuplot-nox installed?)");
}

/// One figure on its own, atomically (a one-file stage).
inline void render_png(const std::string& path, const std::function<void(gnuplotio::Gnuplot&)>& draw,
                       int width_px = 1400, int height_px = 900) {
  logs::OutputStage stage;
  render_png(stage, path, draw, width_px, height_px);
  stage.commit();
}

}  // namespace epuck2::plot
