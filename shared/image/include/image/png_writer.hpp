// PNG files from 8-bit pixels (stb_image_write), for people to look at: offscreen frames, snapshots.
#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace dhr {

// channels: 1 (grey), 2 (grey + alpha), 3 (RGB) or 4 (RGBA); pixels row-major, top row first, tightly packed.
// Returns an error message (bad size or channel count, file not writable), std::nullopt on success.
std::optional<std::string> write_png(const std::string& path, uint32_t width, uint32_t height, uint32_t channels,
                                     std::span<const uint8_t> pixels);

}  // namespace dhr
