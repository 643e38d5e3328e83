#include "image/png_reader.hpp"

// stb_image's PNG decoder, private to this file (static), as png_writer.cpp does with stb_image_write.
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_ONLY_PNG
#include <stb/stb_image.h>

#include <cstdio>
#include <memory>

namespace dhr {

std::optional<RgbImage> read_png_rgb(const std::string& path, std::string* out_error, uint64_t max_pixels) {
  auto fail = [&](const std::string& message) -> std::optional<RgbImage> {
    if (out_error != nullptr) *out_error = path + ": " + message;
    return std::nullopt;
  };
  std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) return fail("cannot open");
  int w = 0, h = 0, channels = 0;
  if (stbi_info_from_file(file.get(), &w, &h, &channels) == 0) return fail("not a PNG file");
  if (w <= 0 || h <= 0 || static_cast<uint64_t>(w) * static_cast<uint64_t>(h) > max_pixels) {
    return fail("unsupported size " + std::to_string(w) + "x" + std::to_string(h));
  }
  std::unique_ptr<stbi_uc, void (*)(void*)> pixels(stbi_load_from_file(file.get(), &w, &h, &channels, 3),
                                                   &stbi_image_free);
  if (!pixels) return fail(std::string("cannot decode: ") + stbi_failure_reason());
  RgbImage image;
  image.width = static_cast<uint32_t>(w);
  image.height = static_cast<uint32_t>(h);
  image.rgb.assign(pixels.get(), pixels.get() + size_t{image.width} * image.height * 3);
  return image;
}

}  // namespace dhr
