#include "frame/frame_coordinator.hpp"

#include <exception>
#include <stdexcept>

#include "render/client_scene.hpp"
#include "vk/check.hpp"
#include "vk/context.hpp"

namespace dhr::client {

namespace {

FrameStepOptions step_options(const CoordinatorOptions& options) {
  FrameStepOptions out;
  out.plan = options.plan;
  out.upload_keys = options.upload_keys;
  out.shadow_owner = options.shadow_owner;
  return out;
}

}  // namespace

FrameCoordinator::FrameCoordinator(const vk::Context& context, const render::ClientScene& scene, Extent eye_extent,
                                   VisibilitySource& visibility, const CoordinatorOptions& options)
    : context_(&context),
      visibility_(&visibility),
      options_(options),
      own_stereo_(std::make_unique<StereoPipeline>(context, scene, eye_extent, options.eye, options.shadow_maps)),
      stereo_(own_stereo_.get()),
      step_(*stereo_, visibility, step_options(options)) {
  create_slots(options.eye.frames_in_flight);
}

FrameCoordinator::FrameCoordinator(const vk::Context& context, StereoPipeline& stereo, VisibilitySource& visibility,
                                   const CoordinatorOptions& options)
    : context_(&context),
      visibility_(&visibility),
      options_(options),
      stereo_(&stereo),
      step_(stereo, visibility, step_options(options)) {
  create_slots(stereo.frames_in_flight());
}

void FrameCoordinator::create_slots(uint32_t count) {
  VkCommandPoolCreateInfo pool_info{};
  pool_info.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool_info.queueFamilyIndex = context_->queue_family();
  const VkDevice device = context_->device();
  VkCommandPool pool = VK_NULL_HANDLE;
  DHR_VK_CHECK(vkCreateCommandPool(device, &pool_info, nullptr, &pool));
  pool_ = vk::CommandPool(device, pool);
  slots_.resize(count);
  for (Slot& slot : slots_) {
    VkCommandBufferAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    alloc.commandPool = pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    DHR_VK_CHECK(vkAllocateCommandBuffers(device, &alloc, &slot.cmd));
    VkFenceCreateInfo fence_info{};
    fence_info.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
    fence_info.flags = VK_FENCE_CREATE_SIGNALED_BIT;
    VkFence fence = VK_NULL_HANDLE;
    DHR_VK_CHECK(vkCreateFence(device, &fence_info, nullptr, &fence));
    slot.fence = vk::Fence(device, fence);
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
  const std::array<render::EyeStats, 2> stats = stereo_->read_stats(slot_index);
  for (uint32_t e = 0; e < 2; ++e) slot.record.eyes[e].stats = stats[e];
  summary_.add(slot.record);
  if (on_frame_) on_frame_(slot.record);
  return true;
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

  VkCommandBuffer cmd = slot.cmd;
  DHR_VK_CHECK(vkResetCommandBuffer(cmd, 0));
  VkCommandBufferBeginInfo begin{};
  begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  DHR_VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
  FrameRecord record = step_.record(cmd, slot_index, input);
  const EyeImages images{&stereo_->eye(0).output(), &stereo_->eye(1).output()};
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
