#include "render/offscreen_sink.hpp"

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "image/png_writer.hpp"
#include "vk/context.hpp"

namespace dhr::render {

std::vector<uint8_t> read_rgba8(const vk::Context& context, vk::Image& image) {
  const VkFormat f = image.format();
  const bool bgra = f == VK_FORMAT_B8G8R8A8_UNORM || f == VK_FORMAT_B8G8R8A8_SRGB;
  if (!bgra && f != VK_FORMAT_R8G8B8A8_UNORM && f != VK_FORMAT_R8G8B8A8_SRGB) {
    throw std::invalid_argument("read_rgba8: the image is not an 8-bit RGBA/BGRA image");
  }
  std::vector<uint8_t> pixels(size_t{image.width()} * image.height() * 4);
  vk::read_image(context, image, pixels.data(), pixels.size());
  if (bgra) {
    for (size_t i = 0; i < pixels.size(); i += 4) std::swap(pixels[i], pixels[i + 2]);
  }
  return pixels;
}

OffscreenPngSink::OffscreenPngSink(const vk::Context& context, std::string directory, uint32_t every_nth,
                                   bool swap_red_blue)
    : context_(&context), directory_(std::move(directory)), every_nth_(every_nth), swap_red_blue_(swap_red_blue) {
  std::error_code ec;
  std::filesystem::create_directories(directory_, ec);
  if (ec || !std::filesystem::is_directory(directory_)) {
    throw std::runtime_error("offscreen sink: cannot create directory '" + directory_ + "'" +
                             (ec ? ": " + ec.message() : std::string()));
  }
}

std::string OffscreenPngSink::path_for(uint64_t frame, uint32_t eye) const {
  char name[64];
  const std::string eye_name = eye == 0 ? "left" : eye == 1 ? "right" : "eye" + std::to_string(eye);
  std::snprintf(name, sizeof(name), "frame_%06llu_%s.png", static_cast<unsigned long long>(frame), eye_name.c_str());
  return (std::filesystem::path(directory_) / name).string();
}

std::optional<std::string> OffscreenPngSink::write(uint64_t frame, uint32_t eye, vk::Image& image) {
  if (!wants(frame)) return std::nullopt;
  const std::vector<uint8_t> rgba = read_rgba8(*context_, image);
  std::vector<uint8_t> rgb(rgba.size() / 4 * 3);
  for (size_t i = 0, j = 0; i < rgba.size(); i += 4, j += 3) {
    rgb[j] = rgba[swap_red_blue_ ? i + 2 : i];
    rgb[j + 1] = rgba[i + 1];
    rgb[j + 2] = rgba[swap_red_blue_ ? i : i + 2];
  }
  const std::string path = path_for(frame, eye);
  if (auto err = write_png(path, image.width(), image.height(), 3, rgb)) throw std::runtime_error(*err);
  ++files_written_;
  return path;
}

}  // namespace dhr::render
