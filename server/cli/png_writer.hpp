// PNG output for snapshots (stb_image_write).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace dhr::server::cli {

// channels: 1 (grey) or 3 (RGB); pixels row-major, top row first. False when the file cannot be written.
bool write_png(const std::string& path, uint32_t width, uint32_t height, uint32_t channels,
               const std::vector<uint8_t>& pixels);

}  // namespace dhr::server::cli
