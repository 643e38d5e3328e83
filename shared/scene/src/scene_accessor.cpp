// Accessor reading with bounds checks against the buffers tinygltf actually loaded (the JSON check in
// scene_validate.cpp used the declared byteLengths; this one guards the memory itself).
#include <tiny_gltf.h>

#include <algorithm>
#include <bit>
#include <cstring>

#include "scene_internal.hpp"

namespace dhr::scene_detail {
namespace {

static_assert(std::endian::native == std::endian::little, "glTF buffers are little-endian; add byte swapping");

const char* type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    case TINYGLTF_TYPE_MAT2:
      return "MAT2";
    case TINYGLTF_TYPE_MAT3:
      return "MAT3";
    case TINYGLTF_TYPE_MAT4:
      return "MAT4";
    default:
      return "?";
  }
}

// Where an accessor's (dense) elements lie in memory; `base` is null when it has no bufferView (zeros).
struct Layout {
  const unsigned char* base = nullptr;
  std::size_t stride = 0;
  std::size_t count = 0;
  int component_type = 0;
  std::size_t component_bytes = 0;
  int components = 0;
  bool normalized = false;
};

// Checks that [offset, offset + stride * (count - 1) + elem) lies inside the bufferView, and the view
// inside its buffer; returns the first byte.
bool locate_view(const tinygltf::Model& model, int view_index, std::size_t offset, std::size_t count,
                 std::size_t stride, std::size_t elem, const char* what, int accessor, const unsigned char** out_base,
                 std::string* out_error) {
  if (view_index < 0 || static_cast<std::size_t>(view_index) >= model.bufferViews.size()) {
    *out_error = format("accessor %d: %s bufferView %d does not exist", accessor, what, view_index);
    return false;
  }
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(view_index)];
  if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size()) {
    *out_error = format("bufferView %d: buffer %d does not exist", view_index, view.buffer);
    return false;
  }
  const std::vector<unsigned char>& data = model.buffers[static_cast<std::size_t>(view.buffer)].data;
  if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset) {
    *out_error = format("bufferView %d: range [%zu, %zu) is past the end of buffer %d (%zu bytes loaded)", view_index,
                        view.byteOffset, view.byteOffset + view.byteLength, view.buffer, data.size());
    return false;
  }
  // count <= 2^32 and stride, elem <= 256 keep this in 64 bits.
  const unsigned long long end = count == 0 ? offset
                                            : static_cast<unsigned long long>(offset) +
                                                  static_cast<unsigned long long>(stride) * (count - 1) + elem;
  if (count > (1ull << 32) || end > view.byteLength) {
    *out_error = format(
        "accessor %d: %s data (offset %zu, stride %zu, count %zu) runs past the end of bufferView %d "
        "(%zu bytes)",
        accessor, what, offset, stride, count, view_index, view.byteLength);
    return false;
  }
  *out_base = data.data() + view.byteOffset + offset;
  return true;
}

bool locate(const tinygltf::Model& model, int index, Layout* out, std::string* out_error) {
  if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) {
    *out_error = format("accessor %d does not exist", index);
    return false;
  }
  const tinygltf::Accessor& a = model.accessors[static_cast<std::size_t>(index)];
  const int comp_bytes = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
  const int components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
  if (comp_bytes <= 0 || components <= 0 || a.componentType == TINYGLTF_COMPONENT_TYPE_INT ||
      a.componentType == TINYGLTF_COMPONENT_TYPE_DOUBLE) {
    *out_error = format("accessor %d: unsupported component type %d / type %d", index, a.componentType, a.type);
    return false;
  }
  out->count = a.count;
  out->component_type = a.componentType;
  out->component_bytes = static_cast<std::size_t>(comp_bytes);
  out->components = components;
  out->normalized = a.normalized;
  const std::size_t elem = out->component_bytes * static_cast<std::size_t>(components);
  out->base = nullptr;
  out->stride = elem;
  if (a.bufferView < 0) return true;  // all zeros (possibly overridden by sparse values)
  const tinygltf::BufferView& view = model.bufferViews.at(static_cast<std::size_t>(std::max(a.bufferView, 0)));
  if (view.byteStride != 0) out->stride = view.byteStride;
  if (out->stride < elem) {
    *out_error =
        format("accessor %d: byteStride %zu is smaller than its element (%zu bytes)", index, out->stride, elem);
    return false;
  }
  return locate_view(model, a.bufferView, a.byteOffset, a.count, out->stride, elem, "its", index, &out->base,
                     out_error);
}

float component_to_float(const unsigned char* p, int component_type, bool normalized) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float f;
      std::memcpy(&f, p, 4);
      return f;
    }
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const auto v = static_cast<std::int8_t>(*p);
      return normalized ? std::max(static_cast<float>(v) / 127.0f, -1.0f) : static_cast<float>(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return normalized ? static_cast<float>(*p) / 255.0f : static_cast<float>(*p);
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      std::int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(static_cast<float>(v) / 32767.0f, -1.0f) : static_cast<float>(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? static_cast<float>(v) / 65535.0f : static_cast<float>(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      std::uint32_t v;
      std::memcpy(&v, p, 4);
      return static_cast<float>(v);
    }
    default:
      return 0.0f;
  }
}

std::uint32_t component_to_index(const unsigned char* p, int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return *p;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    default: {
      std::uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

// Overrides elements listed by a sparse accessor; `write(element, src)` copies one element.
template <typename Write>
bool apply_sparse(const tinygltf::Model& model, int index, std::size_t elem, Write write, std::string* out_error) {
  const tinygltf::Accessor& a = model.accessors[static_cast<std::size_t>(index)];
  if (!a.sparse.isSparse) return true;
  const int ic = a.sparse.indices.componentType;
  if (ic != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ic != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      ic != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
    *out_error = format("accessor %d: sparse indices have component type %d", index, ic);
    return false;
  }
  if (a.sparse.count <= 0 || static_cast<std::size_t>(a.sparse.count) > a.count || a.sparse.indices.byteOffset < 0 ||
      a.sparse.values.byteOffset < 0) {
    *out_error = format("accessor %d: invalid sparse count %d", index, a.sparse.count);
    return false;
  }
  const auto count = static_cast<std::size_t>(a.sparse.count);
  const auto ibytes = static_cast<std::size_t>(tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(ic)));
  const unsigned char* indices = nullptr;
  const unsigned char* values = nullptr;
  if (!locate_view(model, a.sparse.indices.bufferView, static_cast<std::size_t>(a.sparse.indices.byteOffset), count,
                   ibytes, ibytes, "sparse indices", index, &indices, out_error) ||
      !locate_view(model, a.sparse.values.bufferView, static_cast<std::size_t>(a.sparse.values.byteOffset), count, elem,
                   elem, "sparse values", index, &values, out_error)) {
    return false;
  }
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t target = component_to_index(indices + i * ibytes, ic);
    if (target >= a.count) {
      *out_error = format("accessor %d: sparse index %u out of range (count %zu)", index, target, a.count);
      return false;
    }
    write(target, values + i * elem);
  }
  return true;
}

}  // namespace

bool read_accessor_floats(const tinygltf::Model& model, int accessor, int components, std::vector<float>* out,
                          std::string* out_error) {
  Layout l;
  if (!locate(model, accessor, &l, out_error)) return false;
  const tinygltf::Accessor& a = model.accessors[static_cast<std::size_t>(accessor)];
  if (l.components != components) {
    *out_error = format("accessor %d has type %s, expected %d components", accessor, type_name(a.type), components);
    return false;
  }
  if (l.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
    *out_error = format("accessor %d: unsigned int components are not allowed for vertex attributes", accessor);
    return false;
  }
  const auto n = static_cast<std::size_t>(components);
  out->assign(l.count * n, 0.0f);
  float* dst = out->data();
  if (l.base) {
    if (l.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT && l.stride == 4 * n) {
      std::memcpy(dst, l.base, l.count * 4 * n);  // tightly packed floats: the common case
    } else {
      for (std::size_t i = 0; i < l.count; ++i) {
        const unsigned char* src = l.base + i * l.stride;
        for (std::size_t c = 0; c < n; ++c) {
          dst[i * n + c] = component_to_float(src + c * l.component_bytes, l.component_type, l.normalized);
        }
      }
    }
  }
  const std::size_t elem = l.component_bytes * n;
  return apply_sparse(
      model, accessor, elem,
      [&](std::uint32_t target, const unsigned char* src) {
        for (std::size_t c = 0; c < n; ++c) {
          dst[target * n + c] = component_to_float(src + c * l.component_bytes, l.component_type, l.normalized);
        }
      },
      out_error);
}

bool read_accessor_indices(const tinygltf::Model& model, int accessor, std::vector<std::uint32_t>* out,
                           std::string* out_error) {
  Layout l;
  if (!locate(model, accessor, &l, out_error)) return false;
  if (l.components != 1 || l.normalized ||
      (l.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
       l.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
       l.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)) {
    *out_error =
        format("accessor %d cannot hold indices (needs SCALAR unsigned byte/short/int, not normalized)", accessor);
    return false;
  }
  out->assign(l.count, 0u);
  if (l.base) {
    for (std::size_t i = 0; i < l.count; ++i) (*out)[i] = component_to_index(l.base + i * l.stride, l.component_type);
  }
  return apply_sparse(
      model, accessor, l.component_bytes,
      [&](std::uint32_t target, const unsigned char* src) {
        (*out)[target] = component_to_index(src, l.component_type);
      },
      out_error);
}

}  // namespace dhr::scene_detail
