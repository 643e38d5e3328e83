// The per-eye visibility buffer: for each pixel of the guard-banded image, a mask whose bit i is 1 when
// light i is visible (lit) from that pixel. Stored tightly packed, row-major, each mask little-endian in
// 1, 2 or 4 bytes, so the client can upload it unchanged as an R8/R16/R32_UINT image.
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace dhr {

inline constexpr uint32_t kMaxLights = 32;
// Per-eye width or height, guard band included. 4096 keeps the worst-case shard count of a frame
// (incompressible 32-bit masks) within the 16-bit shard index of the wire format.
inline constexpr uint32_t kMaxBufferDimension = 4096;

enum class MaskWidth : uint8_t { k8 = 8, k16 = 16, k32 = 32 };

// 0-8 lights -> 8 bits, 9-16 -> 16, 17-32 -> 32 (callers reject more than kMaxLights).
constexpr MaskWidth mask_width_for_light_count(uint32_t light_count) {
  return light_count <= 8 ? MaskWidth::k8 : light_count <= 16 ? MaskWidth::k16 : MaskWidth::k32;
}
constexpr uint32_t mask_bytes(MaskWidth width) { return static_cast<uint32_t>(width) / 8; }
// 8, 16 or 32 -> the width; anything else -> nullopt (for decoders).
std::optional<MaskWidth> mask_width_from_bits(uint32_t bits);

// Reads / writes one little-endian mask of `bytes` (1, 2 or 4) bytes.
inline uint32_t load_mask(const uint8_t* p, uint32_t bytes) {
  uint32_t v = p[0];
  if (bytes >= 2) v |= static_cast<uint32_t>(p[1]) << 8;
  if (bytes == 4) v |= static_cast<uint32_t>(p[2]) << 16 | static_cast<uint32_t>(p[3]) << 24;
  return v;
}
inline void store_mask(uint8_t* p, uint32_t bytes, uint32_t v) {
  p[0] = static_cast<uint8_t>(v);
  if (bytes >= 2) p[1] = static_cast<uint8_t>(v >> 8);
  if (bytes == 4) {
    p[2] = static_cast<uint8_t>(v >> 16);
    p[3] = static_cast<uint8_t>(v >> 24);
  }
}

struct VisibilityBuffer {
  uint32_t width = 0;
  uint32_t height = 0;
  // Bits in use per mask: one per light in the hard layout, VisibilityLayout::total_bits() with soft levels
  // (whoever interprets the masks holds the layout; the codecs and the reassembler code bits).
  uint32_t light_count = 0;
  MaskWidth mask_bits = MaskWidth::k8;
  std::vector<uint8_t> data;  // width * height masks, row-major, mask_bytes(mask_bits) bytes each

  // A zeroed (all dark) buffer; the mask width follows light_count. Throws std::invalid_argument for
  // light_count > kMaxLights or a dimension above kMaxBufferDimension (setup code, not per packet).
  static VisibilityBuffer create(uint32_t width, uint32_t height, uint32_t light_count);

  uint32_t bytes_per_mask() const { return mask_bytes(mask_bits); }
  size_t pixel_count() const { return static_cast<size_t>(width) * height; }
  size_t size_bytes() const { return pixel_count() * bytes_per_mask(); }
  // Bits that may be set: (1 << light_count) - 1 (VisibilityLayout::used_bits()).
  uint32_t light_bits() const { return light_count >= 32 ? 0xFFFFFFFFu : (1u << light_count) - 1u; }

  uint32_t mask_at(size_t pixel) const { return load_mask(&data[pixel * bytes_per_mask()], bytes_per_mask()); }
  void set_mask_at(size_t pixel, uint32_t mask) { store_mask(&data[pixel * bytes_per_mask()], bytes_per_mask(), mask); }
  uint32_t get(uint32_t x, uint32_t y) const { return mask_at(static_cast<size_t>(y) * width + x); }
  void set(uint32_t x, uint32_t y, uint32_t mask) { set_mask_at(static_cast<size_t>(y) * width + x, mask); }

  // The same masks stored at another width (e.g. 32 bits: what the codec would send without the light-count
  // width). Throws std::invalid_argument when a mask does not fit the narrower width.
  VisibilityBuffer with_mask_width(MaskWidth width) const;

  bool operator==(const VisibilityBuffer&) const = default;
};

}  // namespace dhr
