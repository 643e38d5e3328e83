// Ray payloads of the server's visibility tracer (GLSL only; C++ never sees them).
#ifndef DHR_VISIBILITY_PAYLOAD_GLSL
#define DHR_VISIBILITY_PAYLOAD_GLSL

const uint kVisNoHit = 0xFFFFFFFFu;

// Primary ray: what the closest front face (or double-sided face) was.
struct VisPrimaryPayload {
  uint mesh;       // gl_InstanceCustomIndexEXT (= Scene::meshes index), kVisNoHit on a miss
  uint primitive;  // gl_PrimitiveID within the BLAS (spatially sorted order)
  float u;         // barycentrics: p = (1-u-v) v0 + u v1 + v v2
  float v;
};

#endif  // DHR_VISIBILITY_PAYLOAD_GLSL
