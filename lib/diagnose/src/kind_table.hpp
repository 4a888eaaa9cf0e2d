// The one dispatch from a kind of log to what the diagnosis does with it (issue #19: a room per
// job, one table keyed by the kind): the file that builds its problem (kind_<kind>.cpp), its
// extended model as a coefficient file (extended_model.cpp) and its reading noise between
// replicates (reading_noise.cpp). Defined in kinds.cpp; a kind without a row is not diagnosed.
#pragma once

#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <vector>

#include "epuck2/calibrate/sensors.hpp"
#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/diagnose/extended_model.hpp"
#include "epuck2/logs/log.hpp"

namespace epuck2::diagnose::detail {

class Problem;

struct KindRow {
  logs::Kind kind;
  /// The kind's problem over its logs (kind_<kind>.cpp).
  std::unique_ptr<Problem> (*make)(const std::vector<logs::Log>& logs, const Options& options);
  /// The report's extended model as a coefficient file (coefficients::model_to_json).
  nlohmann::json (*extended)(const Report& r, std::vector<std::string>* left_out, const ModelInputs& inputs);
  /// The reading noise between the logs' replicates, as the calibration measures it; nullptr: the
  /// kind has no replicates (a battery's discharge is one run).
  calibrate::ReadingNoise (*replicate_noise)(const std::vector<logs::Log>& logs);
};

/// The row of `kind`, or nullptr.
const KindRow* kind_row(logs::Kind kind);

}  // namespace epuck2::diagnose::detail
