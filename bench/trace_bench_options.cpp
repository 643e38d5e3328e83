#include "trace_bench_options.hpp"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "bench_views.hpp"
#include "cli/exit_codes.hpp"
#include "scene/light_slots.hpp"

namespace dhr::bench {

std::optional<Extent> parse_trace_bench_size(const std::string& text) {
  unsigned w = 0, h = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%ux%u%c", &w, &h, &tail) != 2 || w < 8 || h < 8 || w > 3800 || h > 3800)
    return std::nullopt;  // 3800: room for the guard band under kMaxBufferDimension
  return Extent{w, h};
}

int trace_bench_usage(FILE* to) {
  std::fprintf(to,
               "usage: trace_bench [--scene PATH]... [--sizes WxH,WxH...] [--repeat N] [--bookmarks N] "
               "[--threads N] [--vulkan-size WxH] [--no-vulkan] [--no-bare] [--quick] [--soft-levels] [--lights N] "
               "[--light-range M]\n"
               "       trace_bench --trace PATH [--trace PATH]... [--scene PATH] [--frames N] [--size WxH] "
               "[--sessions K] [--trace-start S] [--threads N]\n"
               "       [--soft-levels [--truth-every N] [--soft-history N] [--soft-hysteresis L]] [--no-shared] "
               "[--no-refresh] [--no-blocks] "
               "[--no-pairs]\n");
  return to == stderr ? exit_code::kUsage : exit_code::kOk;
}

bool parse_trace_bench_args(int argc, char** argv, TraceBenchOptions& o) {
  bool sizes_given = false, repeat_given = false, bookmarks_given = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--no-vulkan") { o.vulkan = false; continue; }
    if (a == "--no-bare") { o.bare = false; continue; }
    if (a == "--quick") { o.quick = true; continue; }
    if (a == "--soft-levels") { o.soft_levels = true; o.bare = false; continue; }
    if (i + 1 >= argc) return false;
    const std::string v = argv[++i];
    if (a == "--scene") {
      o.scenes.push_back(v);
    } else if (a == "--sizes") {
      o.sizes.clear();
      std::stringstream ss(v);
      for (std::string item; std::getline(ss, item, ',');) {
        const auto e = parse_trace_bench_size(item);
        if (!e) return false;
        o.sizes.push_back(*e);
      }
      if (o.sizes.empty()) return false;
      sizes_given = true;
    } else if (a == "--vulkan-size") {
      const auto e = parse_trace_bench_size(v);
      if (!e) return false;
      o.vulkan_size = *e;
    } else if (a == "--repeat") {
      o.repeat = std::atoi(v.c_str());
      if (o.repeat < 1 || o.repeat > 1000) return false;
      repeat_given = true;
    } else if (a == "--bookmarks") {
      const int n = std::atoi(v.c_str());
      if (n < 1) return false;
      o.bookmarks = static_cast<size_t>(n);
      bookmarks_given = true;
    } else if (a == "--threads") {
      const int n = std::atoi(v.c_str());
      if (n < 0 || n > 1024) return false;
      o.threads = static_cast<unsigned>(n);
    } else if (a == "--lights") {
      const int n = std::atoi(v.c_str());
      if (n < 1 || n > static_cast<int>(kMaxSlotLights)) return false;
      o.lights = static_cast<uint32_t>(n);
    } else if (a == "--light-range") {
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      if (end == v.c_str() || *end != '\0' || !std::isfinite(x) || x < 0.0 || x > 1000.0) return false;
      o.light_range = x;
    } else {
      return false;
    }
  }
  if (o.quick) {  // smoke run: the project's own scene, one bookmark, one small size, Embree only
    if (o.scenes.empty()) o.scenes.push_back(std::string(DHR_SOURCE_DIR) + "/assets/scenes/default_room.gltf");
    if (!sizes_given) o.sizes = {{160, 120}};
    if (!repeat_given) o.repeat = 1;
    if (!bookmarks_given) o.bookmarks = 1;
    o.vulkan = false;
  }
  if (o.scenes.empty()) o.scenes = default_trace_scenes(DHR_SHARED_DATA_DIR, DHR_SOURCE_DIR);
  return true;
}

}  // namespace dhr::bench
