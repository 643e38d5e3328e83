// trace_bench's bookmark mode: its options and command line (trace_bench.cpp; the sequence mode parses its own,
// trace_sequence.hpp).
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "math/projection.hpp"

namespace dhr::bench {

struct TraceBenchOptions {
  std::vector<std::string> scenes;
  std::vector<Extent> sizes{{640, 360}, {1280, 720}, {1832, 1920}};
  int repeat = 3;
  size_t bookmarks = 0;  // 0: all
  unsigned threads = 0;  // 0: all cores
  Extent vulkan_size{160, 120};
  bool vulkan = true;
  bool bare = true;
  bool quick = false;
  bool soft_levels = false;  // trace_layout in the scene's soft layout instead of trace()
  uint32_t lights = 0;       // more than the scene's: bench lights added (bench_lights.hpp)
  double light_range = -1.0; // their range, m (< 0: default_bench_light_range)
};

// WxH with 8..3800 per axis (room for the guard band under kMaxBufferDimension); nullopt otherwise.
std::optional<Extent> parse_trace_bench_size(const std::string& text);

// Prints the usage of both modes; returns kUsage (to stderr) or kOk (to stdout).
int trace_bench_usage(FILE* to = stderr);

// False for an unknown option or a bad value. --quick and defaults applied (the default scenes when none given).
bool parse_trace_bench_args(int argc, char** argv, TraceBenchOptions& o);

}  // namespace dhr::bench
