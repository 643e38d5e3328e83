// Offscreen frame sink: reads a shaded eye image back and writes it as a PNG, every Nth frame.
// For people to look at (docs/client.md); blocking readback, so not for the headset's frame rate.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "vk/image.hpp"

namespace dhr::vk {
class Context;
}

namespace dhr::render {

// Reads an 8-bit RGBA/BGRA image back as tightly packed RGBA bytes (BGRA is swizzled). Waits for all
// previously submitted work. Throws std::invalid_argument for other formats.
std::vector<uint8_t> read_rgba8(const vk::Context& context, vk::Image& image);

class OffscreenPngSink {
 public:
  // Creates `directory` when missing; throws std::runtime_error when that fails. every_nth == 0: never.
  // swap_red_blue: the images hold blue in the red channel (shaded for a B8G8R8A8 swapchain); the PNGs swap back.
  OffscreenPngSink(const vk::Context& context, std::string directory, uint32_t every_nth = 1,
                   bool swap_red_blue = false);

  bool wants(uint64_t frame) const { return every_nth_ != 0 && frame % every_nth_ == 0; }
  // "<directory>/frame_<frame, 6 digits>_<left|right>.png" (eye 0 left, 1 right, others "eye<N>").
  std::string path_for(uint64_t frame, uint32_t eye) const;

  // Writes the image (RGB PNG) when wants(frame); returns its path, std::nullopt when skipped. Throws
  // std::runtime_error when the file cannot be written.
  std::optional<std::string> write(uint64_t frame, uint32_t eye, vk::Image& image);
  uint64_t files_written() const { return files_written_; }
  const std::string& directory() const { return directory_; }

 private:
  const vk::Context* context_;
  std::string directory_;
  uint32_t every_nth_;
  bool swap_red_blue_;
  uint64_t files_written_ = 0;
};

}  // namespace dhr::render
