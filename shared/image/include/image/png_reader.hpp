// PNG input: what the client saved, read back for comparisons (dhr-eval compare) and tests.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dhr {

struct RgbImage {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<uint8_t> rgb;  // width * height * 3, row-major, top row first
};

// Reads a PNG as 8-bit RGB (grey is expanded, alpha dropped, 16-bit narrowed). std::nullopt with a one-line
// reason when the file cannot be read, is not a PNG, or is larger than max_pixels.
std::optional<RgbImage> read_png_rgb(const std::string& path, std::string* out_error,
                                     uint64_t max_pixels = uint64_t{1} << 26);

}  // namespace dhr
