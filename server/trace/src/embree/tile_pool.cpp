#include "trace/embree/tile_pool.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

namespace dhr::server {

uint32_t tile_workers(uint32_t threads, uint32_t tile_count) { return std::max(1u, std::min(threads, tile_count)); }

void run_tiles(uint32_t workers, uint32_t tile_count, const std::function<void(uint32_t, uint32_t)>& work,
               const char* who) {
  std::atomic<uint32_t> next_tile{0};
  std::vector<std::exception_ptr> errors(workers);
  auto run = [&](uint32_t worker) {
    try {
      for (uint32_t t = next_tile.fetch_add(1); t < tile_count; t = next_tile.fetch_add(1)) work(worker, t);
    } catch (...) {
      errors[worker] = std::current_exception();  // e.g. bad_alloc: rethrown on the caller's thread
      next_tile.store(tile_count);
    }
  };
  // A std::thread still joinable when the pool is destroyed would terminate the process: a thread that cannot
  // start ends the run with an error once the started ones finished.
  std::vector<std::thread> pool;
  pool.reserve(workers - 1);
  std::string start_error;
  for (uint32_t w = 1; w < workers && start_error.empty(); ++w) {
    try {
      pool.emplace_back(run, w);
    } catch (const std::system_error& e) {
      start_error = std::string(who) + ": cannot start tracer thread " + std::to_string(w + 1) + " of " +
                    std::to_string(workers) + ": " + e.what();
      next_tile.store(tile_count);  // the started threads stop at their next tile
    }
  }
  if (start_error.empty()) run(0);
  for (std::thread& th : pool) th.join();
  if (!start_error.empty()) throw std::runtime_error(start_error);
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace dhr::server
