// One glTF primitive instance -> a world-space triangle list: strips/fans converted, indices and
// positions validated, transforms applied in double, normals transformed by the inverse transpose,
// generated (flat) when absent and repaired when unusable.
#include <tiny_gltf.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <numeric>

#include "scene_internal.hpp"

namespace dhr::scene_detail {
namespace {

bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Converts the primitive's index sequence to a triangle list in place (glTF 2.0 section 3.7.2.1).
// Strip/fan triangles that repeat a vertex are dropped: they have no area (strips use them as restarts).
std::vector<std::uint32_t> to_triangle_list(const std::vector<std::uint32_t>& seq, int mode) {
  std::vector<std::uint32_t> out;
  if (mode == TINYGLTF_MODE_TRIANGLES) return seq;
  if (seq.size() < 3) return out;
  out.reserve((seq.size() - 2) * 3);
  for (std::size_t i = 0; i + 2 < seq.size(); ++i) {
    std::uint32_t a, b, c;
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      // p_i = {v_i, v_{i+(1+i%2)}, v_{i+(2-i%2)}} keeps every triangle's winding.
      a = seq[i];
      b = seq[i + 1 + (i % 2)];
      c = seq[i + 2 - (i % 2)];
    } else {  // fan: p_i = {v_{i+1}, v_{i+2}, v_0}
      a = seq[i + 1];
      b = seq[i + 2];
      c = seq[0];
    }
    if (a == b || b == c || a == c) continue;
    out.insert(out.end(), {a, b, c});
  }
  return out;
}

glm::dvec3 face_normal_raw(const std::vector<glm::vec3>& p, const std::uint32_t* tri) {
  const glm::dvec3 a(p[tri[0]]);
  return glm::cross(glm::dvec3(p[tri[1]]) - a, glm::dvec3(p[tri[2]]) - a);
}

glm::vec3 unit_or_up(const glm::dvec3& v) {
  const double len = glm::length(v);
  if (!(len > 1e-30) || !std::isfinite(len)) return glm::vec3(0.0f, 1.0f, 0.0f);
  return glm::vec3(v / len);
}

}  // namespace

bool convert_primitive(const tinygltf::Model& model, const tinygltf::Primitive& primitive, const PrimitiveContext& ctx,
                       Budget& budget, SceneStats& stats, WarningSink& warnings, SceneMesh* out,
                       std::string* out_error) {
  const std::string where = format("mesh %d primitive %d (%s)", ctx.mesh, ctx.primitive, ctx.name.c_str());
  auto fail = [&](const std::string& message) {
    *out_error = where + ": " + message;
    return false;
  };
  const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
  auto pos_it = primitive.attributes.find("POSITION");
  if (pos_it == primitive.attributes.end()) return fail("has no POSITION attribute");
  const int pos_accessor = pos_it->second;
  if (pos_accessor < 0 || static_cast<std::size_t>(pos_accessor) >= model.accessors.size()) {
    return fail(format("POSITION accessor %d does not exist", pos_accessor));
  }
  const std::size_t vertex_count = model.accessors[static_cast<std::size_t>(pos_accessor)].count;
  std::size_t sequence_length = vertex_count;
  if (primitive.indices >= 0) {
    if (static_cast<std::size_t>(primitive.indices) >= model.accessors.size()) {
      return fail(format("indices accessor %d does not exist", primitive.indices));
    }
    sequence_length = model.accessors[static_cast<std::size_t>(primitive.indices)].count;
  }
  if (mode == TINYGLTF_MODE_TRIANGLES && sequence_length % 3 != 0) {
    return fail(format("a triangle list needs a multiple of 3 %s, but has %zu",
                       primitive.indices >= 0 ? "indices" : "vertices", sequence_length));
  }
  // Budget before reading anything: an accessor's count alone must not make us allocate gigabytes.
  const std::uint64_t max_triangles =
      mode == TINYGLTF_MODE_TRIANGLES ? sequence_length / 3 : (sequence_length >= 3 ? sequence_length - 2 : 0);
  const bool has_normals = primitive.attributes.count("NORMAL") != 0;
  const std::uint64_t max_vertices = has_normals ? vertex_count : 3 * max_triangles;
  if (max_triangles > budget.triangles_left) {
    return fail(format("exceeds the triangle limit (max_triangles, %llu triangles left)",
                       static_cast<unsigned long long>(budget.triangles_left)));
  }
  if (max_vertices > budget.vertices_left) {
    return fail(format("exceeds the vertex limit (max_vertices, %llu vertices left)",
                       static_cast<unsigned long long>(budget.vertices_left)));
  }

  // Local-space data.
  std::vector<float> positions;
  if (!read_accessor_floats(model, pos_accessor, 3, &positions, out_error)) return fail("POSITION: " + *out_error);
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (!std::isfinite(positions[i])) {
      return fail(format("POSITION (accessor %d) has a non-finite value at vertex %zu", pos_accessor, i / 3));
    }
  }
  std::vector<std::uint32_t> sequence;
  if (primitive.indices >= 0) {
    if (!read_accessor_indices(model, primitive.indices, &sequence, out_error)) return fail("indices: " + *out_error);
    std::size_t bad = 0;
    std::size_t first_bad = 0;
    for (std::size_t i = 0; i < sequence.size(); ++i) {
      if (sequence[i] >= vertex_count) {
        if (bad++ == 0) first_bad = i;
      }
    }
    if (bad > 0) {
      return fail(format("%zu of %zu indices are out of range (index %u at position %zu, but only %zu vertices)", bad,
                         sequence.size(), sequence[first_bad], first_bad, vertex_count));
    }
  } else {
    sequence.resize(vertex_count);
    std::iota(sequence.begin(), sequence.end(), 0u);
  }
  std::vector<std::uint32_t> indices = to_triangle_list(sequence, mode);
  if (ctx.first_instance) {
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) ++stats.strips_converted;
    if (mode == TINYGLTF_MODE_TRIANGLE_FAN) ++stats.fans_converted;
  }

  std::vector<float> normals;
  if (has_normals) {
    const int accessor = primitive.attributes.at("NORMAL");
    if (!read_accessor_floats(model, accessor, 3, &normals, out_error)) return fail("NORMAL: " + *out_error);
    if (normals.size() != positions.size()) {
      return fail(format("NORMAL has %zu elements but POSITION has %zu", normals.size() / 3, vertex_count));
    }
  }
  std::vector<float> texcoords;
  if (ctx.texcoord_set >= 0) {
    const std::string attribute = "TEXCOORD_" + std::to_string(ctx.texcoord_set);
    auto it = primitive.attributes.find(attribute);
    if (it != primitive.attributes.end()) {
      if (!read_accessor_floats(model, it->second, 2, &texcoords, out_error))
        return fail(attribute + ": " + *out_error);
      if (texcoords.size() / 2 != vertex_count) {
        return fail(
            format("%s has %zu elements but POSITION has %zu", attribute.c_str(), texcoords.size() / 2, vertex_count));
      }
      std::size_t bad = 0;
      for (float& t : texcoords) {
        if (!std::isfinite(t)) {
          t = 0.0f;
          ++bad;
        }
      }
      if (bad > 0 && ctx.first_instance) warnings.add(where + ": " + attribute + " has non-finite values; set to 0");
    } else if (ctx.texcoord_required && ctx.first_instance) {
      warnings.add(where + ": its material's base colour texture uses " + attribute +
                   ", which the primitive lacks; the texture is ignored there (colour factor only)");
    }
  }

  // To world space (double), keeping counter-clockwise front faces under mirroring transforms.
  const glm::dmat4& M = ctx.T_world_local;
  const glm::dmat3 linear(M);
  const double det = glm::determinant(linear);
  glm::dmat3 normal_matrix = linear;
  if (std::isfinite(det) && std::abs(det) > 1e-300) normal_matrix = glm::transpose(glm::inverse(linear));
  if (det < 0.0) {
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) std::swap(indices[t + 1], indices[t + 2]);
  }
  std::vector<glm::vec3> world(vertex_count);
  for (std::size_t i = 0; i < vertex_count; ++i) {
    const glm::dvec3 w = glm::dvec3(M * glm::dvec4(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2], 1.0));
    if (!finite3(w) || std::abs(w.x) > 3.0e38 || std::abs(w.y) > 3.0e38 || std::abs(w.z) > 3.0e38) {
      return fail(format("vertex %zu is not finite after the node transform", i));
    }
    world[i] = glm::vec3(w);
  }

  out->name = ctx.name;
  out->material = ctx.material;
  out->geometry = ctx.geometry;
  out->node = ctx.node;
  out->T_world_local = M;
  if (!has_normals) {
    // glTF: without normals, flat shading. Unweld so each corner carries its face's normal.
    if (ctx.first_instance) ++stats.meshes_with_generated_normals;
    out->positions.resize(indices.size());
    out->normals.resize(indices.size());
    if (!texcoords.empty()) out->texcoords.resize(indices.size());
    out->indices.resize(indices.size());
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
      const glm::vec3 n = unit_or_up(face_normal_raw(world, &indices[t]));
      for (std::size_t k = 0; k < 3; ++k) {
        const std::uint32_t v = indices[t + k];
        out->positions[t + k] = world[v];
        out->normals[t + k] = n;
        if (!texcoords.empty())
          out->texcoords[t + k] = ctx.uv_transform.apply({texcoords[2 * v], texcoords[2 * v + 1]});
        out->indices[t + k] = static_cast<std::uint32_t>(t + k);
      }
    }
  } else {
    out->positions = std::move(world);
    out->normals.resize(vertex_count);
    std::vector<std::uint32_t> broken;
    std::uint64_t renormalized = 0;
    for (std::size_t i = 0; i < vertex_count; ++i) {
      const glm::dvec3 n(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]);
      const double len = glm::length(n);
      if (!std::isfinite(len) || len < 1e-6) {
        broken.push_back(static_cast<std::uint32_t>(i));
        continue;
      }
      if (std::abs(len - 1.0) > 5e-3) ++renormalized;
      out->normals[i] = unit_or_up(normal_matrix * (n / len));
    }
    if (!broken.empty()) {
      // Area-weighted average of the adjacent faces (the raw cross product is area-weighted already).
      std::vector<glm::dvec3> sum(vertex_count, glm::dvec3(0.0));
      for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
        const glm::dvec3 f = face_normal_raw(out->positions, &indices[t]);
        for (std::size_t k = 0; k < 3; ++k) sum[indices[t + k]] += f;
      }
      for (std::uint32_t v : broken) out->normals[v] = unit_or_up(sum[v]);
    }
    if (ctx.first_instance && renormalized > 0) {
      stats.normals_renormalized += renormalized;
      warnings.add(where + format(": %llu normals were not unit length; renormalized",
                                  static_cast<unsigned long long>(renormalized)));
    }
    if (ctx.first_instance && !broken.empty()) {
      stats.normals_repaired += broken.size();
      warnings.add(where + format(": %zu normals were zero or not finite; replaced by face normals", broken.size()));
    }
    if (!texcoords.empty()) {
      out->texcoords.resize(vertex_count);
      for (std::size_t i = 0; i < vertex_count; ++i) {
        out->texcoords[i] = ctx.uv_transform.apply({texcoords[2 * i], texcoords[2 * i + 1]});
      }
    }
    out->indices = std::move(indices);
  }
  budget.triangles_left -= out->indices.size() / 3;
  budget.vertices_left -= out->positions.size();
  return true;
}

}  // namespace dhr::scene_detail
