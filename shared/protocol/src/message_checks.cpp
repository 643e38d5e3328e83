// What a decoded message must satisfy beyond its layout: ranges and rules across fields. Run after the
// field-wise read (wire_codec.hpp's read_body); the first failing check names the DecodeError, so the
// order of the checks below is part of the protocol's behaviour (tests/unit/protocol_robustness_test.cpp).
#include "wire_codec.hpp"

#include <cmath>

namespace dhr::wire {
namespace {

bool valid_traced_size(uint32_t eye, uint32_t guard) { return eye >= 1 && eye + 2u * guard <= kMaxBufferDimension; }

bool valid_buffer_size(uint32_t width, uint32_t height) {
  return width >= 1 && width <= kMaxBufferDimension && height >= 1 && height <= kMaxBufferDimension;
}

uint8_t raw(auto value) { return static_cast<uint8_t>(value); }  // an enum field as it arrived

}  // namespace

DecodeError check_nested(View& view) {
  const glm::dvec3& p = view.pose.position;
  const glm::dquat& q = view.pose.orientation;
  const Fov& fov = view.fov;
  // The values came from f64 and f32 fields: widening keeps non-finite values non-finite.
  for (double x : {p.x, p.y, p.z, q.x, q.y, q.z, q.w})
    if (!std::isfinite(x)) return DecodeError::kNonFinite;
  for (float x : {fov.angle_left, fov.angle_right, fov.angle_up, fov.angle_down})
    if (!std::isfinite(x)) return DecodeError::kNonFinite;
  if (validate_pose(view.pose)) return DecodeError::kBadPose;
  const double norm2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
  if (std::fabs(norm2 - 1.0) > kQuaternionNormTolerance) return DecodeError::kBadPose;
  if (validate_fov(fov)) return DecodeError::kBadFov;
  view.pose = normalized(view.pose);
  return DecodeError::kNone;
}

DecodeError validate(const Hello& m) {
  if (!valid_traced_size(m.eye_width, m.guard_x) || !valid_traced_size(m.eye_height, m.guard_y))
    return DecodeError::kBadValue;
  if (m.light_count_wanted > kMaxLights) return DecodeError::kBadValue;
  return DecodeError::kNone;
}

DecodeError validate(const Welcome& m) {
  if (m.light_count > kMaxLights) return DecodeError::kBadValue;
  // Soft levels: granted exactly when some light has a level field, and every field fits 32 bits.
  const bool soft = (m.capabilities & kCapabilitySoftLevels) != 0;
  if (m.soft_light_count > m.light_count || soft != (m.soft_light_count > 0) || m.used_mask_bits() > kMaxLights)
    return DecodeError::kBadValue;
  const auto width = mask_width_from_bits(raw(m.mask_bits));
  if (!width || *width != mask_width_for_light_count(m.used_mask_bits())) return DecodeError::kBadValue;
  if (!valid_buffer_size(m.buffer_width, m.buffer_height)) return DecodeError::kBadValue;
  if (2u * m.guard_x >= m.buffer_width || 2u * m.guard_y >= m.buffer_height) return DecodeError::kBadValue;
  if (m.heartbeat_interval_ms == 0 || m.session_timeout_ms == 0) return DecodeError::kBadValue;
  return DecodeError::kNone;
}

DecodeError validate(const PoseUpdate& m) {
  if (m.display_time_ns < 0 || m.scene_time_ns < 0) return DecodeError::kBadValue;
  return DecodeError::kNone;
}

DecodeError validate(const VisibilityShard& m) {
  if (raw(m.eye) > 1) return DecodeError::kBadValue;
  if (!mask_width_from_bits(raw(m.mask_bits))) return DecodeError::kBadValue;
  if (m.shard_count < 1 || m.shard_index >= m.shard_count) return DecodeError::kBadValue;
  if (!valid_buffer_size(m.buffer_width, m.buffer_height)) return DecodeError::kBadValue;
  const uint64_t pixels = uint64_t{m.buffer_width} * m.buffer_height;
  if (m.pixel_count < 1 || uint64_t{m.first_pixel} + m.pixel_count > pixels) return DecodeError::kBadValue;
  if (m.scene_time_ns < 0) return DecodeError::kBadValue;
  return DecodeError::kNone;
}

DecodeError validate(const Heartbeat& m) {
  if (m.send_time_ns < 0 || m.echo_time_ns < 0 || m.echo_delay_ns < 0) return DecodeError::kBadValue;
  return DecodeError::kNone;
}

DecodeError validate(const Bye& m) {
  if (raw(m.reason) > kMaxByeReason) return DecodeError::kBadValue;
  return DecodeError::kNone;
}

DecodeError validate(NodeTransform& m) {
  const Trs& trs = m.trs;
  const glm::dquat& q = trs.rotation;
  for (double x : {trs.translation.x, trs.translation.y, trs.translation.z, q.x, q.y, q.z, q.w, trs.scale.x,
                   trs.scale.y, trs.scale.z})
    if (!std::isfinite(x)) return DecodeError::kNonFinite;
  if (m.scene_time_ns < 0) return DecodeError::kBadValue;
  const double norm2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
  if (std::fabs(norm2 - 1.0) > kQuaternionNormTolerance) return DecodeError::kBadPose;
  if (!(trs.scale.x > 0.0 && trs.scale.y > 0.0 && trs.scale.z > 0.0)) return DecodeError::kBadValue;
  if (glm::length(trs.translation) > kMaxPositionMetres) return DecodeError::kBadPose;
  m.trs.rotation = glm::normalize(q);
  return DecodeError::kNone;
}

}  // namespace dhr::wire
