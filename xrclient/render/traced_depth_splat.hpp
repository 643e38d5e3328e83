// The warp's traced depth without a raster pass (WarpSettings::depth_splat): the depth of the camera a visibility
// buffer was traced for, made from a display frame's depth instead of rendering the scene again.
//
// The depth test (WarpSettings::depth_test) asks, per 2x2 sample, which surface the traced camera saw there. A
// raster pass of the traced camera answers it exactly, at the cost of drawing the scene once more per traced
// camera. The traced camera is a pose the client displayed a moment ago or will display (the server traces the
// predicted pose), so the eye's previous display frame saw nearly the same surfaces: each of its surface pixels is
// moved into the traced depth camera and written to the texel that contains its projection, the nearest surface
// kept per texel (a z-buffer of points). Texels no pixel reaches hold no surface, and the warp's test does not use
// their samples: such holes open where the traced camera sees more of a surface than the display frame did (at
// silhouettes, at grazing angles, and between the points of a surface the traced camera magnifies), and pixels
// whose samples all fall in them take the shadow maps. What the splat cannot know: surfaces the display frame did
// not see (outside its view or hidden from it) that the traced camera did. Measured against the raster pass in
// docs/evaluation.md ("Disocclusion without a second raster pass"); writing each point to the 2x2 texels nearest
// it (no holes inside a surface, but every silhouette one texel wider), filling holes from their farthest neighbour,
// and four sub-points per pixel were each measured there and were less accurate; writing each pixel's square (its
// corners on its surface's plane) to the texels it covers was as accurate, at twice the time, and adding the other
// eye's previous frame (which sees around an occluder's other side) as accurate too.
//
// GPU: one compute pass into a buffer (atomicMax on the depth's bits), then a copy into the traced depth image. The
// CPU reference (splat_traced_depth_reference) is the same definition in double.
#pragma once
#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>
#include <vector>

#include "math/projection.hpp"
#include "render/pass_util.hpp"
#include "vk/buffer.hpp"
#include "vk/image.hpp"

namespace dhr::vk {
class Context;
}

namespace dhr::render {

class TracedDepthSplat {
 public:
  // Up to `per_slot` splats per frame slot (the frames in flight times this many descriptor sets and buffers).
  TracedDepthSplat(const vk::Context& context, uint32_t slots, uint32_t per_slot);

  // Records the splat of `source_depth` (a display frame's depth, D32 reversed-Z, SHADER_READ_ONLY_OPTIMAL, written
  // with `source` at `near_plane`) into `target` (D32 with TRANSFER_DST usage, `target_camera`'s extent), use
  // `index` (< per_slot) of `slot`. Leaves `target` in SHADER_READ_ONLY_OPTIMAL, its writes visible to later shader
  // reads. Throws std::invalid_argument for a slot or index out of range or sizes that differ from the cameras'.
  void record(VkCommandBuffer cmd, uint32_t slot, uint32_t index, const vk::Image& source_depth, const Camera& source,
              vk::Image& target, const Camera& target_camera, double near_plane);

 private:
  struct Use {
    VkDescriptorSet set = VK_NULL_HANDLE;
    vk::Buffer texels;
  };
  const vk::Context* context_;
  ComputePassCore core_;
  uint32_t per_slot_;
  std::vector<Use> uses_;
};

// The CPU reference: the same splat in double. `source_depth`: source.extent's depth values, row-major.
std::vector<float> splat_traced_depth_reference(std::span<const float> source_depth, const Camera& source,
                                                const Camera& target, double near_plane);

}  // namespace dhr::render
