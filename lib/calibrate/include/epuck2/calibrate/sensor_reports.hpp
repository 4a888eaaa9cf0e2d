// Each sensor calibration's two outputs, beside its result type (sensors.hpp): the coefficient
// file (docs/coefficient-files.md) and the human report the CLI prints. One file per kind
// (lib/calibrate/src/<kind>_report.cpp); the pieces every kind shares are in report_json.hpp and
// report_text.hpp. Neither decides whether a fit is good enough to write: the caller checks that
// first (the CLI: exit 1, or a warning under --accept-misfit, added to the fit's `warnings`).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/fit/least_squares.hpp"
#include "epuck2/models/kinds.hpp"
#include "epuck2/logs/log.hpp"

namespace epuck2::calibrate {

/// The model a fit gives (lib/models kinds.hpp): the fitted coefficients, what the calibration
/// holds fixed (the plug-in's ranges), each sensor's reading noise; the proximity's from the fit
/// to the maxima (`means`: the fit to the means, the file's second curve). What the coefficient
/// file's model sections are written from (lib/coefficients calibration_model_json).
models::sensors::ProximityModel model_of(const ProximityFit& f, bool means = false);
models::sensors::LightModel model_of(const LightFit& f);
models::sensors::GroundModel model_of(const GroundFit& f);
models::sensors::CameraModel model_of(const CameraFit& f);
models::sensors::DriveModel model_of(const DriveFit& f);

/// The fit's parameters with their standard errors, named as in the file's `parameters` (the
/// means' `mean_a`..., ground's `gain[0]`..., the camera's derived `aperture_deg`): what
/// add_robots compares the robots by.
std::vector<fit::ParameterEstimate> robot_estimates(const ProximityFit& f);
std::vector<fit::ParameterEstimate> robot_estimates(const LightFit& f);
std::vector<fit::ParameterEstimate> robot_estimates(const GroundFit& f);
std::vector<fit::ParameterEstimate> robot_estimates(const CameraFit& f);
std::vector<fit::ParameterEstimate> robot_estimates(const DriveFit& f);

/// The kind's coefficient file for a fit of `logs` (their paths are its `sources`): the model
/// sections by lib/coefficients (calibration_model_json of model_of(f)), the report fields around
/// them. Throws NoUsableFit when a channel's reading noise could not be measured (measured_noise).
nlohmann::json coefficient_json(const ProximityFit& f, const std::vector<logs::Log>& logs);
nlohmann::json coefficient_json(const LightFit& f, const std::vector<logs::Log>& logs);
nlohmann::json coefficient_json(const GroundFit& f, const std::vector<logs::Log>& logs);
nlohmann::json coefficient_json(const CameraFit& f, const std::vector<logs::Log>& logs);
nlohmann::json coefficient_json(const DriveFit& f, const std::vector<logs::Log>& logs);

/// The kind's human report (what `epuck2-fit KIND` prints without --json).
std::string report_text(const ProximityFit& f);
std::string report_text(const LightFit& f);
std::string report_text(const GroundFit& f);
std::string report_text(const CameraFit& f);
std::string report_text(const DriveFit& f);

}  // namespace epuck2::calibrate
