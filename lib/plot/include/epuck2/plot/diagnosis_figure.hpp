// The diagnosis figure (epuck2-fit diagnose --plot FILE): the residuals, measured minus simulated,
// before the findings (the recalibrated base model) and after them, one panel per measured
// quantity (drive: the ToF in mm and the wheel encoders in steps; camera: the column and the row
// in pixels), against the covariate the verdict names (Report::covariates). A continuous
// covariate gives a scatter with the means of equal-count bins; a category (log, sensor, axis,
// channel) gives labelled strips, before and after side by side, points jittered sideways, and
// their means. Before and after share the panel's y scale; residuals beyond it are drawn at its
// edge and counted in the legend. The format follows the file name's extension.
#pragma once

#include <string>
#include <vector>

#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/logs/output.hpp"

namespace epuck2::plot {

/// A log column's axis label from its name's unit suffix: "temperature_c" -> "temperature (°C)",
/// "height_m" -> "height (mm)" (a column in metres is drawn in mm, as every distance of the
/// figures); a name without a known suffix -> "NAME (as logged: no unit in its name)".
std::string column_label(const std::string& name);

/// Stages the figure in `stage` (in place once it commits). `log_names` label the logs (the
/// `log` covariate's categories), in the order the diagnosis read them; `log_robots` (the same
/// order, optional) name each log's robot: logs of several robots give each robot its marker,
/// named in the legend.
void diagnosis_figure(logs::OutputStage& stage, const std::string& path, const diagnose::Report& report,
                      const std::vector<std::string>& log_names, const std::vector<std::string>& log_robots = {});

}  // namespace epuck2::plot
