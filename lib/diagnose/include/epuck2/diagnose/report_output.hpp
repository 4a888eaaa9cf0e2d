// A diagnosis's report (diagnose.hpp's Report) as its two outputs, beside the result type: the
// JSON report, which doubles as a coefficient file (docs/diagnose.md, docs/coefficient-files.md),
// and the human report the CLI prints.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "epuck2/diagnose/diagnose.hpp"
#include "epuck2/diagnose/extended_model.hpp"

namespace epuck2::diagnose {

/// The JSON report of a diagnosis of the logs at `paths`, with the extended model's sections
/// (extended_model_json with `inputs`).
nlohmann::json report_json(const Report& r, const std::vector<std::string>& paths, const ModelInputs& inputs);

/// The human report; `base_name` names the model diagnosed ("The plug-in's model with the
/// coefficients given", or a coefficient file's).
std::string report_text(const Report& r, const std::string& base_name);

}  // namespace epuck2::diagnose
