// How the Embree backend hands occlusion rays to Embree: a knob of the tracer (EmbreeTracerConfig) that the
// tile kernel (embree_trace_tile.hpp) reads, so it sits below both.
#pragma once

namespace dhr::server {

enum class ShadowQuery {
  kSingle,   // rtcOccluded1 per ray, incoherent
  kStream,   // rtcOccluded1M over a tile's rays, ordered light-major and block by block, coherent
  kPackets,  // rtcOccluded16 per run of up to 16 rays of one 4x4 block toward one light
};

}  // namespace dhr::server
