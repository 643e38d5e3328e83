// Base-colour image decoding through tinygltf's image hook: only images that a material uses as its
// base colour are decoded, and only after their header's dimensions pass the limits, so a tiny file
// claiming a 100k x 100k image cannot exhaust memory. Failures never fail the load (colour fallback).
#include <tiny_gltf.h>

#include <cstring>

#include "scene_internal.hpp"

namespace dhr::scene_detail {
namespace {

std::uint32_t be32(const unsigned char* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}
std::uint32_t be16(const unsigned char* p) { return (std::uint32_t{p[0]} << 8) | p[1]; }

// Reads the dimensions from a PNG or JPEG header. False: neither format (or a truncated header).
bool sniff_dimensions(const unsigned char* bytes, std::size_t size, std::uint32_t* out_w, std::uint32_t* out_h) {
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  if (size >= 24 && std::memcmp(bytes, kPng, 8) == 0 && std::memcmp(bytes + 12, "IHDR", 4) == 0) {
    *out_w = be32(bytes + 16);
    *out_h = be32(bytes + 20);
    return true;
  }
  if (size < 4 || bytes[0] != 0xFF || bytes[1] != 0xD8) return false;
  std::size_t pos = 2;
  while (pos + 4 <= size) {
    if (bytes[pos] != 0xFF) return false;
    const unsigned char marker = bytes[pos + 1];
    if (marker == 0xFF) {  // fill byte
      ++pos;
      continue;
    }
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD8)) {  // markers without a length
      pos += 2;
      continue;
    }
    const std::uint32_t length = be16(bytes + pos + 2);
    const bool is_sof = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (is_sof) {
      if (pos + 9 > size) return false;
      *out_h = be16(bytes + pos + 5);
      *out_w = be16(bytes + pos + 7);
      return true;
    }
    if (length < 2) return false;
    pos += 2 + length;
  }
  return false;
}

std::string first_line(const std::string& s) {
  const std::size_t end = s.find('\n');
  return end == std::string::npos ? s : s.substr(0, end);
}

}  // namespace

bool decode_image_callback(tinygltf::Image* image, int image_index, std::string* /*err*/, std::string* /*warn*/,
                           int /*req_width*/, int /*req_height*/, const unsigned char* bytes, int size,
                           void* user_data) {
  auto* ctx = static_cast<ImageDecodeContext*>(user_data);
  if (ctx == nullptr || image == nullptr || image_index < 0) return true;
  const auto idx = static_cast<std::size_t>(image_index);
  if (ctx->failures.size() <= idx) ctx->failures.resize(idx + 1);
  if (!ctx->options->decode_images || idx >= ctx->wanted.size() || !ctx->wanted[idx]) return true;
  if (bytes == nullptr || size <= 0) {
    ctx->failures[idx] = "has no data";
    return true;
  }
  std::uint32_t w = 0;
  std::uint32_t h = 0;
  if (!sniff_dimensions(bytes, static_cast<std::size_t>(size), &w, &h)) {
    ctx->failures[idx] = "is not a PNG or JPEG image";
    return true;
  }
  const std::uint32_t max_dim = ctx->options->max_image_dimension;
  if (w == 0 || h == 0 || w > max_dim || h > max_dim) {
    ctx->failures[idx] = format("is %ux%u pixels (limit %u per side)", w, h, max_dim);
    return true;
  }
  // tinygltf sizes the pixel buffer in int (w * h * 4 channels * 2 bytes for 16-bit PNGs).
  if (std::uint64_t{w} * h > (1ull << 27)) {
    ctx->failures[idx] = format("is %ux%u pixels (more than 2^27 pixels cannot be decoded)", w, h);
    return true;
  }
  const std::uint64_t rgba_bytes = std::uint64_t{w} * h * 4;
  if (ctx->decoded_bytes + rgba_bytes > ctx->options->max_image_bytes) {
    ctx->failures[idx] = format("would exceed the decoded-image budget (%llu bytes)",
                                static_cast<unsigned long long>(ctx->options->max_image_bytes));
    return true;
  }
  std::string decode_error;
  std::string decode_warning;
  // No user data: tinygltf's default options expand every image to RGBA. The requested size is 0
  // because images' JSON width/height are not part of glTF 2.0.
  if (!tinygltf::LoadImageData(image, image_index, &decode_error, &decode_warning, 0, 0, bytes, size, nullptr)) {
    ctx->failures[idx] = "could not be decoded (" + first_line(decode_error) + ")";
    image->image.clear();
    return true;
  }
  ctx->decoded_bytes += image->image.size();
  return true;
}

bool convert_to_rgba8(const tinygltf::Image& image, SceneImage* out, std::string* out_reason) {
  if (image.image.empty()) {
    *out_reason = "could not be read (missing or unreadable file)";
    return false;
  }
  if (image.width <= 0 || image.height <= 0 || image.component < 1 || image.component > 4 ||
      (image.bits != 8 && image.bits != 16)) {
    *out_reason = format("has an unsupported layout (%dx%d, %d channels, %d bits)", image.width, image.height,
                         image.component, image.bits);
    return false;
  }
  const auto pixels = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  const auto channels = static_cast<std::size_t>(image.component);
  const std::size_t bytes_per_channel = image.bits == 16 ? 2 : 1;
  if (image.image.size() != pixels * channels * bytes_per_channel) {
    *out_reason = "has a pixel buffer of the wrong size";
    return false;
  }
  out->width = static_cast<std::uint32_t>(image.width);
  out->height = static_cast<std::uint32_t>(image.height);
  out->rgba8.resize(pixels * 4);
  const unsigned char* src = image.image.data();
  auto channel = [&](std::size_t pixel, std::size_t c) -> std::uint8_t {
    const std::size_t i = pixel * channels + c;
    if (bytes_per_channel == 1) return src[i];
    std::uint16_t v;
    std::memcpy(&v, src + 2 * i, 2);
    return static_cast<std::uint8_t>((std::uint32_t{v} * 255u + 32767u) / 65535u);
  };
  std::uint8_t* dst = out->rgba8.data();
  if (channels == 4 && bytes_per_channel == 1) {
    std::memcpy(dst, src, pixels * 4);
    return true;
  }
  for (std::size_t p = 0; p < pixels; ++p) {
    std::uint8_t r, g, b, a = 255;
    if (channels <= 2) {
      r = g = b = channel(p, 0);
      if (channels == 2) a = channel(p, 1);
    } else {
      r = channel(p, 0);
      g = channel(p, 1);
      b = channel(p, 2);
      if (channels == 4) a = channel(p, 3);
    }
    dst[4 * p + 0] = r;
    dst[4 * p + 1] = g;
    dst[4 * p + 2] = b;
    dst[4 * p + 3] = a;
  }
  return true;
}

}  // namespace dhr::scene_detail
