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
#include "epuck2/logs/log.hpp"

namespace epuck2::calibrate {

/// The kind's coefficient file for a fit of `logs` (their paths are its `sources`). Throws
/// NoUsableFit when a channel's reading noise could not be measured (add_noise).
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
