#include "metrics/visibility_synthetic.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace dhr {
namespace {

// splitmix64: tiny, well-mixed and identical everywhere.
class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(seed) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform(double lo, double hi) { return lo + (hi - lo) * static_cast<double>(next() >> 11) * 0x1.0p-53; }

 private:
  uint64_t state_;
};

}  // namespace

VisibilityBuffer make_uniform_visibility(uint32_t width, uint32_t height, uint32_t light_count, uint32_t mask) {
  VisibilityBuffer b = VisibilityBuffer::create(width, height, light_count);
  const uint32_t m = mask & b.light_bits();
  for (size_t i = 0; i < b.pixel_count(); ++i) b.set_mask_at(i, m);
  return b;
}

VisibilityBuffer make_random_visibility(uint32_t width, uint32_t height, uint32_t light_count, uint64_t seed) {
  VisibilityBuffer b = VisibilityBuffer::create(width, height, light_count);
  Rng rng(seed);
  for (size_t i = 0; i < b.pixel_count(); ++i) b.set_mask_at(i, static_cast<uint32_t>(rng.next()) & b.light_bits());
  return b;
}

VisibilityBuffer make_stripe_visibility(uint32_t width, uint32_t height, uint32_t light_count, uint32_t period) {
  VisibilityBuffer b = VisibilityBuffer::create(width, height, light_count);
  const uint32_t p = std::max<uint32_t>(2, period);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      uint32_t mask = 0;
      for (uint32_t l = 0; l < light_count; ++l) {
        const uint32_t pl = p + l;
        if ((x + y + l * 3) % pl < pl / 2) mask |= 1u << l;
      }
      b.set(x, y, mask);
    }
  return b;
}

VisibilityBuffer make_blob_visibility(uint32_t width, uint32_t height, uint32_t light_count, uint64_t seed) {
  VisibilityBuffer b = VisibilityBuffer::create(width, height, light_count);
  struct Blob {
    double cx, cy, rx, ry, angle, wobble_amp, wobble_freq, phase;
  };
  Rng rng(seed);
  std::vector<std::vector<Blob>> blobs(light_count);
  const double w = width, h = height, size = std::min(w, h);
  for (auto& list : blobs) {
    const int count = 2 + static_cast<int>(rng.next() % 4);
    for (int i = 0; i < count; ++i)
      list.push_back(Blob{rng.uniform(0.0, w), rng.uniform(0.3 * h, h), rng.uniform(0.05, 0.3) * size,
                          rng.uniform(0.03, 0.15) * size, rng.uniform(0.0, 3.14159), rng.uniform(0.0, 0.15),
                          static_cast<double>(3 + rng.next() % 6), rng.uniform(0.0, 6.28318)});
  }
  const double horizon = 0.25 * h;  // above it: "sky", no geometry, no light reaches the camera's surface
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      uint32_t mask = 0;
      if (y >= horizon) {
        for (uint32_t l = 0; l < light_count; ++l) {
          bool shadowed = false;
          for (const Blob& bl : blobs[l]) {
            const double dx = x - bl.cx, dy = y - bl.cy;
            const double reach = std::max(bl.rx, bl.ry) * (1.0 + bl.wobble_amp);
            if (std::fabs(dx) > reach || std::fabs(dy) > reach) continue;
            const double c = std::cos(bl.angle), s = std::sin(bl.angle);
            const double u = (c * dx + s * dy) / bl.rx, v = (-s * dx + c * dy) / bl.ry;
            const double r = 1.0 + bl.wobble_amp * std::sin(bl.wobble_freq * std::atan2(v, u) + bl.phase);
            if (u * u + v * v < r * r) {
              shadowed = true;
              break;
            }
          }
          if (!shadowed) mask |= 1u << l;
        }
      }
      b.set(x, y, mask);
    }
  return b;
}

namespace {

struct Hit {
  double t = 1e30;
  glm::dvec3 normal{0.0};
};

struct Sphere {
  glm::dvec3 c;
  double r;
};
struct Box {
  glm::dvec3 lo, hi;
};

bool hit_sphere(const Sphere& s, const glm::dvec3& o, const glm::dvec3& d, double t_max, Hit* hit) {
  const glm::dvec3 oc = o - s.c;
  const double b = glm::dot(oc, d), c = glm::dot(oc, oc) - s.r * s.r;
  const double disc = b * b - c;
  if (disc < 0.0) return false;
  const double t = -b - std::sqrt(disc);
  if (t <= 1e-9 || t >= t_max) return false;
  if (hit) {
    hit->t = t;
    hit->normal = (o + t * d - s.c) / s.r;
  }
  return true;
}

bool hit_box(const Box& bx, const glm::dvec3& o, const glm::dvec3& d, double t_max, Hit* hit) {
  double t0 = 1e-9, t1 = t_max;
  int axis = -1;
  double sign = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double inv = 1.0 / d[a];
    double tn = (bx.lo[a] - o[a]) * inv, tf = (bx.hi[a] - o[a]) * inv;
    double sn = -1.0;
    if (tn > tf) {
      std::swap(tn, tf);
      sn = 1.0;
    }
    if (tn > t0) {
      t0 = tn;
      axis = a;
      sign = sn;
    }
    t1 = std::min(t1, tf);
    if (t0 > t1) return false;
  }
  if (axis < 0) return false;  // origin inside the box
  if (hit) {
    hit->t = t0;
    hit->normal = glm::dvec3(0.0);
    hit->normal[axis] = sign;
  }
  return true;
}

}  // namespace

VisibilityBuffer make_room_visibility(uint32_t width, uint32_t height, uint32_t light_count, uint64_t seed) {
  VisibilityBuffer b = VisibilityBuffer::create(width, height, light_count);
  Rng rng(seed);
  const glm::dvec3 room_lo(-3.0, 0.0, -4.0), room_hi(3.0, 2.8, 4.0);
  std::vector<Sphere> spheres;
  std::vector<Box> boxes;
  for (int i = 0; i < 4; ++i) {
    const double r = rng.uniform(0.15, 0.45);
    spheres.push_back(Sphere{{rng.uniform(-2.4, 2.4), r + rng.uniform(0.0, 0.6), rng.uniform(-3.5, 0.5)}, r});
  }
  // One draw per statement: the order in which a call's arguments are evaluated is unspecified (GCC takes them
  // right to left on x86-64, left to right on aarch64), so draws inside one call gave each CPU another room.
  // The draws below keep the order x86-64 used, so every buffer measured there stays the same.
  for (int i = 0; i < 5; ++i) {
    const double cz = rng.uniform(-3.5, 0.5);
    const double cx = rng.uniform(-2.4, 2.4);
    const double hz = rng.uniform(0.15, 0.6);
    const double hy = rng.uniform(0.2, 1.0);
    const double hx = rng.uniform(0.15, 0.6);
    boxes.push_back(Box{{cx - hx, 0.0, cz - hz}, {cx + hx, 2.0 * hy, cz + hz}});
  }
  std::vector<glm::dvec3> lights;
  for (uint32_t l = 0; l < light_count; ++l) {
    const double z = rng.uniform(-3.5, 2.0);
    const double y = rng.uniform(1.6, 2.6);
    const double x = rng.uniform(-2.5, 2.5);
    lights.emplace_back(x, y, z);
  }
  const double light_range = 7.0;

  // Camera at eye height near the front wall, looking down the room and slightly down; 90 deg horizontal FOV.
  const glm::dvec3 eye(0.3, 1.6, 3.2);
  const glm::dvec3 forward = glm::normalize(glm::dvec3(-0.1, -0.3, -1.0));
  const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0.0, 1.0, 0.0)));
  const glm::dvec3 up = glm::cross(right, forward);
  const double tan_x = 1.0, tan_y = tan_x * height / width;

  auto occluded = [&](const glm::dvec3& o, const glm::dvec3& d, double t_max) {
    for (const Sphere& s : spheres)
      if (hit_sphere(s, o, d, t_max, nullptr)) return true;
    for (const Box& bx : boxes)
      if (hit_box(bx, o, d, t_max, nullptr)) return true;
    return false;
  };

  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const double u = (2.0 * (x + 0.5) / width - 1.0) * tan_x;
      const double v = (1.0 - 2.0 * (y + 0.5) / height) * tan_y;
      const glm::dvec3 d = glm::normalize(forward + u * right + v * up);
      Hit best;
      // Room interior: the far side of the axis-aligned room box.
      for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0) continue;
        const double plane = d[a] > 0.0 ? room_hi[a] : room_lo[a];
        const double t = (plane - eye[a]) / d[a];
        if (t > 0.0 && t < best.t) {
          best.t = t;
          best.normal = glm::dvec3(0.0);
          best.normal[a] = d[a] > 0.0 ? -1.0 : 1.0;
        }
      }
      Hit h;
      for (const Sphere& s : spheres)
        if (hit_sphere(s, eye, d, best.t, &h)) best = h;
      for (const Box& bx : boxes)
        if (hit_box(bx, eye, d, best.t, &h)) best = h;
      const glm::dvec3 p = eye + best.t * d;
      const glm::dvec3 origin = p + best.normal * 1e-6 * std::max(1.0, glm::length(p));
      uint32_t mask = 0;
      for (uint32_t l = 0; l < light_count; ++l) {
        const glm::dvec3 to_light = lights[l] - origin;
        const double dist = glm::length(to_light);
        const glm::dvec3 dir = to_light / dist;
        if (dist > light_range || glm::dot(best.normal, dir) <= 0.0) continue;
        if (!occluded(origin, dir, dist)) mask |= 1u << l;
      }
      b.set(x, y, mask);
    }
  return b;
}

}  // namespace dhr
