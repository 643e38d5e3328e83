#include "image/png_writer.hpp"

// stb_image_write's implementation, private to this file (static), so it cannot clash with other copies
// (tinygltf's shared library, dhr-server's snapshot writer).
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wcast-align"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

namespace dhr {

std::optional<std::string> write_png(const std::string& path, uint32_t width, uint32_t height, uint32_t channels,
                                     std::span<const uint8_t> pixels) {
  if (channels < 1 || channels > 4) return "PNG " + path + ": " + std::to_string(channels) + " channels (1-4)";
  if (width == 0 || height == 0 || width > 65535 || height > 65535) {
    return "PNG " + path + ": unsupported size " + std::to_string(width) + "x" + std::to_string(height);
  }
  const size_t expected = size_t{width} * height * channels;
  if (pixels.size() != expected) {
    return "PNG " + path + ": " + std::to_string(pixels.size()) + " bytes given, " + std::to_string(expected) +
           " expected";
  }
  const int ok = stbi_write_png(path.c_str(), static_cast<int>(width), static_cast<int>(height),
                                static_cast<int>(channels), pixels.data(), static_cast<int>(width * channels));
  if (ok == 0) return "PNG " + path + ": cannot write the file";
  return std::nullopt;
}

}  // namespace dhr
