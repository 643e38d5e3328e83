// Zero-initialised OpenXR structs with their type tag set: `T x{XR_TYPE_...}` would trip
// -Wmissing-field-initializers, and a forgotten type tag is a classic OpenXR bug.
#pragma once
#include <openxr/openxr.h>

namespace dhr::xr {

template <typename T>
T make_xr(XrStructureType type) {
  T value{};
  value.type = type;
  return value;
}

}  // namespace dhr::xr
