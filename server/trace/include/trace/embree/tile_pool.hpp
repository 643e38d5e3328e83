// The Embree tracers' work split: an image cut into tiles, claimed by a few std::threads through an atomic
// counter (load balance). Shared by the hard-shadow tracer (EmbreeTracer) and the soft-visibility image
// (trace/soft/soft_image.hpp), so both start, stop and report thread failures the same way.
#pragma once
#include <cstdint>
#include <functional>

namespace dhr::server {

// How many workers run_tiles uses for `threads` (>= 1) and `tile_count` tiles: never more than the tiles.
uint32_t tile_workers(uint32_t threads, uint32_t tile_count);

// Calls work(worker, tile) for every tile in [0, tile_count) exactly once, on `workers` threads (the caller's
// thread is worker 0; worker < workers). A worker's exception stops the others at their next tile and is
// rethrown here after all joined. A thread that cannot start (the system's thread limit) ends the run with
// std::runtime_error "<who>: cannot start tracer thread K of N: ...", after the started ones finished.
void run_tiles(uint32_t workers, uint32_t tile_count, const std::function<void(uint32_t, uint32_t)>& work,
               const char* who);

}  // namespace dhr::server
