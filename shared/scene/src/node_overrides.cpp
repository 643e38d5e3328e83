// The rule of scene/node_overrides.hpp: hold from each stamp, extrapolate beyond the newest for a bounded horizon.
#include "scene/node_overrides.hpp"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

namespace dhr {
namespace {

constexpr double kRotationNormTolerance = 1e-3;  // as the protocol's decoder (kQuaternionNormTolerance)
// An extrapolated scale never shrinks below this share of the newest one (stays > 0: no mirrored geometry).
constexpr double kMinExtrapolatedScale = 1e-3;

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// The newest two transforms continued to `t` (seconds, past b's stamp), within the horizon.
Trs extrapolated(const NodeTransformSample& a, const NodeTransformSample& b, double t) {
  const double t0 = node_stamp_seconds(a.scene_time_ns);
  const double t1 = node_stamp_seconds(b.scene_time_ns);
  const double ahead = std::min(t - t1, node_stamp_seconds(kNodeExtrapolationHorizonNs));
  const double u = ahead / (t1 - t0);  // stamps strictly increase: t1 > t0
  Trs out;
  out.translation = b.trs.translation + (b.trs.translation - a.trs.translation) * u;
  out.scale = glm::max(b.trs.scale + (b.trs.scale - a.trs.scale) * u, b.trs.scale * kMinExtrapolatedScale);
  out.rotation = slerp_shortest(a.trs.rotation, b.trs.rotation, 1.0 + u);
  return out;
}

}  // namespace

const char* to_string(NodeTransformVerdict verdict) {
  switch (verdict) {
    case NodeTransformVerdict::kAccepted: return "accepted";
    case NodeTransformVerdict::kUnknownNode: return "unknown node";
    case NodeTransformVerdict::kOutOfOrder: return "out of order";
    case NodeTransformVerdict::kLate: return "late";
    case NodeTransformVerdict::kInvalid: return "invalid";
  }
  return "unknown";
}

bool valid_trs(const Trs& trs) {
  const glm::dquat& q = trs.rotation;
  if (!finite(trs.translation) || !finite(trs.scale)) return false;
  if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z) || !std::isfinite(q.w)) return false;
  if (std::fabs(glm::dot(q, q) - 1.0) > kRotationNormTolerance) return false;
  return trs.scale.x > 0.0 && trs.scale.y > 0.0 && trs.scale.z > 0.0;
}

glm::dmat4 trs_matrix(const Trs& trs) {
  glm::dmat4 m = glm::translate(glm::dmat4(1.0), trs.translation);
  m = m * glm::mat4_cast(trs.rotation);
  return glm::scale(m, trs.scale);
}

NodeTransformVerdict NodeOverrides::add(const SceneAnimation& animation, std::uint32_t node,
                                        std::int64_t scene_time_ns, const Trs& trs, std::int64_t not_before_ns) {
  if (!animation.find(node)) return NodeTransformVerdict::kUnknownNode;
  auto it = std::lower_bound(nodes_.begin(), nodes_.end(), node,
                             [](const Node& n, std::uint32_t index) { return n.node < index; });
  const bool known = it != nodes_.end() && it->node == node;
  if (known && scene_time_ns <= it->samples.back().scene_time_ns) return NodeTransformVerdict::kOutOfOrder;
  if (scene_time_ns < not_before_ns) return NodeTransformVerdict::kLate;
  if (scene_time_ns < 0 || !valid_trs(trs)) return NodeTransformVerdict::kInvalid;
  if (!known) it = nodes_.insert(it, Node{node, {}});
  std::vector<NodeTransformSample>& samples = it->samples;
  if (samples.size() == kNodeOverrideHistory) samples.erase(samples.begin());
  samples.push_back(NodeTransformSample{scene_time_ns, Trs{trs.translation, glm::normalize(trs.rotation), trs.scale}});
  ++revision_;
  return NodeTransformVerdict::kAccepted;
}

const NodeOverrides::Node* NodeOverrides::find(std::uint32_t node) const {
  const auto it = std::lower_bound(nodes_.begin(), nodes_.end(), node,
                                   [](const Node& n, std::uint32_t index) { return n.node < index; });
  return it != nodes_.end() && it->node == node ? &*it : nullptr;
}

const NodeTransformSample* NodeOverrides::newest(std::uint32_t node) const {
  const Node* n = find(node);
  return n ? &n->samples.back() : nullptr;
}

std::optional<Trs> NodeOverrides::trs_at(std::uint32_t node, double t) const {
  const Node* n = find(node);
  if (!n || !std::isfinite(t)) return std::nullopt;
  const std::vector<NodeTransformSample>& s = n->samples;
  // The newest transform stamped at or before t.
  const auto after = std::upper_bound(s.begin(), s.end(), t, [](double x, const NodeTransformSample& sample) {
    return x < node_stamp_seconds(sample.scene_time_ns);
  });
  if (after == s.begin()) return std::nullopt;  // before the first: the animation or rest
  const auto at = after - 1;
  if (after != s.end() || s.size() < 2 || t == node_stamp_seconds(at->scene_time_ns)) return at->trs;
  return extrapolated(*(at - 1), *at, t);
}

std::optional<glm::dmat4> NodeOverrides::local_at(std::uint32_t node, double t) const {
  const std::optional<Trs> trs = trs_at(node, t);
  if (!trs) return std::nullopt;
  return trs_matrix(*trs);
}

}  // namespace dhr
