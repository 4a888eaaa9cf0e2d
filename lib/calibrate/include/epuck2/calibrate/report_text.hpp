// A calibration's results as text: the lines every sensor report shares (a parameter with its
// standard error, what a fit did with the readings, its statistics and correlations, a channel's
// reading noise), written into a Text the CLI prints. The same results as JSON: report_json.hpp.
#pragma once

#include <string>
#include <vector>

#include "epuck2/calibrate/reading_noise.hpp"
#include "epuck2/fit/report.hpp"
#include "epuck2/fit/robust.hpp"

namespace epuck2::calibrate {

/// A report being written: printf-style pieces appended to one text.
class Text {
 public:
  /// Appends `format` filled as printf fills it.
  void operator()(const char* format, ...) __attribute__((format(printf, 2, 3)));
  const std::string& str() const { return text_; }

 private:
  std::string text_;
};

/// The statistics line (lmfit's conventions) for residuals in `unit`.
void write_statistics(Text& out, const fit::FitStatistics& s, const std::string& unit, const char* indent = "  ");

/// The correlations with |r| > 0.1, or that there are none.
void write_correlations(Text& out, const std::vector<fit::Correlation>& c, const char* indent = "  ");

/// The autocorrelation correction of a time series' standard errors, in words.
void write_autocorrelation(Text& out, const fit::AutocorrelationCorrection& a, const char* indent = "  ");

/// What a fit did with the readings: the loss, the censoring per rail, the outliers, the
/// statistics in `unit` (the readings' unit), the correlations, the autocorrelation correction
/// when given, the lack of fit. A reading without rails (`has_rails` false: the camera's pixels,
/// the encoders' steps) gets no rail counts and no Tobit line.
void write_handling(Text& out, const fit::RobustFit& r, const std::string& unit = "", const char* indent = "  ",
                    const fit::AutocorrelationCorrection* autocorrelation = nullptr, bool has_rails = true);

/// A channel's reading noise (the coefficient file's `noise` entry).
void write_noise(Text& out, const ReadingNoise& n);

/// What every sensor report ends with: each channel's reading noise. (The count of warnings that
/// follows is the CLI's, apps/sensor_support.hpp finish(): the file's warnings hold more than the
/// fit's, e.g. the robots' comparison.)
void write_noise_sections(Text& out, const std::vector<ReadingNoise>& channels);

/// A parameter line: value ± standard error (two significant digits, fit::format_uncertain), or
/// the reason there is none; `note` follows in parentheses; with an autocorrelation correction,
/// the corrected error beside the covariance's.
void write_parameter(Text& out, const fit::RobustFit& r, const std::string& name, const std::string& unit = "",
                     const char* indent = "  ", const std::string& note = "",
                     const fit::AutocorrelationCorrection* autocorrelation = nullptr);

}  // namespace epuck2::calibrate
