// Real visibility buffers for bench/codec_bench: a scene traced with the server's Embree tracer from
// every camera bookmark, both eyes (built only when dhr_server is, see bench/CMakeLists.txt).
#pragma once
#include "codec_measure.hpp"
#include "math/projection.hpp"

#include <string>

namespace dhr::bench {

inline constexpr double kBenchFovDegrees = 90.0;  // horizontal, of the displayed region

// The displayed size and guard band for a traced (guard-banded) buffer size, in the paper's proportion
// (1920x1080 displayed + 64x36 guard = 1984x1116).
void split_guard_band(Extent traced, Extent& out_display, GuardBand& out_guard);

// Loads `scene_path`, reads "<scene>.cameras.json" and traces both eyes of every bookmark at `traced`
// size. False with a one-line reason in out_error when the scene, bookmarks or tracer are unusable.
bool trace_bookmark_buffers(const std::string& scene_path, Extent traced, unsigned threads, BufferSet& out,
                            std::string* out_error);

}  // namespace dhr::bench
