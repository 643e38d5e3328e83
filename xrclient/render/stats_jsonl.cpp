#include "render/stats_jsonl.hpp"

#include <nlohmann/json.hpp>
#include <stdexcept>

#include "render/eye_pipeline.hpp"

namespace dhr::render {

JsonLinesWriter::JsonLinesWriter(const std::string& path) : path_(path) {
  file_ = std::fopen(path.c_str(), "w");
  if (file_ == nullptr) throw std::runtime_error("cannot open statistics file '" + path + "' for writing");
}

JsonLinesWriter::~JsonLinesWriter() {
  if (file_ != nullptr) std::fclose(file_);
}

void JsonLinesWriter::write(const std::string& json_object) {
  if (json_object.find('\n') != std::string::npos) {
    throw std::invalid_argument("JSON lines: an entry must be a single line");
  }
  if (std::fputs(json_object.c_str(), file_) < 0 || std::fputc('\n', file_) == EOF || std::fflush(file_) != 0) {
    throw std::runtime_error("cannot write to statistics file '" + path_ + "'");
  }
  ++lines_;
}

std::string eye_stats_json(uint64_t frame, uint32_t eye, const EyeStats& stats) {
  nlohmann::ordered_json j;
  j["frame"] = frame;
  j["eye"] = eye;
  j["width"] = stats.extent.width;
  j["height"] = stats.extent.height;
  j["gpu_valid"] = stats.gpu.valid;
  j["gbuffer_ms"] = stats.gpu.gbuffer_ms;
  j["warp_ms"] = stats.gpu.warp_ms;
  j["shading_ms"] = stats.gpu.shading_ms;
  j["forward"] = stats.forward;
  j["forward_ms"] = stats.gpu.forward_ms;
  j["total_ms"] = stats.gpu.total_ms;
  j["shadow_update_lights"] = stats.shadow_update.lights;
  j["shadow_update_faces"] = stats.shadow_update.faces;
  j["shadow_update_ms"] = stats.gpu.shadow_update_ms;
  for (size_t s = 0; s < kWarpStatusCount; ++s) j[to_string(static_cast<WarpStatus>(s))] = stats.warp.by_status[s];
  j["unknown"] = stats.unknown_pixels();
  j["meshes_drawn"] = stats.draws.meshes_drawn;
  j["meshes_culled"] = stats.draws.meshes_culled;
  j["triangles"] = stats.draws.triangles_drawn;
  j["visibility_used"] = stats.visibility_used;
  return j.dump();
}

}  // namespace dhr::render
