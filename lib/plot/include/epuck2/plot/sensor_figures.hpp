// The sensor calibrations' figures (epuck2-fit proximity|light|ground|camera|drive --plot FILE):
// the readings, the fitted curve and the plug-in's, from the kind's fit (epuck2/calibrate/sensors.hpp).
//  * proximity: normalised reading against distance, the per-distance min..max, means and maxima,
//    Eq. 1 fitted to the maxima and to the means, the plug-in's and the E-Puck (v1) polynomials
//    (paper Fig. 4c);
//  * light: raw reading against distance per source intensity, Eq. 2 with the fitted gamma and
//    with the plug-in's (paper Fig. 5);
//  * ground: raw reading against grey level per sensor, each sensor's line and the plug-in's;
//  * camera: the LED's image column and row against its direction, the fitted pinhole and the
//    plug-in's (two panels);
//  * drive: small multiples, the ToF against time in one panel per commanded speed, the runs
//    standing still against the obstacle's distance, the encoders of every run against the
//    commanded distance; the fit and the plug-in clipped at the rails (out-of-range codes apart).
// Logs of several robots: a marker per robot (proximity, light, ground, camera, drive), named in
// the legend.
// The format follows the file name's extension (epuck2/plot/figure.hpp).
#pragma once

#include <string>

#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/logs/output.hpp"

namespace epuck2::plot {

/// Each stages the figure in `stage` (in place once it commits).
void proximity_figure(logs::OutputStage& stage, const std::string& path, const calibrate::ProximityFit& fit);
void light_figure(logs::OutputStage& stage, const std::string& path, const calibrate::LightFit& fit);
void ground_figure(logs::OutputStage& stage, const std::string& path, const calibrate::GroundFit& fit);
void camera_figure(logs::OutputStage& stage, const std::string& path, const calibrate::CameraFit& fit);
void drive_figure(logs::OutputStage& stage, const std::string& path, const calibrate::DriveFit& fit);
/// The drive figure's legend entries for the fitted curve (its steps per metre) and the plug-in's
/// (7763.656 steps/m, no slip); `narrow`: a paper's column, short entries.
std::string drive_fit_legend(double steps_per_m, bool narrow);
std::string drive_plugin_legend(bool narrow);

}  // namespace epuck2::plot
