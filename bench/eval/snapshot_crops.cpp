#include "snapshot_crops.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "image/png_writer.hpp"
#include "picture_canvas.hpp"

namespace dhr::eval {

namespace {

constexpr Rgb kBackground{30, 31, 36};
constexpr Rgb kText{236, 236, 236};
constexpr int kMargin = 16;
constexpr int kGap = 12;
constexpr float kLabelPixels = 17.0f;

RgbImage cropped(const RgbImage& image, const CropRect& c) {
  RgbImage out{c.width, c.height, std::vector<uint8_t>(size_t{c.width} * c.height * 3)};
  for (uint32_t y = 0; y < c.height; ++y) {
    const uint8_t* row = &image.rgb[(size_t{c.y + y} * image.width + c.x) * 3];
    std::copy(row, row + size_t{c.width} * 3, &out.rgb[size_t{y} * c.width * 3]);
  }
  return out;
}

}  // namespace

std::optional<CropRect> parse_crop(const std::string& text) {
  std::array<unsigned, 4> v{};
  int used = 0;
  if (std::sscanf(text.c_str(), "%u,%u,%u,%u%n", &v[0], &v[1], &v[2], &v[3], &used) != 4 ||
      used != static_cast<int>(text.size()) || v[2] == 0 || v[3] == 0 || v[2] > 4096 || v[3] > 4096) {
    return std::nullopt;
  }
  return CropRect{v[0], v[1], v[2], v[3]};
}

std::optional<std::string> write_crop_picture(const CropPicture& request, std::string* out_error) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(request.out_dir) / "snapshots";
  const std::string eye = "_eye" + std::to_string(request.eye) + ".png";
  auto load = [&](const std::string& name) -> std::optional<RgbImage> {
    std::string error;
    auto image = read_png_rgb((dir / name).string(), &error);
    if (!image) {
      if (out_error != nullptr) *out_error = error;
      return std::nullopt;
    }
    const CropRect& c = request.crop;
    if (uint64_t{c.x} + c.width > image->width || uint64_t{c.y} + c.height > image->height) {
      if (out_error != nullptr) {
        *out_error = "--snapshot-crop " + std::to_string(c.x) + "," + std::to_string(c.y) + "," +
                     std::to_string(c.width) + "," + std::to_string(c.height) + " does not lie inside the " +
                     std::to_string(image->width) + "x" + std::to_string(image->height) + " snapshots";
      }
      return std::nullopt;
    }
    return cropped(*image, c);
  };
  // Columns: exact, then each method; rows: the shaded images, then the wrong bits (none for exact).
  std::vector<std::string> labels{"exact"};
  std::vector<RgbImage> shaded, wrong;
  const auto exact = load("exact_guard" + request.guard + eye);
  if (!exact) return std::nullopt;
  shaded.push_back(*exact);
  for (const std::string& method : request.methods) {
    const std::string base = method + "_rtt" + request.rtt + "_guard" + request.guard;
    const auto image = load(base + eye);
    const auto bits = image ? load(base + "_wrong_bits" + eye) : std::nullopt;
    if (!image || !bits) return std::nullopt;
    labels.push_back(method + " at " + request.rtt + " ms");
    shaded.push_back(*image);
    wrong.push_back(*bits);
  }

  std::string font_error;
  const std::unique_ptr<TextFace> face = TextFace::load(default_font_path(), &font_error);
  const uint32_t scale = std::clamp<uint32_t>(240 / std::max(request.crop.width, request.crop.height), 1, 8);
  const int w = static_cast<int>(request.crop.width * scale), h = static_cast<int>(request.crop.height * scale);
  int column = w;
  for (const std::string& label : labels) {
    if (face != nullptr) column = std::max(column, face->width(label, kLabelPixels));
  }
  const int label_h = face != nullptr ? static_cast<int>(kLabelPixels * 1.35f) : 0;
  const int columns = static_cast<int>(shaded.size());
  Canvas canvas(static_cast<uint32_t>(2 * kMargin + columns * column + (columns - 1) * kGap),
                static_cast<uint32_t>(2 * kMargin + label_h + 2 * h + kGap), kBackground);
  for (int c = 0; c < columns; ++c) {
    const int x = kMargin + c * (column + kGap);
    if (face != nullptr) face->draw(canvas, x, kMargin, labels[static_cast<size_t>(c)], kLabelPixels, kText);
    canvas.blit(shaded[static_cast<size_t>(c)], x, kMargin + label_h, scale);
    if (c > 0) canvas.blit(wrong[static_cast<size_t>(c - 1)], x, kMargin + label_h + h + kGap, scale);
  }
  const std::string path =
      (dir / ("crop_rtt" + request.rtt + "_guard" + request.guard + eye)).string();
  const RgbImage& picture = canvas.image();
  if (auto err = write_png(path, picture.width, picture.height, 3, picture.rgb)) {
    if (out_error != nullptr) *out_error = *err;
    return std::nullopt;
  }
  return path;
}

}  // namespace dhr::eval
