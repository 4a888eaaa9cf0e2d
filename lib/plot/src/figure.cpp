#include "epuck2/plot/figure.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>

#include <unistd.h>

namespace epuck2::plot {

namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// The pixel canvas as a PDF page: a figure's pixels are laid out for gnuplot's 11 pt text as
// pngcairo draws it. Measured on the drive figure (a title's width against the page's), a
// pdfcairo page shows the same proportions of text to plot at 72 canvas pixels to the inch with
// 11 pt text, or at 144 with 5.5 pt: the default page is width_px / 144 inches (1500 px: 10.4 in)
// with the fonts at half size. (The 144 measured first held only for that 10.4 in page with text
// twice the size: every PDF then had its text overflow the layout.)
constexpr double kPixelsPerInch = 144.0;
/// Canvas pixels per printed inch at which the layout's text is 11 pt.
constexpr double kDesignPixelsPerInch = 72.0;
/// The text size the layouts are written for, as printed: every figure names an 11 pt font, which
/// gnuplot's cairo terminals (pngcairo, pdfcairo) draw at 4/3 of its size (pango's 96 dpi against
/// the page's 72; measured: pdftotext -bbox on an 8.5x6cm page asked for 8 pt gave text boxes 12.4 pt
/// high, 10.7 pt text at DejaVu Sans' 1.164 em from descent to ascent, and 12.6 pt for a ',13' title) and the svg terminal, with its
/// fontscale 1.35, alike. So the design's text prints at 11 x 4/3 = 14.67 pt at 72 canvas pixels to
/// the inch, and --font-size 8 asks for fonts scaled by 8 / 14.67 to print at 8 pt.
constexpr double kDesignFont_pt = 11.0 * 4.0 / 3.0;
/// A PNG drawn for a page (--figure-size or --font-size) has this resolution.
constexpr double kPagePngDpi = 300.0;
/// A page with a size but no --font-size: text of this size.
constexpr double kPageFont_pt = 9.0;

Page g_page;

bool paged() { return g_page.width_in > 0 || g_page.font_pt > 0; }

/// The printed text size: a page's; without one, what the default PDF page gives the design's text.
double printed_font_pt() {
  if (g_page.font_pt > 0) return g_page.font_pt;
  if (g_page.width_in > 0) return kPageFont_pt;
  return kDesignFont_pt * kDesignPixelsPerInch / kPixelsPerInch;  // 7.3 pt printed on the default page (5.5 pt named)
}

/// The terminal for a canvas of width_px x height_px (design pixels). Without a page: a PNG or SVG
/// of exactly the canvas, a PDF of canvas / 144 inches. With one: the page's printed size, every
/// font (the body's and the titles' ',14') scaled by fontscale, so titles keep their proportion.
std::string terminal(Format format, int width_px, int height_px) {
  const double font = printed_font_pt();
  const double scale = font / kDesignFont_pt;  // printed points per design point
  // The printed size: the page's own (not the canvas's, which is rounded to whole pixels), else
  // the canvas at the pixels per inch its text size gives.
  const double per_in = kDesignPixelsPerInch / scale;
  const double w_in = g_page.width_in > 0 ? g_page.width_in : width_px / per_in;
  const double h_in = g_page.height_in > 0 ? g_page.height_in : height_px / per_in;
  char buf[320];
  switch (format) {
    case Format::png:
      // On a page the markers scale with the text, as the PDF's (at 300 dpi they were drawn at the
      // screen's size: a third of a millimetre, the robots' markers not told apart), and a line of
      // width 1 is pdfcairo's half point (0.5 x 300 / 72 pixels), not one pixel (0.08 mm).
      if (paged())
        std::snprintf(buf, sizeof buf,
                      "set terminal pngcairo size %d,%d noenhanced font 'DejaVu Sans,11' fontscale %.4f pointscale %.4f linewidth %.4f background rgb 'white'\n",
                      static_cast<int>(std::lround(w_in * kPagePngDpi)), static_cast<int>(std::lround(h_in * kPagePngDpi)),
                      kPagePngDpi / per_in, kPagePngDpi / per_in, 0.5 * kPagePngDpi / 72.0);
      else
        std::snprintf(buf, sizeof buf,
                      "set terminal pngcairo size %d,%d noenhanced font 'DejaVu Sans,11' background rgb 'white'\n", width_px,
                      height_px);
      break;
    case Format::svg:
      // svg's type is smaller than pngcairo's at the same size (measured: x1.33-1.36 to match).
      // A page is 96 px to the inch (the SVG pixel), so it prints at its size.
      if (paged())
        std::snprintf(buf, sizeof buf,
                      "set terminal svg size %d,%d noenhanced font 'DejaVu Sans,11' fontscale %.4f background rgb 'white'\n",
                      static_cast<int>(std::lround(w_in * 96)), static_cast<int>(std::lround(h_in * 96)), 1.35 * 96 / per_in);
      else
        std::snprintf(buf, sizeof buf,
                      "set terminal svg size %d,%d noenhanced font 'DejaVu Sans,11' fontscale 1.35 background rgb 'white'\n",
                      width_px, height_px);
      break;
    case Format::pdf:
      // Markers scale with the text on a page (pdfcairo draws them at a fixed size otherwise: on an
      // 8.5 cm page they were as large as the text's capitals).
      std::snprintf(buf, sizeof buf,
                    "set terminal pdfcairo size %.3fin,%.3fin noenhanced font 'DejaVu Sans,11' fontscale %.4f pointscale %.4f background rgb 'white'\n",
                    w_in, h_in, scale, paged() ? scale : 1.0);
      break;
  }
  return buf;
}

/// The svg terminal draws a marker `ps` times 4.5 SVG pixels whatever the page (it has no
/// pointscale): on an 8.5 cm page at 8 pt the markers printed twice the PDF's, as large as the
/// text's capitals. On a page every marker of the SVG at `path` (a `<use xlink:href='#gpPt…'`
/// with its `scale(S)`) is scaled by `factor`, as pdfcairo's pointscale scales the PDF's.
void scale_svg_markers(const std::string& path, double factor) {
  std::string svg;
  {
    std::ifstream in(path, std::ios::binary);
    std::stringstream all;
    all << in.rdbuf();
    svg = all.str();
  }
  std::string out;
  out.reserve(svg.size());
  const std::string use = "<use xlink:href='#gpPt", scale = "scale(";
  std::size_t from = 0;
  for (std::size_t at = svg.find(use); at != std::string::npos; at = svg.find(use, at + 1)) {
    const std::size_t end = svg.find('>', at), s = svg.find(scale, at);
    if (s == std::string::npos || s > end) continue;
    const std::size_t number = s + scale.size(), close = svg.find(')', number);
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", std::atof(svg.c_str() + number) * factor);
    out.append(svg, from, number - from).append(buf);
    from = close;
  }
  out.append(svg, from, std::string::npos);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << out;
}

}  // namespace

void set_page(const Page& page) { g_page = page; }
const Page& page() { return g_page; }

std::pair<double, double> parse_figure_size(const std::string& text) {
  const std::string expected = "expected WIDTHxHEIGHT with a unit, cm, mm or in (e.g. 8.5x6cm for one column, 17x10cm for two)";
  const std::size_t x = text.find_first_of("xX");
  std::size_t unit_at = text.find_first_not_of("0123456789.", x == std::string::npos ? 0 : x + 1);
  if (x == std::string::npos || x == 0 || unit_at == std::string::npos || unit_at == x + 1)
    throw std::invalid_argument("'" + text + "': " + expected);
  const std::string unit = text.substr(unit_at);
  const double per_inch = unit == "in" ? 1.0 : unit == "cm" ? 2.54 : unit == "mm" ? 25.4 : 0.0;
  if (per_inch == 0) throw std::invalid_argument("'" + text + "': unknown unit '" + unit + "'; " + expected);
  double w = 0, h = 0;
  try {
    std::size_t used = 0;
    w = std::stod(text.substr(0, x), &used);
    if (used != x) throw std::invalid_argument("");
    const std::string hs = text.substr(x + 1, unit_at - x - 1);
    h = std::stod(hs, &used);
    if (used != hs.size()) throw std::invalid_argument("");
  } catch (const std::exception&) {
    throw std::invalid_argument("'" + text + "': " + expected);
  }
  w /= per_inch;
  h /= per_inch;
  // A figure between a stamp (1 in) and a poster page (40 in).
  if (!(w >= 1.0 && w <= 40.0 && h >= 1.0 && h <= 40.0))
    throw std::invalid_argument("'" + text + "': each side must lie between 1 in (2.54 cm) and 40 in");
  return {w, h};
}

std::pair<int, int> canvas_px(int default_width_px, int default_height_px) {
  if (!paged()) return {default_width_px, default_height_px};
  // Design pixels per printed inch at the page's text size; a side the page leaves open keeps the
  // default page's printed size.
  const double per_in = kDesignPixelsPerInch * kDesignFont_pt / printed_font_pt();
  const double w_in = g_page.width_in > 0 ? g_page.width_in : default_width_px / kPixelsPerInch;
  const double h_in = g_page.height_in > 0 ? g_page.height_in : default_height_px / kPixelsPerInch;
  return {static_cast<int>(std::lround(w_in * per_in)), static_cast<int>(std::lround(h_in * per_in))};
}

std::optional<Format> format_of(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".png") return Format::png;
  if (ext == ".svg") return Format::svg;
  if (ext == ".pdf") return Format::pdf;
  return std::nullopt;
}

std::string accepted_extensions() { return ".png, .svg or .pdf"; }

std::string why_not_a_figure(const std::string& path) {
  if (format_of(path)) return "";
  const std::string ext = std::filesystem::path(path).extension().string();
  return "'" + path + "' " + (ext.empty() ? std::string("has no extension") : "has the extension '" + ext + "'") +
         "; a figure is drawn as .png (PNG), .svg (SVG) or .pdf (PDF), chosen by the file name's extension";
}

std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '\\' || c == '"') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    // Other control characters cannot reach gnuplot's command line intact: shown as '?'.
    out += static_cast<unsigned char>(c) < 0x20 ? '?' : c;
  }
  return out + "\"";
}

std::string datablock(const std::string& name, const std::vector<std::vector<double>>& rows) {
  std::ostringstream os;
  os.precision(10);
  os << '$' << name << " << EOD\n";
  for (const auto& r : rows) {
    for (std::size_t i = 0; i < r.size(); ++i) os << (i ? " " : "") << r[i];
    os << '\n';
  }
  os << "EOD\n";
  return os.str();
}

std::string multiplot(const Layout& l, const std::string& title, int title_font_pt) {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "set multiplot layout %d,%d title %s font ',%d' margins screen %.4f,%.4f,%.4f,%.4f spacing screen %.4f,%.4f\n",
                l.rows, l.cols, quoted(title).c_str(), title_font_pt, l.left, l.right, l.bottom, l.top, l.hspace, l.vspace);
  return buf;
}

std::string wrapped(const std::string& text, double width_px, double font_pt) {
  std::string out, line, word;
  auto flush_word = [&]() {
    if (word.empty()) return;
    if (!line.empty() && text_px(line + " " + word, font_pt) > width_px) {
      out += line + "\n";
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
    word.clear();
  };
  for (char c : text) {
    if (c == ' ') {
      flush_word();
    } else if (c == '\n') {
      flush_word();
      out += line + "\n";
      line.clear();
    } else {
      word += c;
    }
  }
  flush_word();
  return out + line;
}

double text_px(const std::string& text, double font_pt) {
  // DejaVu Sans' advance widths (units of 1/2048 em) for ' ' (32) to '~' (126), read from the
  // hmtx table of /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf (fonts-dejavu-core 2.37).
  static constexpr unsigned short kAscii[95] = {
      651,  821,  942,  1716, 1303, 1946, 1597, 563,  799,  799,  1024, 1716, 651,  739,  651,  690,  1303, 1303, 1303,
      1303, 1303, 1303, 1303, 1303, 1303, 1303, 690,  690,  1716, 1716, 1716, 1087, 2048, 1401, 1405, 1430, 1577, 1294,
      1178, 1587, 1540, 604,  604,  1343, 1141, 1767, 1532, 1612, 1235, 1612, 1423, 1300, 1251, 1499, 1401, 2025, 1403,
      1251, 1403, 799,  690,  799,  1716, 1024, 1024, 1255, 1300, 1126, 1300, 1260, 721,  1300, 1298, 569,  569,  1186,
      569,  1995, 1298, 1253, 1300, 1300, 842,  1067, 803,  1298, 1212, 1675, 1212, 1212, 1075, 1303, 690,  1303, 1716};
  double units = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 32 && c < 127) units += kAscii[c - 32];
    else if ((c & 0xC0) != 0x80) units += 2048;  // the first byte of any other character: an em
  }
  return units / 2048.0 * font_pt * 4.0 / 3.0;
}

double tic_step(double lo, double hi, int count) {
  const double raw = (hi - lo) / std::max(1, count);
  if (!(raw > 0) || !std::isfinite(raw)) return 1;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  double step = 10 * p;
  for (double m : {5.0, 2.0, 1.0})
    if (m * p >= raw) step = m * p;
  // At least two tics inside [lo, hi] (a scale with one labelled tic cannot be read): a finer
  // step of the same series (…, 10, 5, 2, 1, 0.5, …) until there are.
  auto inside = [&](double d) { return std::floor(hi / d) - std::ceil(lo / d) + 1; };
  for (int k = 0; k < 6 && inside(step) < 2; ++k) {
    const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-9));
    step *= mantissa > 4.5 ? 0.4 : 0.5;  // 5 -> 2, 2 -> 1, 1 -> 0.5
  }
  return step;
}

int tics_that_fit(double length_px, double px_per_tic) {
  return std::max(3, static_cast<int>(length_px / px_per_tic));
}

namespace {
std::vector<std::string> g_warnings;
}

void check_panel_height(const std::string& figure, double panel_h_px, int rows) {
  if (!paged() || panel_h_px >= kMinPanel_px || rows < 1) return;
  // Canvas pixels to printed millimetres: the layouts' text is 11 pt at kDesignPixelsPerInch.
  const double per_in = kDesignPixelsPerInch * kDesignFont_pt / printed_font_pt();
  const double mm_per_px = 25.4 / per_in;
  const double need_mm = (kMinPanel_px - panel_h_px) * rows * mm_per_px;
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "%s: the page leaves its %d row%s of panels %.0f mm high each (%s): give the figure about %.0f mm more "
                "height (--figure-size)",
                figure.c_str(), rows, rows == 1 ? "" : "s", std::max(0.0, panel_h_px * mm_per_px),
                panel_h_px > 0 ? "too small to read" : "no room at all", std::ceil(need_mm));
  g_warnings.emplace_back(buf);
}

std::vector<std::string> take_figure_warnings() {
  std::vector<std::string> out;
  out.swap(g_warnings);
  return out;
}

int robot_point_type(std::size_t robot) {
  static const int kMarkers[] = {7, 4, 8, 6, 12, 10};
  return kMarkers[robot % 6];
}

namespace {

/// The title an entry of legend_band() shows: what follows its last " title ", unquoted.
std::string entry_title(const std::string& entry) {
  const std::size_t at = entry.rfind(" title ");
  if (at == std::string::npos) return "";
  std::string t = entry.substr(at + 7);
  if (t.size() >= 2 && (t.front() == '\'' || t.front() == '"')) t = t.substr(1, t.size() - 2);
  return t;
}

/// Characters of `text` as printed (a UTF-8 sequence is one).
std::size_t printed_length(const std::string& text) {
  std::size_t n = 0;
  for (unsigned char c : text) n += (c & 0xC0) != 0x80;
  return n;
}

}  // namespace

std::string legend_band(double left, double right, double /*bottom*/, double top, const std::vector<std::string>& entries,
                        int font_pt, int max_rows) {
  // The columns are laid out here, not by gnuplot: gnuplot sizes a key's columns by its own
  // estimate of the text's width, which differs between terminals (the svg terminal's is about
  // 1.4x the drawn text), and centres a key wider than the band on the band, so that its first
  // column fell off the canvas (the drive SVG at 8.5x14cm lost "forward", "backwards" and
  // "standing still"). Each column is a plot of its own with a one-column key at the column's
  // left edge; a column's share of the band is its longest title's share (plus the sample's).
  // The plot behind a column reaches the canvas's foot (it draws nothing): gnuplot wraps a key
  // taller than its plot into a second column.
  const std::size_t n = entries.size();
  if (n == 0) return "";
  const std::size_t rows = std::max<std::size_t>(1, std::min<std::size_t>(n, static_cast<std::size_t>(std::max(1, max_rows))));
  const std::size_t cols = (n + rows - 1) / rows;
  std::vector<double> weight(cols, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    weight[i / rows] = std::max(weight[i / rows], 7.0 + static_cast<double>(printed_length(entry_title(entries[i]))));
  double total = 0;
  for (double w : weight) total += w;
  std::string out;
  double x = left;
  for (std::size_t c = 0; c < cols; ++c) {
    const double w = (right - left) * weight[c] / total;
    char buf[640];
    std::snprintf(buf, sizeof buf,
                  "set multiplot next\nset lmargin at screen %.4f\nset rmargin at screen %.4f\nset bmargin at screen %.4f\n"
                  "set tmargin at screen %.4f\nunset border\nunset xtics\nunset ytics\nunset x2tics\nunset y2tics\n"
                  "unset title\nunset xlabel\nunset ylabel\nunset grid\nunset xzeroaxis\nunset label\nunset arrow\n"
                  "set xrange [0:1]\nset yrange [0:1]\n"
                  "set key at screen %.4f,%.4f left top vertical maxcols 1 Left reverse samplen 4 spacing 1.2 width 0 font ',%d'\n",
                  x, std::min(right, x + w), 0.0, top, x, top, font_pt);
    out += buf;
    out += "plot ";
    for (std::size_t i = c * rows; i < std::min(n, (c + 1) * rows); ++i) out += (i == c * rows ? "" : ", ") + entries[i];
    out += "\n";
    x += w;
  }
  return out;
}

void render(logs::OutputStage& stage, const std::string& path, const Draw& draw, int width_px, int height_px) {
  namespace fs = std::filesystem;
  const std::optional<Format> format = format_of(path);
  if (!format) throw UnknownFormat(why_not_a_figure(path));
  if (width_px <= 0 || height_px <= 0) std::tie(width_px, height_px) = canvas_px(1400, 900);
  const std::string tmp = stage.reserve(path);
  // gnuplot's own messages: dropped, or with EPUCK2_PLOT_STRICT set (the figure tests) an error.
  const bool strict = std::getenv("EPUCK2_PLOT_STRICT") != nullptr;
  static int figures = 0;
  const fs::path messages = fs::temp_directory_path() / ("epuck2-gnuplot-" + std::to_string(::getpid()) + "-" +
                                                         std::to_string(++figures) + ".txt");
  std::string messages_text;  // a shell word: single-quoted
  for (char c : messages.string()) messages_text += c == '\'' ? std::string("'\\''") : std::string(1, c);
  // With EPUCK2_PLOT_SCRIPT_DIR naming a folder, every command and datum sent to gnuplot is also
  // kept there as NAME.gp (NAME: the figure's file name), to restyle a figure by hand or to check
  // what it draws (the figure tests read the curves and points from it). Its `set output` names
  // the staged temporary: change it before running the script.
  std::string command = strict ? "gnuplot 2>'" + messages_text + "'" : std::string("gnuplot 2>/dev/null");
  if (const char* dir = std::getenv("EPUCK2_PLOT_SCRIPT_DIR"); dir != nullptr && *dir != '\0') {
    std::error_code dir_ec;
    if (!fs::is_directory(dir, dir_ec))
      throw std::runtime_error(path + ": EPUCK2_PLOT_SCRIPT_DIR '" + dir + "' is not a folder (the figure's gnuplot script is kept there)");
    std::string script;  // a shell word: single-quoted
    for (char c : (fs::path(dir) / (fs::path(path).filename().string() + ".gp")).string())
      script += c == '\'' ? std::string("'\\''") : std::string(1, c);
    command = "tee '" + script + "' | " + command;
  }
  {
    gnuplotio::Gnuplot gp(command);
    gp << "set encoding utf8\n";
    gp << terminal(*format, width_px, height_px);
    std::string path_text;  // single-quoted: every byte but a newline as it is ('' stands for ')
    for (char c : tmp) path_text += c == '\'' ? std::string("''") : std::string(1, c);
    gp << "set output '" << path_text << "'\n";
    draw(gp);
    gp << "unset output\n";
    gp << "exit\n";
  }  // the destructor closes the pipe and waits for gnuplot
  std::error_code ec;
  if (strict) {
    std::ifstream in(messages);
    std::stringstream said;
    said << in.rdbuf();
    fs::remove(messages, ec);
    if (!said.str().empty()) throw std::runtime_error(path + ": gnuplot said: " + said.str());
  }
  if (!fs::exists(tmp, ec) || fs::file_size(tmp, ec) == 0)
    throw std::runtime_error(path + ": gnuplot did not draw the figure (is gnuplot-nox installed?)");
  if (*format == Format::svg && paged()) scale_svg_markers(tmp, printed_font_pt() / kDesignFont_pt);
}

void render(const std::string& path, const Draw& draw, int width_px, int height_px) {
  logs::OutputStage stage;
  render(stage, path, draw, width_px, height_px);
  stage.commit();
}

}  // namespace epuck2::plot
