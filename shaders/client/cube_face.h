// Cube shadow-map faces (GLSL; the C++ twin is render/shadow_maps.cpp's cube_lookup). A light's six faces are
// 90-degree cameras at the light looking along +X, -X, +Y, -Y, +Z, -Z (faces 0-5) with (right, up):
//   +X (0,0,1),(0,1,0)   -X (0,0,-1),(0,1,0)   +Y (1,0,0),(0,0,1)   -Y (1,0,0),(0,0,-1)
//   +Z (-1,0,0),(0,1,0)  -Z (1,0,0),(0,1,0)
// A direction v from the light falls on the face of its largest |component| (ties: x before y before z,
// + before -); on that face its tangents are (v.R, v.U) / |v.F| and its texel ((tx + 1) / 2, (1 - ty) / 2)
// times the face size, clamped to the face. The depth stored there is near / (distance along F).
#ifndef DHR_CUBE_FACE_H
#define DHR_CUBE_FACE_H

struct CubeLookup {
  uint face;
  ivec2 texel;     // within the face
  vec2 position;   // continuous texel coordinate before clamping
  float distance;  // along the face's axis
};

float cube_face_distance(vec3 v) { return max(abs(v.x), max(abs(v.y), abs(v.z))); }

CubeLookup cube_lookup(vec3 v, uint size) {
  const vec3 a = abs(v);
  CubeLookup c;
  float x, y;
  if (a.x >= a.y && a.x >= a.z) {
    c.distance = a.x;
    c.face = v.x >= 0.0 ? 0u : 1u;
    x = v.x >= 0.0 ? v.z : -v.z;
    y = v.y;
  } else if (a.y >= a.z) {
    c.distance = a.y;
    c.face = v.y >= 0.0 ? 2u : 3u;
    x = v.x;
    y = v.y >= 0.0 ? v.z : -v.z;
  } else {
    c.distance = a.z;
    c.face = v.z >= 0.0 ? 4u : 5u;
    x = v.z >= 0.0 ? -v.x : v.x;
    y = v.y;
  }
  const float s = float(size);
  const vec2 t = vec2(x, y) / c.distance;
  c.position = vec2((t.x + 1.0) * 0.5 * s, (1.0 - t.y) * 0.5 * s);
  c.texel = clamp(ivec2(floor(c.position)), ivec2(0), ivec2(int(size) - 1));
  return c;
}

#endif  // DHR_CUBE_FACE_H
