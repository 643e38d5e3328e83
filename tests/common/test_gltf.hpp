// A glTF document built in a test, with one embedded buffer (a base64 data URI): tests add buffer views,
// accessors, meshes and nodes, or write `doc` directly, then load text() with load_scene_from_memory.
#pragma once
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "test_base64.hpp"

namespace dhr::test {

class TestGltf {
 public:
  TestGltf() { doc = {{"asset", {{"version", "2.0"}}}}; }

  int view(const void* data, std::size_t bytes) {
    while (blob_.size() % 4) blob_.push_back(0);
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", blob_.size()}, {"byteLength", bytes}});
    const auto* p = static_cast<const unsigned char*>(data);
    blob_.insert(blob_.end(), p, p + bytes);
    return static_cast<int>(doc["bufferViews"].size()) - 1;
  }
  int accessor(int view_index, int component_type, std::size_t count, const char* type, bool normalized = false) {
    nlohmann::json a = {{"bufferView", view_index}, {"componentType", component_type}, {"count", count}, {"type", type}};
    if (normalized) a["normalized"] = true;
    doc["accessors"].push_back(std::move(a));
    return static_cast<int>(doc["accessors"].size()) - 1;
  }
  // A view of `bytes` bytes of `data` and an accessor over it.
  int accessor(const void* data, std::size_t bytes, int component_type, std::size_t count, const char* type,
               bool normalized = false) {
    return accessor(view(data, bytes), component_type, count, type, normalized);
  }
  int floats(const std::vector<float>& v, const char* type, std::size_t components) {
    return accessor(v.data(), v.size() * 4, 5126, v.size() / components, type);
  }
  int node(nlohmann::json n) {
    doc["nodes"].push_back(std::move(n));
    return static_cast<int>(doc["nodes"].size()) - 1;
  }
  // Puts the given roots in scene 0 (unless the test already wrote scenes) and serializes.
  std::string text(std::vector<int> roots = {0}) {
    if (!doc.contains("scenes")) doc["scenes"] = nlohmann::json::array({{{"nodes", roots}}});
    if (!blob_.empty()) {
      doc["buffers"] = nlohmann::json::array(
          {{{"byteLength", blob_.size()}, {"uri", "data:application/octet-stream;base64," + base64(blob_)}}});
    }
    return doc.dump();
  }
  nlohmann::json doc;

 private:
  std::vector<unsigned char> blob_;
};

}  // namespace dhr::test
