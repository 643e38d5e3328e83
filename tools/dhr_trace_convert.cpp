// dhr-trace-convert: any supported head-pose trace -> the canonical dhr-trace CSV (docs/traces.md).
// Exit status: 0 converted; 1 the output could not be written; 2 bad input or bad command line.
#include <CLI/CLI.hpp>
#include "cli/finite_range.hpp"

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "cli/exit_codes.hpp"
#include "traces/pose_trace.hpp"

namespace {

constexpr int kExitWriteFailed = dhr::exit_code::kFailure;
constexpr int kExitBadInput = dhr::exit_code::kUsage;

std::string seconds_text(double s) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3f s", s);
  return buffer;
}

std::string number_text(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", v);
  return buffer;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Converts a head-pose trace (canonical dhr-trace CSV, Gul et al. 2020 HoloLens raw or interpolated, "
      "Nasrabadi et al. 2019 360-video) to the canonical dhr-trace CSV, in OpenXR's frame. "
      "Exit status: 0 converted, 1 output not written, 2 bad input or usage.",
      "dhr-trace-convert"};
  std::string input;
  std::string output;
  std::string format_name = "auto";
  double rate_hz = 0.0;
  double max_seconds = -1.0;
  std::size_t max_rows = dhr::TraceReadOptions{}.max_rows;
  bool quiet = false;
  app.add_option("IN", input, "input trace file")->required();
  app.add_option("OUT", output, "output file, canonical CSV ('-' for stdout)")->required();
  app.add_option("--format", format_name, "input format (auto detects it from the first line)")
      ->check(CLI::IsMember({"auto", "canonical", "gul2020-raw", "gul2020-interp", "nasrabadi2019"}))
      ->capture_default_str();
  app.add_option("--rate", rate_hz, "resample at this rate (Hz), e.g. 90 for playback; default: keep the rows")
      ->check(dhr::cli::FiniteRange(0.001, 10000.0));
  app.add_option("--max-seconds", max_seconds, "keep only the first S seconds")->check(CLI::NonNegativeNumber);
  app.add_option("--max-rows", max_rows, "refuse inputs with more data rows than this")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_flag("-q,--quiet", quiet, "print errors only (no summary, no warnings)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help (code 0) or the error with a hint
    return code == 0 ? 0 : kExitBadInput;
  }

  const std::optional<dhr::TraceFormat> format = dhr::parse_trace_format(format_name);
  dhr::TraceReadOptions options;
  options.max_rows = max_rows;
  const dhr::TraceReadResult read = dhr::read_pose_trace(input, format.value_or(dhr::TraceFormat::kAuto), options);
  if (!read) {
    std::fprintf(stderr, "dhr-trace-convert: %s\n", read.error.c_str());
    return kExitBadInput;
  }
  dhr::PoseTrace trace = *read.trace;
  if (!quiet) {
    for (const std::string& w : trace.warnings) std::fprintf(stderr, "dhr-trace-convert: warning: %s\n", w.c_str());
  }
  const std::size_t rows_in = trace.samples.size();
  const double duration_in = trace.duration();

  std::string provenance = "converted by dhr-trace-convert from " +
                           std::filesystem::path(input).filename().string() + " (" +
                           dhr::trace_format_name(read.format) + ")";
  if (max_seconds >= 0.0) {
    trace = dhr::truncate_trace(trace, max_seconds);
    provenance += ", first " + number_text(max_seconds) + " s";
  }
  if (rate_hz > 0.0) {
    try {
      trace = dhr::resample_trace(trace, rate_hz);
    } catch (const std::invalid_argument& e) {
      std::fprintf(stderr, "dhr-trace-convert: %s\n", e.what());
      return kExitBadInput;
    }
    provenance += ", resampled at " + number_text(rate_hz) + " Hz";
  }
  trace.comments.push_back(provenance);

  if (output == "-") {
    const std::string text = dhr::format_canonical_trace(trace);
    if (std::fwrite(text.data(), 1, text.size(), stdout) != text.size() || std::fflush(stdout) != 0) {
      std::fprintf(stderr, "dhr-trace-convert: writing to stdout failed\n");
      return kExitWriteFailed;
    }
  } else {
    std::string error;
    if (!dhr::write_pose_trace(output, trace, &error)) {
      std::fprintf(stderr, "dhr-trace-convert: %s\n", error.c_str());
      return kExitWriteFailed;
    }
  }
  if (!quiet) {
    std::fprintf(stderr, "dhr-trace-convert: %s (%s): %zu rows, %s -> %s: %zu rows, %s\n", input.c_str(),
                 dhr::trace_format_name(read.format), rows_in, seconds_text(duration_in).c_str(),
                 output == "-" ? "stdout" : output.c_str(), trace.samples.size(),
                 seconds_text(trace.duration()).c_str());
  }
  return 0;
}
