// Per-frame statistics as JSON lines (render::JsonLinesWriter): one line per frame with both eyes' GPU
// pass times, warp counts, visibility age and response time (xrclient/frame/frame_record.hpp).
#pragma once
#include <string>

#include "frame/frame_record.hpp"
#include "render/stats_jsonl.hpp"

namespace dhr::client {

class StatsSink {
 public:
  explicit StatsSink(const std::string& path) : writer_(path) {}  // throws std::runtime_error naming the file
  void write(const FrameRecord& record) { writer_.write(frame_record_json(record)); }
  uint64_t lines() const { return writer_.lines(); }

 private:
  render::JsonLinesWriter writer_;
};

}  // namespace dhr::client
