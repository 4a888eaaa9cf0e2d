// PNG figures drawn by gnuplot (gnuplot-iostream, pngcairo terminal), written atomically: gnuplot
// draws into a temporary file that is renamed onto the target once gnuplot has finished.
#pragma once

#include <gnuplot-iostream.h>

#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <unistd.h>

namespace epuck2::plot {

/// Calls `draw` with a gnuplot whose terminal and output are set; `draw` sets up and plots.
/// Throws std::runtime_error when gnuplot produced no image.
inline void render_png(const std::string& path, const std::function<void(gnuplotio::Gnuplot&)>& draw,
                       int width_px = 1400, int height_px = 900) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(dir)) throw std::runtime_error(path + ": the folder " + dir.string() + " does not exist");
  const fs::path tmp = dir / ("." + target.filename().string() + ".tmp." + std::to_string(::getpid()));
  {
    gnuplotio::Gnuplot gp("gnuplot -persist 2>/dev/null");
    gp << "set terminal pngcairo size " << width_px << "," << height_px << " enhanced font 'DejaVu Sans,11'\n";
    gp << "set output '" << tmp.string() << "'\n";
    draw(gp);
    gp << "unset output\n";
    gp << "exit\n";
  }  // the destructor closes the pipe and waits for gnuplot
  std::error_code ec;
  if (!fs::exists(tmp, ec) || fs::file_size(tmp, ec) == 0) {
    fs::remove(tmp, ec);
    throw std::runtime_error(path + ": gnuplot did not draw the figure (is gnuplot-nox installed?)");
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot rename the figure into place");
  }
}

}  // namespace epuck2::plot
