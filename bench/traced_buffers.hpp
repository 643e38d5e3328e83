// Real visibility buffers for bench/codec_bench: a scene traced with the server's Embree tracer from
// every camera bookmark, both eyes (built only when dhr_server is, see bench/CMakeLists.txt).
#pragma once
#include "bench_views.hpp"
#include "codec_measure.hpp"
#include "math/projection.hpp"

#include <string>

namespace dhr::bench {

inline constexpr double kBenchFovDegrees = 90.0;  // horizontal, of the displayed region


// Loads `scene_path`, reads "<scene>.cameras.json" and traces both eyes of every bookmark at `traced`
// size. False with a one-line reason in out_error when the scene, bookmarks or tracer are unusable.
bool trace_bookmark_buffers(const std::string& scene_path, Extent traced, unsigned threads, BufferSet& out,
                            std::string* out_error);

}  // namespace dhr::bench
