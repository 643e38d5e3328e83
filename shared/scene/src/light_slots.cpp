#include "scene/light_slots.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>

#include "shaders/shader_interface.h"
#include "visibility/visibility_layout.hpp"

namespace dhr {
namespace {

constexpr float kMaxPlacedRangeM = 1e4f;

// Whole millimetres; positions beyond this are refused (their squares must stay far inside int64).
constexpr double kMaxCoordinateMm = 1e9;

int64_t to_mm(double metres, const char* what) {
  const double mm = std::round(metres * 1000.0);
  if (!std::isfinite(mm) || std::fabs(mm) > kMaxCoordinateMm) {
    throw std::invalid_argument(std::string("light slots: ") + what + " is not finite or beyond 1e6 m");
  }
  return static_cast<int64_t>(mm);
}

// A light placed in the grid: its centre and reach (range + margin), mm.
struct Reach {
  std::array<int64_t, 3> centre{};
  int64_t radius = 0;
};

int64_t floor_div(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

// Squared distance from `c` to the box [lo, hi] along one axis.
int64_t axis_gap(int64_t c, int64_t lo, int64_t hi) { return c < lo ? lo - c : c > hi ? c - hi : 0; }

}  // namespace

LightSlots LightSlots::identity(uint32_t light_count) {
  if (light_count > kMaxLights) throw std::invalid_argument("light slots: the identity holds at most 32 lights");
  LightSlots slots;
  slots.slot_of_.resize(light_count);
  slots.slot_soft_.assign(light_count, false);
  slots.table_.resize(light_count);
  for (uint32_t i = 0; i < light_count; ++i) slots.slot_of_[i] = slots.table_[i] = static_cast<uint16_t>(i);
  slots.max_per_cell_ = light_count;
  return slots;
}

LightSlots LightSlots::assign(std::span<const SceneLight> lights) {
  if (lights.size() > kMaxSlotLights) {
    throw std::invalid_argument("light slots: " + std::to_string(lights.size()) + " lights (at most " +
                                std::to_string(kMaxSlotLights) + ")");
  }
  const uint32_t n = static_cast<uint32_t>(lights.size());
  if (n <= kMaxLights) {
    LightSlots slots = identity(n);
    for (uint32_t i = 0; i < n; ++i) slots.slot_soft_[i] = lights[i].has_extent();
    return slots;
  }

  LightSlots slots;
  slots.identity_ = false;
  slots.slot_of_.assign(n, kNoSlotLight);
  std::vector<Reach> reach(n);
  std::vector<bool> gridded(n, false);
  std::array<int64_t, 3> lo{}, hi{};
  bool any = false;
  for (uint32_t i = 0; i < n; ++i) {
    const SceneLight& l = lights[i];
    // A range beyond kMaxPlacedRangeM reaches as far as none: global (a legal glTF value must not refuse the scene).
    const bool placed = l.range > 0.0f && l.range <= kMaxPlacedRangeM &&
                        (l.type == SceneLight::Type::kPoint || l.type == SceneLight::Type::kSpot);
    if (!placed) continue;
    gridded[i] = true;
    for (int a = 0; a < 3; ++a) reach[i].centre[a] = to_mm(l.position[a], "a light's position");
    reach[i].radius = to_mm(l.range, "a light's range") + kSlotMarginMm;
    for (int a = 0; a < 3; ++a) {
      const int64_t a0 = reach[i].centre[a] - reach[i].radius, a1 = reach[i].centre[a] + reach[i].radius;
      lo[a] = any ? std::min(lo[a], a0) : a0;
      hi[a] = any ? std::max(hi[a], a1) : a1;
    }
    any = true;
  }

  // Global lights first, one slot each, in light order; the bits they take are gone for the rest.
  uint32_t bits = 0;
  const auto bits_of = [&](uint32_t i) { return lights[i].has_extent() ? kSoftLevelBits : 1u; };
  for (uint32_t i = 0; i < n; ++i) {
    if (gridded[i]) continue;
    if (bits + bits_of(i) > 32) {
      slots.dropped_.push_back(i);
      continue;
    }
    bits += bits_of(i);
    slots.slot_of_[i] = static_cast<uint16_t>(slots.slot_soft_.size());
    slots.slot_soft_.push_back(lights[i].has_extent());
    ++slots.global_;
  }

  // The grid: cells of kSlotCellMm, doubled until at most kMaxSlotCells cover every light's reach.
  if (any) {
    int64_t cell = kSlotCellMm;
    std::array<uint32_t, 3> dims{};
    for (;;) {
      uint64_t total = 1;
      for (int a = 0; a < 3; ++a) {
        dims[a] = static_cast<uint32_t>((hi[a] - lo[a]) / cell + 1);
        total *= dims[a];
      }
      if (total <= kMaxSlotCells) break;
      cell *= 2;
    }
    slots.origin_mm_ = lo;
    slots.cell_mm_ = cell;
    slots.cells_ = dims;
    slots.grid_cells_ = dims[0] * dims[1] * dims[2];
  }

  // The cells each light's reach touches (integer sphere-box test), and per cell the lights touching it.
  std::vector<std::vector<uint32_t>> touched(n);
  std::vector<std::vector<uint16_t>> in_cell(slots.grid_cells_);
  for (uint32_t i = 0; i < n; ++i) {
    if (!gridded[i]) continue;
    const Reach& r = reach[i];
    std::array<int64_t, 3> c0{}, c1{};
    for (int a = 0; a < 3; ++a) {
      c0[a] = std::max<int64_t>(floor_div(r.centre[a] - r.radius - slots.origin_mm_[a], slots.cell_mm_), 0);
      c1[a] = std::min<int64_t>(floor_div(r.centre[a] + r.radius - slots.origin_mm_[a], slots.cell_mm_),
                                slots.cells_[a] - 1);
    }
    for (int64_t z = c0[2]; z <= c1[2]; ++z) {
      for (int64_t y = c0[1]; y <= c1[1]; ++y) {
        for (int64_t x = c0[0]; x <= c1[0]; ++x) {
          const std::array<int64_t, 3> c{x, y, z};
          int64_t d2 = 0;
          for (int a = 0; a < 3; ++a) {
            const int64_t box_lo = slots.origin_mm_[a] + c[a] * slots.cell_mm_;
            const int64_t g = axis_gap(r.centre[a], box_lo, box_lo + slots.cell_mm_);
            d2 += g * g;
          }
          if (d2 > r.radius * r.radius) continue;
          const uint32_t index = static_cast<uint32_t>((z * slots.cells_[1] + y) * slots.cells_[0] + x);
          touched[i].push_back(index);
          in_cell[index].push_back(static_cast<uint16_t>(i));
        }
      }
    }
  }
  // Two lights conflict when some cell holds both.
  using LightSet = std::array<uint64_t, kMaxSlotLights / 64>;
  std::vector<LightSet> conflicts(n, LightSet{});
  for (const std::vector<uint16_t>& cell : in_cell)
    for (uint16_t a : cell)
      for (uint16_t b : cell)
        if (a != b) conflicts[a][b / 64] |= uint64_t{1} << (b % 64);
  std::vector<uint32_t> degree(n, 0);
  for (uint32_t i = 0; i < n; ++i)
    for (uint64_t word : conflicts[i]) degree[i] += static_cast<uint32_t>(__builtin_popcountll(word));

  // DSatur colouring: next, the uncoloured light whose conflicts hold the most distinct slots (then the most
  // conflicts, then the lowest index); it takes the lowest slot of its kind none of them holds, else a new slot
  // while the 32 bits last, else it is dropped. saturation[i]: the slots i's coloured conflicts hold.
  std::vector<uint32_t> saturation(n, 0);
  std::vector<bool> done(n, true);
  uint32_t left = 0;
  for (uint32_t i = 0; i < n; ++i)
    if (gridded[i]) done[i] = false, ++left;
  for (; left > 0; --left) {
    uint32_t next = n;
    for (uint32_t i = 0; i < n; ++i) {
      if (done[i]) continue;
      if (next == n) {
        next = i;
        continue;
      }
      const int si = __builtin_popcount(saturation[i]), sn = __builtin_popcount(saturation[next]);
      if (si > sn || (si == sn && degree[i] > degree[next])) next = i;
    }
    done[next] = true;
    const bool soft = lights[next].has_extent();
    uint32_t slot = slots.slot_count();
    for (uint32_t s = slots.global_; s < slots.slot_count(); ++s) {
      if ((saturation[next] >> s & 1u) == 0 && slots.slot_soft_[s] == soft) {
        slot = s;
        break;
      }
    }
    if (slot == slots.slot_count()) {
      if (bits + bits_of(next) > 32) {
        slots.dropped_.push_back(next);
        touched[next].clear();
        continue;
      }
      bits += bits_of(next);
      slots.slot_soft_.push_back(soft);
    }
    slots.slot_of_[next] = static_cast<uint16_t>(slot);
    for (uint32_t w = 0; w < conflicts[next].size(); ++w)
      for (uint64_t word = conflicts[next][w]; word != 0; word &= word - 1)
        saturation[w * 64 + static_cast<uint32_t>(__builtin_ctzll(word))] |= 1u << slot;
  }
  std::sort(slots.dropped_.begin(), slots.dropped_.end());

  // The table: per cell, its light in each slot; global slots hold their light everywhere; the last row is outside.
  const uint32_t w = slots.slot_count();
  slots.table_.assign(static_cast<size_t>(slots.grid_cells_ + 1) * w, kNoSlotLight);
  for (uint32_t i = 0; i < n; ++i) {
    if (slots.slot_of_[i] == kNoSlotLight) continue;
    if (!gridded[i]) {
      for (uint32_t c = 0; c <= slots.grid_cells_; ++c) slots.table_[static_cast<size_t>(c) * w + slots.slot_of_[i]] = static_cast<uint16_t>(i);
    } else {
      for (uint32_t c : touched[i]) slots.table_[static_cast<size_t>(c) * w + slots.slot_of_[i]] = static_cast<uint16_t>(i);
    }
  }
  for (uint32_t c = 0; c <= slots.grid_cells_; ++c) {
    uint32_t count = 0;
    for (uint32_t s = 0; s < w; ++s) count += slots.table_[static_cast<size_t>(c) * w + s] != kNoSlotLight;
    slots.max_per_cell_ = std::max(slots.max_per_cell_, count);
  }
  return slots;
}

uint32_t LightSlots::cell_index(const glm::dvec3& p) const {
  // Per hit of the tracer: a multiply by the cell's inverse and a truncation (the value is checked non-negative
  // first), not a division and a floor. Rounding at a cell boundary may differ from the exact quotient's, which the
  // margin makes harmless (a light reaching the point is registered in both cells).
  const double per_mm = 1.0 / static_cast<double>(cell_mm_);
  uint32_t c[3];
  for (int a = 0; a < 3; ++a) {
    const double v = (p[a] * 1000.0 - static_cast<double>(origin_mm_[a])) * per_mm;
    if (!(v >= 0.0 && v < static_cast<double>(cells_[a]))) return grid_cells_;  // outside (NaN too)
    c[a] = static_cast<uint32_t>(v);
  }
  return (c[2] * cells_[1] + c[1]) * cells_[0] + c[0];
}

const uint16_t* LightSlots::lights_at(const glm::dvec3& p) const { return lights_in(cell_of(p)); }

std::vector<SceneLight> LightSlots::field_lights(std::span<const SceneLight> lights) const {
  if (lights.size() != slot_of_.size()) throw std::invalid_argument("light slots: field_lights of other lights");
  std::vector<SceneLight> out(slot_count());
  std::vector<bool> set(slot_count(), false);
  for (uint32_t i = 0; i < lights.size(); ++i) {
    const uint16_t s = slot_of_[i];
    if (s == kNoSlotLight || set[s]) continue;
    out[s] = lights[i];
    set[s] = true;
  }
  return out;
}

std::vector<uint32_t> LightSlots::gpu_words(const glm::dvec3& relative_to) const {
  std::vector<uint32_t> out(shader::kVisSlotHeaderWords, 0u);
  if (is_identity()) return out;  // never read: the shaders are told about slots only when there are some
  for (int a = 0; a < 3; ++a)
    out[a] = std::bit_cast<uint32_t>(static_cast<float>(static_cast<double>(origin_mm_[a]) - relative_to[a] * 1000.0));
  out[3] = std::bit_cast<uint32_t>(static_cast<float>(cell_mm_));
  for (int a = 0; a < 3; ++a) out[4 + a] = cells_[a];
  out[7] = slot_count();
  out.reserve(out.size() + table_.size());
  for (uint16_t light : table_) out.push_back(light == kNoSlotLight ? shader::kVisNoSlotLight : light);
  return out;
}

std::string LightSlots::describe() const {
  if (is_identity()) return std::to_string(light_count()) + " lights, one slot each";
  std::string s = std::to_string(light_count()) + " lights in " + std::to_string(slot_count()) + " slots (" +
                  std::to_string(global_) + " global, grid " + std::to_string(cells_[0]) + " x " +
                  std::to_string(cells_[1]) + " x " + std::to_string(cells_[2]) + " cells of " +
                  std::to_string(cell_mm_) + " mm, at most " + std::to_string(max_per_cell_) + " lights per cell)";
  if (!dropped_.empty()) s += ", " + std::to_string(dropped_.size()) + " left without a slot";
  return s;
}

}  // namespace dhr
