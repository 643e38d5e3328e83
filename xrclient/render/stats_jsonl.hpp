// Per-frame statistics as JSON lines: one JSON object per line, flushed as written, so a crash keeps what
// came before and tools can stream the file.
#pragma once
#include <cstdint>
#include <cstdio>
#include <string>

namespace dhr::render {

struct EyeStats;

class JsonLinesWriter {
 public:
  // Truncates/creates the file; throws std::runtime_error naming it when it cannot be opened.
  explicit JsonLinesWriter(const std::string& path);
  ~JsonLinesWriter();
  JsonLinesWriter(const JsonLinesWriter&) = delete;
  JsonLinesWriter& operator=(const JsonLinesWriter&) = delete;

  // Appends one line; `json_object` must be a single-line JSON text (a newline in it throws
  // std::invalid_argument). Throws std::runtime_error when the write fails.
  void write(const std::string& json_object);
  uint64_t lines() const { return lines_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  uint64_t lines_ = 0;
};

// {"frame":N,"eye":E,"width":..,"height":..,"gpu_valid":..,"gbuffer_ms":..,"warp_ms":..,
//  "shading_ms":..,"forward":..,"forward_ms":..,"total_ms":..,"shadow_update_lights":..,"shadow_update_faces":..,
//  "shadow_update_ms":.. (eye 0: the frame's shadow-map re-render, StereoPipeline),"known":..,"background":..,"behind":..,"outside":..,"missing_row":..,
//  "no_data":..,"unknown":..,"meshes_drawn":..,"meshes_culled":..,"triangles":..,"visibility_used":..}
std::string eye_stats_json(uint64_t frame, uint32_t eye, const EyeStats& stats);

}  // namespace dhr::render
