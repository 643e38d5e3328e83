// `dhr-eval report DIR`: plots (gnuplot, SVG) and a Markdown page from DIR/results.json and DIR/run.json.
#pragma once
#include <string>

namespace dhr::eval {

// Writes DIR/*.svg (and the .dat/.gp files that make them) and DIR/report.md. Returns the exit code.
int write_report(const std::string& dir);

}  // namespace dhr::eval
