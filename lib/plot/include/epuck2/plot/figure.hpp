// Figures drawn by gnuplot (gnuplot-iostream), in the format the file name's extension asks for
// (.png: pngcairo, .svg: svg, .pdf: pdfcairo), staged with the run's other outputs: gnuplot draws
// into the stage's temporary file, which the stage renames onto the target only when the whole
// run succeeds (epuck2/logs/output.hpp). Every figure of the project goes through render().
#pragma once

#include <gnuplot-iostream.h>

#include <functional>
#include <optional>
#include <utility>
#include <stdexcept>
#include <string>
#include <vector>

#include "epuck2/logs/output.hpp"

namespace epuck2::plot {

enum class Format { png, svg, pdf };

/// The format named by `path`'s extension, case-insensitively: .png, .svg or .pdf; none otherwise.
std::optional<Format> format_of(const std::string& path);

/// What a figure's name may end in, for messages and --help: ".png, .svg or .pdf".
std::string accepted_extensions();

/// Why `path` cannot name a figure ("" when it can), e.g. "'fits.jpg' has the extension '.jpg';
/// a figure is drawn as .png (PNG), .svg (SVG) or .pdf (PDF), chosen by the extension".
std::string why_not_a_figure(const std::string& path);

/// A figure file name whose extension names no format we draw.
struct UnknownFormat : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

/// A paper's figure: its printed size and the size of its text. Unset (0) fields keep the
/// defaults: a figure's own canvas in pixels at 144 to the inch (a 1500-pixel PNG is 10.4 in
/// wide) and text of 11 pt. Set once per run (the CLI's --figure-size and --font-size) before
/// drawing; every figure the run draws takes it.
struct Page {
  double width_in = 0, height_in = 0;  ///< the printed size (0: the figure's default)
  double font_pt = 0;                  ///< the body text (0: 11 pt; titles keep their proportion to it)
};
void set_page(const Page& page);
const Page& page();
/// "8.5x6cm", "3.3x2.5in", "85x60mm" as a size in inches; throws std::invalid_argument saying
/// what was expected.
std::pair<double, double> parse_figure_size(const std::string& text);

/// The canvas a figure lays itself out on, in the pixels its margins are written in (text of
/// 11 pt at 144 pixels to the inch): its default size when no page is set; else the page's size
/// at the page's text size (smaller text leaves more pixels for the plot, larger text fewer).
std::pair<int, int> canvas_px(int default_width_px, int default_height_px);

/// Draws a figure: `draw` sets up and plots (the terminal, its size, font and output are set).
using Draw = std::function<void(gnuplotio::Gnuplot&)>;

/// Calls `draw` with a gnuplot whose terminal (from `path`'s extension) and output are set; the
/// figure is staged in `stage` (in place once the stage commits). Text is UTF-8 and printed as
/// given (no enhanced-text markup: file names keep their underscores). The size is in pixels for
/// PNG and SVG; a PDF page has the PNG's proportions of text to plot at 144 pixels to the inch.
/// Throws UnknownFormat for another extension (before anything is staged), std::runtime_error
/// when the folder does not exist or gnuplot produced no figure. gnuplot's messages are dropped;
/// with the environment variable EPUCK2_PLOT_STRICT set (the figure tests) any message it writes
/// (an error or a warning in the commands) is a std::runtime_error quoting it.
/// The canvas (width_px x height_px) is in design pixels: a figure with a layout of its own
/// passes canvas_px() of its default; without sizes, canvas_px(1400, 900).
void render(logs::OutputStage& stage, const std::string& path, const Draw& draw, int width_px = 0,
            int height_px = 0);

/// One figure on its own, atomically (a one-file stage).
void render(const std::string& path, const Draw& draw, int width_px = 0, int height_px = 0);

/// `text` as a gnuplot string: double-quoted, backslash and double quote escaped, a newline
/// written as the escape \n (a line break in a title); other control characters become '?'.
std::string quoted(const std::string& text);

/// A gnuplot datablock: `$name << EOD`, one line per row, `EOD`.
std::string datablock(const std::string& name, const std::vector<std::vector<double>>& rows);

/// `set multiplot layout ROWS,COLS` with one overall title placed clear of the panels' titles:
/// the panels fill [left, right] x [bottom, top] of the canvas (screen fractions), spaced by
/// `hspace` and `vspace` (screen fractions, room for each panel's title and axis labels), and the
/// overall title sits above `top`.
struct Layout {
  int rows = 1, cols = 1;
  double left = 0.07, right = 0.98, bottom = 0.08, top = 0.88;
  double hspace = 0.07, vspace = 0.10;
};
std::string multiplot(const Layout& layout, const std::string& title, int title_font_pt = 15);

/// The last plots of a multiplot: a legend alone across [left, right] x [bottom, top] (screen
/// fractions), for panels that share it, in columns of at most `max_rows` entries (filled column
/// by column) that this function lays out itself (each column a plot with a one-column key at its
/// left edge, its share of the band its longest title's share): gnuplot's own key layout drops
/// a column that its width estimate says overflows, which differs from terminal to terminal.
/// `entries` are plot elements without data, e.g. "NaN with lines lw 2 lc rgb 'red' title 'cubic'"
/// (the title last). Leaves the multiplot's settings changed (border, tics, labels): issue it
/// after the last panel.
std::string legend_band(double left, double right, double bottom, double top, const std::vector<std::string>& entries,
                        int font_pt = 11, int max_rows = 1);

/// `text` broken into lines (at spaces) that fit `width_px` canvas pixels in text of `font_pt`
/// (the layouts' 11 pt body, a title's 13 or 14; measured by text_px()), for a page narrower than
/// the figure's own canvas. Line breaks already in `text` are kept; a word wider than a line has
/// a line of its own.
std::string wrapped(const std::string& text, double width_px, double font_pt = 11);

/// The canvas pixels `text` (UTF-8, one line) takes in DejaVu Sans, the figures' font, at
/// `font_pt` (the layouts' points: the body's 11, a key's 9): each character's advance from the
/// font's metrics (DejaVuSans.ttf, hmtx table, 2048 units to the em) times the em, which the cairo
/// terminals draw at 4/3 of the points named (kDesignFont_pt). A character outside printable ASCII
/// and the few symbols the figures write counts a whole em (no narrower than it prints). For
/// deciding whether a label fits before gnuplot draws it, and for wrapped().
double text_px(const std::string& text, double font_pt = 11);

/// A page narrower than this many canvas pixels is a paper's column (8.5 cm at 8 pt is about 440
/// of them; two columns, 17.6 cm, 915 at 8 pt and 730 at 10 pt): its figures stack their panels,
/// leave their titles to the caption and put their legends below the plot.
constexpr int kNarrowCanvas_px = 700;

/// A tic step giving at most about `count` tics over [lo, hi]: 1, 2 or 5 times a power of ten
/// (at least (hi - lo) / count), finer when fewer than two tics would fall inside [lo, hi].
double tic_step(double lo, double hi, int count);

/// How many tics an axis `length_px` canvas pixels long holds with `px_per_tic` between them (at
/// least 3): about 40 on a y axis (a line of text and a gap), 60 to 90 on an x axis (a label's
/// width). gnuplot's automatic tics ignore the text's size: on a short panel they overlapped.
int tics_that_fit(double length_px, double px_per_tic);

/// On a page (--figure-size, --font-size) whose height leaves a figure's `rows` rows of panels
/// under kMinPanel_px canvas pixels each (`panel_h_px`), a warning saying how high the panels
/// print and how much height the figure needs, kept for take_figure_warnings(): a figure cannot
/// draw 16 panels legibly in 6 cm, and says so instead of drawing them silently a few pixels high.
/// (60 canvas pixels: 11 mm printed at 8 pt; the drive's panels at 8.5x14cm are 74 and read well.)
constexpr double kMinPanel_px = 60;
void check_panel_height(const std::string& figure, double panel_h_px, int rows);
/// The warnings check_panel_height() kept since the last call, oldest first (each "FIGURE: ...").
std::vector<std::string> take_figure_warnings();

/// The point type (gnuplot's pt) of robot number `robot` in the figures that tell robots apart:
/// filled circle, open square, open triangle, open circle, open diamond, open inverted triangle.
int robot_point_type(std::size_t robot);

/// An axis label: quantity and unit, "distance to the surface (mm)".
inline std::string axis_label(const std::string& quantity, const std::string& unit) { return quantity + " (" + unit + ")"; }

}  // namespace epuck2::plot
