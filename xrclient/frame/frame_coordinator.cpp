#include "frame/frame_coordinator.hpp"

#include <algorithm>
#include <exception>
#include <stdexcept>

#include "log/log.hpp"
#include "render/client_scene.hpp"
#include "vk/check.hpp"
#include "vk/context.hpp"

namespace dhr::client {

FrameCoordinator::FrameCoordinator(const vk::Context& context, const render::ClientScene& scene, Extent eye_extent,
                                   VisibilitySource& visibility, const CoordinatorOptions& options)
    : context_(&context),
      visibility_(&visibility),
      options_(options),
      extent_(eye_extent),
      planner_(options.plan) {
  for (auto& eye : eyes_) eye = std::make_unique<render::EyePipeline>(context, scene, eye_extent, options.eye);
  if (options.eye.warp.uses_shadow_maps()) {
    shadow_maps_ = std::make_unique<render::ShadowMaps>(context, scene, options.shadow_maps);
    log::info("shadow maps: %zu lights, %u texels per face, rendered in %.1f ms", shadow_maps_->tiles().size(),
              shadow_maps_->face_size(), shadow_maps_->render_ms());
  }
  VkCommandPoolCreateInfo pool_info{};
  pool_info.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool_info.queueFamilyIndex = context.queue_family();
  VkCommandPool pool = VK_NULL_HANDLE;
  DHR_VK_CHECK(vkCreateCommandPool(context.device(), &pool_info, nullptr, &pool));
  pool_ = vk::CommandPool(context.device(), pool);
  slots_.resize(options.eye.frames_in_flight);
  for (Slot& slot : slots_) {
    VkCommandBufferAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    alloc.commandPool = pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    DHR_VK_CHECK(vkAllocateCommandBuffers(context.device(), &alloc, &slot.cmd));
    VkFenceCreateInfo fence_info{};
    fence_info.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
    fence_info.flags = VK_FENCE_CREATE_SIGNALED_BIT;
    VkFence fence = VK_NULL_HANDLE;
    DHR_VK_CHECK(vkCreateFence(context.device(), &fence_info, nullptr, &fence));
    slot.fence = vk::Fence(context.device(), fence);
  }
}

FrameCoordinator::~FrameCoordinator() {
  // Command buffers and images must not be in use when they are destroyed.
  if (context_ != nullptr) vkDeviceWaitIdle(context_->device());
}

bool FrameCoordinator::complete_slot(uint32_t slot_index) {
  Slot& slot = slots_[slot_index];
  if (!slot.pending) return true;
  VkFence fence = slot.fence.get();
  const VkResult r = vkWaitForFences(context_->device(), 1, &fence, VK_TRUE, options_.gpu_wait_timeout_ns);
  if (r != VK_SUCCESS) {
    error_ = r == VK_TIMEOUT ? "the GPU did not finish a frame in time" : "waiting for a frame failed";
    return false;
  }
  slot.pending = false;
  for (uint32_t e = 0; e < 2; ++e) slot.record.eyes[e].stats = eyes_[e]->read_stats(slot_index);
  summary_.add(slot.record);
  if (on_frame_) on_frame_(slot.record);
  return true;
}

void FrameCoordinator::take_visibility() {
  for (uint32_t e = 0; e < 2; ++e) {
    VisibilityFrame incoming;
    if (visibility_->take_newest(e, incoming)) planner_.offer(e, std::move(incoming));
  }
}

bool FrameCoordinator::run_frame(const FrameInput& input, FrameSink& sink) {
  if (!error_.empty()) return false;
  // Vulkan and sink failures throw from deep inside the passes; per frame they become a status.
  try {
    return record_and_submit(input, sink);
  } catch (const std::exception& e) {
    error_ = e.what();
    return false;
  }
}

bool FrameCoordinator::record_and_submit(const FrameInput& input, FrameSink& sink) {
  const uint32_t slot_index = static_cast<uint32_t>(submitted_ % slots_.size());
  if (!complete_slot(slot_index)) return false;
  Slot& slot = slots_[slot_index];

  visibility_->tick();
  const FramePose& pose = input.pose;
  visibility_->send_pose(pose);
  take_visibility();
  const std::optional<VisibilityFormat> format = visibility_->format();
  const FramePlan plan = planner_.plan(pose, format ? std::optional<TracedFormat>(format->traced) : std::nullopt,
                                       [this](uint64_t f) { return visibility_->response_ns(f); });

  FrameRecord record;
  record.frame = pose.frame;
  record.display_time_ns = pose.display_time_ns;
  record.pose_reused = input.pose_reused;
  record.response_ms = plan.response_ms;

  VkCommandBuffer cmd = slot.cmd;
  DHR_VK_CHECK(vkResetCommandBuffer(cmd, 0));
  VkCommandBufferBeginInfo begin{};
  begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  DHR_VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
  std::array<VisibilityInput, 2> inputs;
  std::array<VisibilityInput, 2> older;
  for (uint32_t e = 0; e < 2; ++e) {
    const EyePlan& p = plan.eyes[e];
    inputs[e] = p.visibility;
    // Non-zero and unique per (frame, eye): an unchanged complete buffer is not uploaded again; a partial one
    // may still fill in, so it is always uploaded.
    inputs[e].key = p.has_visibility && p.complete ? p.visibility_frame * 2 + e + 1 : 0;
    older[e] = p.older;
    older[e].key = p.older.buffer != nullptr && p.older_complete ? p.older_frame * 2 + e + 1 : 0;
    eyes_[e]->prepare(cmd, slot_index, inputs[e], &older[e]);
  }
  for (uint32_t e = 0; e < 2; ++e) {
    const EyePlan& p = plan.eyes[e];
    EyeFrameRecord& er = record.eyes[e];
    er.has_visibility = p.has_visibility;
    er.visibility_frame = p.visibility_frame;
    er.complete = p.complete;
    er.age = p.age;
    er.display_frame = p.display_frame;
    er.predicted = p.predicted;
    const VisibilityInput& other = inputs[1 - e];
    render::WarpSourceInput other_source;
    other_source.visibility = &other;
    if (other.buffer != nullptr) other_source.traced_depth = eyes_[1 - e]->traced_depth(other.traced);
    eyes_[e]->record(cmd, slot_index, p.view, inputs[e], other_source, shadow_maps_.get(), &older[e]);
    rendered_views_[e] = p.view;
  }
  const EyeImages images{&eyes_[0]->output(), &eyes_[1]->output()};
  sink.record(cmd, pose.frame, images);
  DHR_VK_CHECK(vkEndCommandBuffer(cmd));

  VkFence fence = slot.fence.get();
  DHR_VK_CHECK(vkResetFences(context_->device(), 1, &fence));
  VkCommandBufferSubmitInfo cmd_info{};
  cmd_info.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO;
  cmd_info.commandBuffer = cmd;
  VkSubmitInfo2 submit{};
  submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO_2;
  submit.commandBufferInfoCount = 1;
  submit.pCommandBufferInfos = &cmd_info;
  const VkResult r = context_->submit(submit, fence);
  if (r != VK_SUCCESS) {
    error_ = "submitting a frame failed (VkResult " + std::to_string(static_cast<int>(r)) + ")";
    return false;
  }
  slot.pending = true;
  slot.record = std::move(record);
  last_slot_ = slot_index;
  ++submitted_;
  sink.after_submit(pose.frame, images);
  return true;
}

bool FrameCoordinator::finish() {
  try {
    // Oldest first, so on_frame sees frames in order.
    const size_t n = slots_.size();
    for (size_t i = 0; i < n; ++i) {
      const uint32_t slot_index = static_cast<uint32_t>((submitted_ + i) % n);
      if (!complete_slot(slot_index)) return false;
    }
    return true;
  } catch (const std::exception& e) {
    error_ = e.what();
    return false;
  }
}

}  // namespace dhr::client
