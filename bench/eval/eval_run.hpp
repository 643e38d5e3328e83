// `dhr-eval run`: loads the scene and trace, computes the ground truth once per frame, steps every
// setting's session through the same frames, and writes DIR/results.json, DIR/results.csv, DIR/run.json.
#pragma once
#include "eval_settings.hpp"

#include <string>

namespace dhr::eval {

// Returns the process exit code; one-line errors on stderr.
int run_eval(const RunOptions& options, const std::string& command_line);

}  // namespace dhr::eval
