// Scene seeds for fuzz_scene: small but feature-rich glTF files built here (a textured triangle with
// normals and texture coordinates, lights of every type, a strip without normals, a node hierarchy with
// instancing and KHR_texture_transform), as .gltf text with data: URIs and as .glb with a BIN chunk.
#include "fuzz_support.hpp"
#include "test_base64.hpp"

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

#include <cstring>
#include <string>

namespace dhr::fuzz {

std::vector<Seed> scene_seeds();

namespace {

void append_f32(Bytes& b, float f) {
  uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  put_u32(b, bits);
}

void write_to_bytes(void* context, void* data, int size) {
  auto* out = static_cast<Bytes*>(context);
  const auto* p = static_cast<const uint8_t*>(data);
  out->insert(out->end(), p, p + size);
}

// A 4x4 RGBA checkerboard as PNG or JPEG.
Bytes tiny_image(bool jpeg) {
  uint8_t pixels[4 * 4 * 4];
  for (int i = 0; i < 16; ++i) {
    const bool on = ((i % 4) + (i / 4)) % 2 == 0;
    pixels[4 * i + 0] = on ? 230 : 20;
    pixels[4 * i + 1] = on ? 120 : 40;
    pixels[4 * i + 2] = 60;
    pixels[4 * i + 3] = 255;
  }
  Bytes out;
  if (jpeg) {
    stbi_write_jpg_to_func(write_to_bytes, &out, 4, 4, 4, pixels, 80);
  } else {
    stbi_write_png_to_func(write_to_bytes, &out, 4, 4, 4, pixels, 16);
  }
  return out;
}

std::string base64(const Bytes& in) { return test::base64(std::vector<unsigned char>(in.begin(), in.end())); }

// One triangle: positions (36 bytes), normals (36), texcoords (24), u16 indices (6 + 2 padding).
Bytes triangle_buffer() {
  Bytes b;
  const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const float normals[9] = {0, 0, 1, 0, 0, 1, 0, 0, 1};
  const float uvs[6] = {0, 0, 1, 0, 0, 1};
  for (float f : positions) append_f32(b, f);
  for (float f : normals) append_f32(b, f);
  for (float f : uvs) append_f32(b, f);
  for (uint16_t i : {0, 1, 2, 0}) put_u16(b, i);
  return b;
}

constexpr const char* kTriangleViewsAndAccessors = R"(
  "bufferViews": [
    {"buffer": 0, "byteOffset": 0, "byteLength": 36, "target": 34962},
    {"buffer": 0, "byteOffset": 36, "byteLength": 36, "target": 34962},
    {"buffer": 0, "byteOffset": 72, "byteLength": 24, "target": 34962},
    {"buffer": 0, "byteOffset": 96, "byteLength": 6, "target": 34963}%s
  ],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0,0,0], "max": [1,1,0]},
    {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
    {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"},
    {"bufferView": 3, "componentType": 5123, "count": 3, "type": "SCALAR"}
  ],)";

std::string fill(const char* fmt, const std::string& a) {
  std::string out;
  const char* at = std::strstr(fmt, "%s");
  out.append(fmt, static_cast<size_t>(at - fmt));
  out += a;
  out += at + 2;
  return out;
}

// The JSON of the textured triangle; `buffer` and `image` are the JSON objects of buffers[0]/images[0],
// `extra_view` an extra bufferView entry (with a leading comma) or "".
std::string triangle_json(const std::string& buffer, const std::string& image, const std::string& extra_view) {
  return std::string(R"({
  "asset": {"version": "2.0", "generator": "dhr fuzz seeds"},
  "extensionsUsed": ["KHR_lights_punctual", "KHR_texture_transform"],
  "scene": 0,
  "scenes": [{"nodes": [0, 1, 2, 3]}],
  "nodes": [
    {"mesh": 0, "translation": [0, 0, -2], "rotation": [0, 0.3826834, 0, 0.9238795], "scale": [1, 2, 1]},
    {"translation": [0, 2, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
    {"rotation": [-0.7071068, 0, 0, 0.7071068], "extensions": {"KHR_lights_punctual": {"light": 1}}},
    {"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 1,2,3,1], "extensions": {"KHR_lights_punctual": {"light": 2}}}
  ],
  "meshes": [{"name": "tri", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                             "indices": 3, "material": 0}]}],
  "materials": [{"name": "checker", "doubleSided": true,
    "pbrMetallicRoughness": {"baseColorFactor": [1, 0.9, 0.8, 1],
      "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {"offset": [0.5, 0], "rotation": 0.2, "scale": [2, 2]}}}}}],
  "textures": [{"source": 0, "sampler": 0}],
  "samplers": [{"wrapS": 33071, "wrapT": 33648}],
  "images": [)") + image + R"(],
  "buffers": [)" + buffer + "]," + fill(kTriangleViewsAndAccessors, extra_view) + R"(
  "extensions": {"KHR_lights_punctual": {"lights": [
    {"type": "point", "color": [1, 0.9, 0.8], "intensity": 20, "range": 6},
    {"type": "directional", "intensity": 3},
    {"type": "spot", "intensity": 40, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}}
  ]}}
})";
}

Bytes text(const std::string& s) { return Bytes(s.begin(), s.end()); }

Bytes glb(std::string json, Bytes bin) {
  while (json.size() % 4 != 0) json.push_back(' ');
  while (bin.size() % 4 != 0) bin.push_back(0);
  Bytes out;
  put_u32(out, 0x46546C67);  // "glTF"
  put_u32(out, 2);
  put_u32(out, static_cast<uint32_t>(12 + 8 + json.size() + (bin.empty() ? 0 : 8 + bin.size())));
  put_u32(out, static_cast<uint32_t>(json.size()));
  put_u32(out, 0x4E4F534A);  // JSON
  out.insert(out.end(), json.begin(), json.end());
  if (bin.empty()) return out;  // no BIN chunk
  put_u32(out, static_cast<uint32_t>(bin.size()));
  put_u32(out, 0x004E4942);  // BIN
  put_bytes(out, bin);
  return out;
}

// A strip of 4 vertices (two triangles) without normals (flat normals get generated), two instances of
// it under a parent node, and a mesh without material.
std::string strip_json(const Bytes& buffer) {
  return R"({
  "asset": {"version": "2.0"},
  "scenes": [{"nodes": [0]}],
  "nodes": [{"children": [1, 2], "scale": [-1, 1, 1]}, {"mesh": 0}, {"mesh": 0, "translation": [0, 0, 3]}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "mode": 5}]}],
  "buffers": [{"byteLength": )" + std::to_string(buffer.size()) +
         R"(, "uri": "data:application/octet-stream;base64,)" + base64(buffer) + R"("}],
  "bufferViews": [{"buffer": 0, "byteLength": 48}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0,0,0], "max": [1,1,0]}]
})";
}

// A triangle whose node drives (LINEAR translation) and turns (STEP rotation) over 2 s, with a point light
// on a child node, so that the fuzzer starts from the animation reader's paths.
std::string animated_json() {
  Bytes b;
  for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) append_f32(b, f);                // positions
  for (float f : {0.f, 1.f, 2.f}) append_f32(b, f);                                               // key times
  for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 0.f, 0.f}) append_f32(b, f);                // translations
  for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.7071068f, 0.f, 0.7071068f, 0.f, 1.f, 0.f, 0.f}) append_f32(b, f);
  return R"({
  "asset": {"version": "2.0", "generator": "dhr fuzz seeds"},
  "extensionsUsed": ["KHR_lights_punctual"],
  "scenes": [{"nodes": [0]}],
  "nodes": [{"mesh": 0, "children": [1]},
            {"translation": [0, 1, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
  "animations": [{"name": "drive", "samplers": [{"input": 1, "output": 2, "interpolation": "LINEAR"},
                                               {"input": 1, "output": 3, "interpolation": "STEP"}],
                  "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}},
                               {"sampler": 1, "target": {"node": 0, "path": "rotation"}}]}],
  "buffers": [{"byteLength": )" + std::to_string(b.size()) + R"(, "uri": "data:application/octet-stream;base64,)" +
         base64(b) + R"("}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 12},
                  {"buffer": 0, "byteOffset": 48, "byteLength": 36}, {"buffer": 0, "byteOffset": 84, "byteLength": 48}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0,0,0], "max": [1,1,0]},
                {"bufferView": 1, "componentType": 5126, "count": 3, "type": "SCALAR", "min": [0], "max": [2]},
                {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC3"},
                {"bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC4"}],
  "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 10}]}}
})";
}

}  // namespace

std::vector<Seed> scene_seeds() {
  std::vector<Seed> out;
  const Bytes tri = triangle_buffer();
  const std::string data_buffer = R"({"byteLength": )" + std::to_string(tri.size()) +
                                  R"(, "uri": "data:application/octet-stream;base64,)" + base64(tri) + R"("})";
  const std::string png_image = R"({"uri": "data:image/png;base64,)" + base64(tiny_image(false)) + R"("})";
  out.push_back({"triangle.gltf", text(triangle_json(data_buffer, png_image, ""))});

  // .glb: the JPEG image lives in the BIN chunk after the geometry (bufferView 4).
  Bytes bin = tri;
  const Bytes jpeg = tiny_image(true);
  const size_t image_offset = bin.size();
  put_bytes(bin, jpeg);
  const std::string glb_buffer = R"({"byteLength": )" + std::to_string(bin.size()) + "}";
  const std::string glb_view = R"(,
    {"buffer": 0, "byteOffset": )" + std::to_string(image_offset) +
                               R"(, "byteLength": )" + std::to_string(jpeg.size()) + "}";
  out.push_back({"triangle.glb", glb(triangle_json(glb_buffer, R"({"bufferView": 4, "mimeType": "image/jpeg"})", glb_view),
                                     bin)});

  Bytes strip;
  for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f, 1.f, 1.f, 0.f}) append_f32(strip, f);
  out.push_back({"strip.gltf", text(strip_json(strip))});
  out.push_back({"minimal.gltf", text(R"({"asset": {"version": "2.0"}})")});
  out.push_back({"minimal.glb", glb(R"({"asset":{"version":"2.0"}})", {})});
  out.push_back({"animated.gltf", text(animated_json())});
  return out;
}

}  // namespace dhr::fuzz
