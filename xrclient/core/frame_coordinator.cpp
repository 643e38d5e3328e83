#include "core/frame_coordinator.hpp"

#include <algorithm>
#include <exception>
#include <stdexcept>

#include "core/log.hpp"
#include "render/client_scene.hpp"
#include "vk/check.hpp"
#include "vk/context.hpp"

namespace dhr::client {

Camera traced_camera(const View& view, const VisibilityFormat& format) {
  const Extent displayed{format.buffer.width > format.guard.x ? format.buffer.width - format.guard.x : 0,
                         format.buffer.height > format.guard.y ? format.buffer.height - format.guard.y : 0};
  return Camera::with_guard_band(view, displayed, format.guard);
}

FrameCoordinator::FrameCoordinator(const vk::Context& context, const render::ClientScene& scene, Extent eye_extent,
                                   VisibilitySource& visibility, const CoordinatorOptions& options)
    : context_(&context),
      visibility_(&visibility),
      options_(options),
      extent_(eye_extent),
      history_(options.history_frames) {
  for (auto& eye : eyes_) eye = std::make_unique<render::EyePipeline>(context, scene, eye_extent, options.eye);
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

void FrameCoordinator::take_visibility(FrameRecord& record) {
  for (uint32_t e = 0; e < 2; ++e) {
    VisibilityFrame incoming;
    if (!visibility_->take_newest(e, incoming)) continue;
    // The newest wins; an older frame (reordering across reconnects) never replaces a newer one.
    if (held_[e] && held_[e]->frame_number > incoming.frame_number) continue;
    const uint64_t f = incoming.frame_number;
    held_[e] = std::move(incoming);
    // One response time per visibility frame: the first time it is used (both eyes complete).
    if (!record.response_ms && (!responded_frame_ || f > *responded_frame_)) {
      if (const auto ns = visibility_->response_ns(f)) {
        record.response_ms = static_cast<double>(*ns) * 1e-6;
        responded_frame_ = f;
      }
    }
  }
}

render::VisibilityInput FrameCoordinator::visibility_input(uint32_t eye) const {
  render::VisibilityInput input;
  const std::optional<VisibilityFormat> format = visibility_->format();
  if (!held_[eye] || !format) return input;
  const VisibilityFrame& v = *held_[eye];
  VisibilityFormat actual = *format;
  actual.buffer = Extent{v.buffer.width, v.buffer.height};
  input.buffer = &v.buffer;
  input.traced = traced_camera(v.view, actual);
  if (!v.complete) input.row_valid = v.row_valid;
  // Non-zero and unique per (frame, eye): an unchanged complete buffer is not uploaded again; a partial one
  // may still fill in, so it is always uploaded.
  input.key = v.complete ? v.frame_number * 2 + eye + 1 : 0;
  return input;
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
  visibility_->send_pose(input.frame, input.display_time_ns, input.views);
  history_.record(input.frame, input.display_time_ns, input.views);

  FrameRecord record;
  record.frame = input.frame;
  record.display_time_ns = input.display_time_ns;
  record.pose_reused = input.pose_reused;
  take_visibility(record);

  VkCommandBuffer cmd = slot.cmd;
  DHR_VK_CHECK(vkResetCommandBuffer(cmd, 0));
  VkCommandBufferBeginInfo begin{};
  begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  DHR_VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
  for (uint32_t e = 0; e < 2; ++e) {
    EyeFrameRecord& er = record.eyes[e];
    std::optional<uint64_t> vis_frame;
    if (held_[e]) vis_frame = held_[e]->frame_number;
    const ScheduleDecision d = decide_schedule(options_.schedule, options_.x_max, input.frame, vis_frame);
    er.has_visibility = vis_frame.has_value();
    er.visibility_frame = vis_frame.value_or(0);
    er.complete = held_[e] ? held_[e]->complete : true;
    er.age = d.age;
    er.display_frame = input.frame;
    View shown = input.views[e];
    if (d.display_frame != input.frame) {
      if (const auto views = history_.find(d.display_frame)) {
        shown = (*views)[e];
        er.display_frame = d.display_frame;
      }
    }
    er.predicted = er.has_visibility ? er.display_frame - std::min(er.display_frame, er.visibility_frame) : 0;
    eyes_[e]->record(cmd, slot_index, shown, visibility_input(e));
  }
  const EyeImages images{&eyes_[0]->output(), &eyes_[1]->output()};
  sink.record(cmd, input.frame, images);
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
  ++submitted_;
  sink.after_submit(input.frame, images);
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
