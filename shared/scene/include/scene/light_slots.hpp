// Many lights in one 32-bit mask (issue 28, "Many lights"; docs/server.md, "Light slots"). A mask holds at most 32
// bits, so a scene with more lights than kMaxLights gives each light a *slot* (a field of the mask) shared with
// lights that can never reach the same surface point: the lights are coloured by a world grid. A light with a range
// is registered in every grid cell its reach (range + kSlotMarginM) touches, and lights registered in a common
// cell take different slots; a light without a range (and the sun) is *global*: its own slot, in every cell. A
// pixel's field `s` is then the visibility of the one light slot `s` holds in the cell of the pixel's surface
// point (none: the field is 0 and nothing is added). Both ends derive the slots from the scene's lights (the
// scene hash is checked at the handshake), so nothing of them travels; the grid is computed in integer
// millimetres so that both ends get the same slots whatever their floating-point unit does. A surface point that
// lies within the margin of a cell boundary may be binned differently by the two ends, which is harmless: a light
// reaching the point is registered in every cell within the margin, in the same slot.
//
// With at most kMaxLights lights the slots are the identity (slot i = light i, no grid): masks are exactly those
// of before. Lights that find no slot within 32 bits are left out of every mask and named (dropped()). Slots are
// placed where the lights stand at rest: the tracers and the client refuse a scene with more than kMaxLights lights
// and animation.
#pragma once
#include <array>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace dhr {

inline constexpr uint16_t kNoSlotLight = 0xFFFFu;
inline constexpr uint32_t kMaxSlotLights = 256;  // lights LightSlots::assign places
inline constexpr int64_t kSlotCellMm = 250;     // the grid's cell edge, mm (grown to keep at most kMaxSlotCells)
inline constexpr int64_t kSlotMarginMm = 50;    // a light's reach is its range plus this, mm
inline constexpr uint32_t kMaxSlotCells = 1u << 16;

class LightSlots {
 public:
  // The identity for `light_count` lights (<= kMaxLights).
  static LightSlots identity(uint32_t light_count);
  // Slots for `lights` (at most kMaxSlotLights): the identity for at most kMaxLights lights, else the grid
  // colouring above. A soft light (an extent) takes a slot of soft lights (kSoftLevelBits bits), a hard light a
  // slot of hard ones. Throws std::invalid_argument for more than kMaxSlotLights lights or a non-finite position
  // or range.
  static LightSlots assign(std::span<const SceneLight> lights);

  bool is_identity() const { return identity_; }
  uint32_t light_count() const { return static_cast<uint32_t>(slot_of_.size()); }
  uint32_t slot_count() const { return static_cast<uint32_t>(slot_soft_.size()); }
  // Light i's slot; kNoSlotLight for a dropped light.
  uint16_t slot_of(uint32_t light) const { return slot_of_[light]; }
  // Per slot: it holds soft lights (VisibilityLayout::for_lights takes this).
  const std::vector<bool>& soft_slots() const { return slot_soft_; }
  // Lights left without a slot (their indices, ascending).
  const std::vector<uint32_t>& dropped() const { return dropped_; }
  // Lights that hold a slot alone in every cell (no range).
  uint32_t global_lights() const { return global_; }

  // The slot_count() lights of the cell holding `p` (world, metres), kNoSlotLight where a slot has none there.
  // For the identity: 0, 1, ... everywhere.
  const uint16_t* lights_at(const glm::dvec3& p) const;
  uint16_t light_at(uint32_t slot, const glm::dvec3& p) const { return lights_at(p)[slot]; }
  // The grid cell holding `p` (world, metres): points of one cell have the same lights_at. One id for every point
  // outside the grid, and 0 everywhere for the identity.
  uint32_t cell_of(const glm::dvec3& p) const { return grid_cells_ == 0 ? 0u : cell_index(p); }
  // lights_at for a point of cell `cell` (cell_of's).
  const uint16_t* lights_in(uint32_t cell) const { return table_.data() + static_cast<size_t>(cell) * slot_count(); }

  // The grid, for the client's shaders (which bin a point the same way, in float): cell c = (x, y, z) covers
  // [origin + c * cell, origin + (c + 1) * cell) in mm; table() has slot_count() entries per cell, x fastest, then
  // one row for points outside the grid (global lights only).
  const std::array<int64_t, 3>& origin_mm() const { return origin_mm_; }
  int64_t cell_mm() const { return cell_mm_; }
  const std::array<uint32_t, 3>& cells() const { return cells_; }
  const std::vector<uint16_t>& table() const { return table_; }
  // The most lights any cell holds (what a pixel can need traced or shaded).
  uint32_t max_lights_per_cell() const { return max_per_cell_; }

  // One light per field, the lowest-indexed light slot f holds (its kind is the slot's): what a pass that only
  // counts the fields and their kinds is given. For the identity: the lights. `lights`: those assign() was given.
  std::vector<SceneLight> field_lights(std::span<const SceneLight> lights) const;

  // What the shaders read (shaders/shader_interface.h, kVisSlotHeaderWords): the grid's origin in mm relative to
  // `relative_to` (metres, subtracted in double, then float bits), its cell edge (float bits), its cells per axis,
  // the fields per row, then the table, one uint per entry (kVisNoSlotLight: none). Just the header for the identity.
  std::vector<uint32_t> gpu_words(const glm::dvec3& relative_to) const;

  // One line for logs: "N lights in S slots (G global, grid X x Y x Z cells of C mm, at most M per cell), D dropped".
  std::string describe() const;

  bool operator==(const LightSlots&) const = default;

 private:
  uint32_t cell_index(const glm::dvec3& p) const;  // grid_cells_ when outside

  bool identity_ = true;
  std::vector<uint16_t> slot_of_;
  std::vector<bool> slot_soft_;
  std::vector<uint32_t> dropped_;
  uint32_t global_ = 0;
  std::array<int64_t, 3> origin_mm_{};
  int64_t cell_mm_ = kSlotCellMm;
  std::array<uint32_t, 3> cells_{};
  uint32_t grid_cells_ = 0;
  std::vector<uint16_t> table_;
  uint32_t max_per_cell_ = 0;
};

}  // namespace dhr
