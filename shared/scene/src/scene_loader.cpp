// load_scene: reads the file (bounded), checks the .glb container and the JSON ourselves, then lets
// tinygltf load buffers and images through size-limited file callbacks, and builds the Scene.
// Nothing throws out of here: every exception becomes an error naming the file.
#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>
#include <nlohmann/json.hpp>

#include "scene/scene.hpp"
#include "scene_internal.hpp"

namespace dhr {
namespace {

namespace fs = std::filesystem;
using scene_detail::format;

constexpr std::uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;
constexpr std::uint32_t kChunkBin = 0x004E4942;
constexpr int kMaxJsonDepth = 256;  // tinygltf converts "extras" recursively

std::uint32_t le32(const unsigned char* p) {
  return std::uint32_t{p[0]} | (std::uint32_t{p[1]} << 8) | (std::uint32_t{p[2]} << 16) | (std::uint32_t{p[3]} << 24);
}

SceneLoadResult failure(const std::string& name, const std::string& problem) {
  SceneLoadResult r;
  r.error = name + ": " + problem;
  return r;
}

// Reads a whole file, refusing anything that is not a regular file or is larger than `max_bytes`.
bool read_file(const std::string& path, std::uint64_t max_bytes, std::vector<unsigned char>* out,
               std::string* out_error) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status)) {
    *out_error = "file not found";
    return false;
  }
  if (!fs::is_regular_file(status)) {
    *out_error = "not a regular file";
    return false;
  }
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) {
    *out_error = "cannot read the file size (" + ec.message() + ")";
    return false;
  }
  if (size > max_bytes) {
    *out_error = format("the file has %llu bytes, more than the limit (max_file_bytes = %llu)",
                        static_cast<unsigned long long>(size), static_cast<unsigned long long>(max_bytes));
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    *out_error = "cannot open the file";
    return false;
  }
  out->resize(static_cast<std::size_t>(size));
  if (size > 0 && !in.read(reinterpret_cast<char*>(out->data()), static_cast<std::streamsize>(size))) {
    *out_error = "cannot read the file";
    return false;
  }
  return true;
}

// tinygltf file-system hooks: only plain reads, size-limited; no writes, no path expansion.
bool fs_exists(const std::string& path, void*) {
  std::error_code ec;
  return fs::is_regular_file(path, ec);
}
std::string fs_expand(const std::string& path, void*) { return path; }
bool fs_read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user_data) {
  const auto* options = static_cast<const SceneLoadOptions*>(user_data);
  return read_file(path, options->max_file_bytes, out, err);
}
bool fs_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err = "writing is disabled";
  return false;
}

std::string percent_decode(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size() && std::isxdigit(static_cast<unsigned char>(s[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(s[i + 2]))) {
      out.push_back(static_cast<char>(std::stoi(s.substr(i + 1, 2), nullptr, 16)));
      i += 2;
    } else {
      out.push_back(s[i]);
    }
  }
  return out;
}

// Nesting depth of JSON text, ignoring brackets inside strings.
int json_depth(const unsigned char* text, std::size_t size) {
  int depth = 0;
  int max_depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < size; ++i) {
    const unsigned char c = text[i];
    if (in_string) {
      if (c == '\\') {
        ++i;
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      max_depth = std::max(max_depth, ++depth);
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return max_depth;
}

// Splits a .glb into its JSON chunk and BIN chunk description; error when the container is broken.
bool parse_glb(const unsigned char* data, std::size_t size, const unsigned char** out_json, std::size_t* out_json_size,
               scene_detail::ContainerInfo* info, scene_detail::WarningSink& warnings, std::string* out_error) {
  if (size < 20) {
    *out_error = format(".glb header truncated (%zu bytes)", size);
    return false;
  }
  const std::uint32_t version = le32(data + 4);
  const std::uint32_t length = le32(data + 8);
  const std::uint32_t json_length = le32(data + 12);
  if (version != 2) {
    *out_error = format(".glb container version %u is not supported (need 2)", version);
    return false;
  }
  if (length > size) {
    *out_error = format(".glb truncated: the header says %u bytes, the file has %zu", length, size);
    return false;
  }
  if (length < size) warnings.add(format("%zu bytes after the .glb's declared length are ignored", size - length));
  if (le32(data + 16) != kChunkJson || json_length == 0 || 20ull + json_length > length) {
    *out_error = "the .glb's first chunk is not a valid JSON chunk";
    return false;
  }
  *out_json = data + 20;
  *out_json_size = json_length;
  info->is_glb = true;
  const std::uint64_t bin_start = 20ull + json_length;
  if (bin_start == length) return true;
  if (bin_start + 8 > length) {
    *out_error = "the .glb has a truncated chunk after the JSON chunk";
    return false;
  }
  const std::uint32_t bin_length = le32(data + bin_start);
  if (le32(data + bin_start + 4) != kChunkBin || bin_length < 4 || bin_length % 4 != 0 ||
      bin_start + 8 + bin_length > length) {
    *out_error = format("the .glb's second chunk is not a valid BIN chunk (length %u, %llu bytes available)",
                        bin_length, static_cast<unsigned long long>(length - bin_start - 8));
    return false;
  }
  info->has_bin_chunk = true;
  info->bin_chunk_bytes = bin_length;
  return true;
}

// External .bin files must exist with exactly byteLength bytes (as tinygltf requires): say so clearly.
bool check_external_buffers(const nlohmann::json& root, const std::string& base_dir, std::string* out_error) {
  if (!root.contains("buffers")) return true;
  const nlohmann::json& buffers = root["buffers"];
  for (std::size_t i = 0; i < buffers.size(); ++i) {
    const std::string uri = buffers[i].value("uri", std::string());
    if (uri.empty() || uri.rfind("data:", 0) == 0) continue;
    const std::string name = percent_decode(uri);
    const fs::path path = fs::path(base_dir) / name;
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
      *out_error = format("buffers[%zu]: file '%s' not found (next to the glTF file)", i, name.c_str());
      return false;
    }
    const std::uintmax_t size = fs::file_size(path, ec);
    const std::uint64_t expected = buffers[i].value("byteLength", std::uint64_t{0});
    if (ec || size < expected) {
      *out_error = format("buffers[%zu]: file '%s' has %llu bytes, but byteLength is %llu", i, name.c_str(),
                          static_cast<unsigned long long>(size), static_cast<unsigned long long>(expected));
      return false;
    }
  }
  return true;
}

std::string one_line(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  for (char& c : s) {
    if (c == '\n') c = ';';
  }
  return s;
}

SceneLoadResult load_impl(const unsigned char* data, std::size_t size, const std::string& base_dir,
                          const std::string& name, const SceneLoadOptions& options) {
  if (size == 0) return failure(name, "the file is empty");
  if (size > options.max_file_bytes) {
    return failure(name, format("the file has %zu bytes, more than the limit (max_file_bytes = %llu)", size,
                                static_cast<unsigned long long>(options.max_file_bytes)));
  }
  if (size > 0xFFFFFFFFull) return failure(name, "files of 4 GiB or more are not supported");
  scene_detail::WarningSink warnings;
  scene_detail::ContainerInfo info;
  const unsigned char* json_text = data;
  std::size_t json_size = size;
  std::string error;
  if (size >= 4 && le32(data) == kGlbMagic) {
    if (!parse_glb(data, size, &json_text, &json_size, &info, warnings, &error)) return failure(name, error);
  }
  if (json_depth(json_text, json_size) > kMaxJsonDepth) {
    return failure(name, format("the JSON is nested more than %d levels deep", kMaxJsonDepth));
  }
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(json_text, json_text + json_size);
  } catch (const nlohmann::json::exception& e) {
    return failure(name, std::string("not valid glTF JSON: ") + e.what());
  }
  if (auto problem = scene_detail::validate_gltf_json(root, info, warnings)) return failure(name, *problem);
  if (!check_external_buffers(root, base_dir, &error)) return failure(name, error);

  scene_detail::ImageDecodeContext images;
  images.options = &options;
  images.wanted = scene_detail::base_color_image_mask(root);
  const scene_detail::LightJson light_json = scene_detail::extract_light_json(root);
  root = nlohmann::json();  // free it before tinygltf builds its own copy

  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(scene_detail::decode_image_callback, &images);
  tinygltf::FsCallbacks callbacks{fs_exists, fs_expand, fs_read, fs_write,
                                  const_cast<void*>(static_cast<const void*>(&options))};
  loader.SetFsCallbacks(callbacks);
  tinygltf::Model model;
  std::string tiny_error;
  std::string tiny_warning;
  const bool loaded =
      info.is_glb ? loader.LoadBinaryFromMemory(&model, &tiny_error, &tiny_warning, data,
                                                static_cast<unsigned int>(size), base_dir)
                  : loader.LoadASCIIFromString(&model, &tiny_error, &tiny_warning, reinterpret_cast<const char*>(data),
                                               static_cast<unsigned int>(size), base_dir);
  warnings.add_lines(tiny_warning);
  if (!loaded) return failure(name, "tinygltf could not load it: " + one_line(tiny_error));

  SceneLoadResult result;
  result.scene.emplace();
  Scene& scene = *result.scene;
  scene.source = name;
  if (!scene_detail::build_scene(model, options, images, light_json, warnings, &scene, &error)) return failure(name, error);
  scene.warnings = warnings.take();
  return result;
}

template <typename F>
SceneLoadResult guarded(const std::string& name, F&& f) {
  try {
    return f();
  } catch (const std::bad_alloc&) {
    return failure(name, "out of memory while loading (lower the limits in SceneLoadOptions?)");
  } catch (const std::exception& e) {
    return failure(name, std::string("unexpected error while loading: ") + e.what());
  } catch (...) {
    return failure(name, "unexpected error while loading");
  }
}

}  // namespace

SceneLoadResult load_scene(const std::string& path, const SceneLoadOptions& options) {
  return guarded(path, [&] {
    std::vector<unsigned char> bytes;
    std::string error;
    if (!read_file(path, options.max_file_bytes, &bytes, &error)) return failure(path, error);
    std::string base_dir = fs::path(path).parent_path().string();
    if (base_dir.empty()) base_dir = ".";
    return load_impl(bytes.data(), bytes.size(), base_dir, path, options);
  });
}

SceneLoadResult load_scene_from_memory(const void* data, std::size_t size, const std::string& base_dir,
                                       const std::string& name, const SceneLoadOptions& options) {
  return guarded(name, [&] {
    if (data == nullptr && size > 0) return failure(name, "no data");
    return load_impl(static_cast<const unsigned char*>(data), size, base_dir.empty() ? "." : base_dir, name, options);
  });
}

}  // namespace dhr
