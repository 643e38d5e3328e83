// client_bench's frame-loop configurations: the client's own FrameCoordinator over a CodedVisibilitySource (a new
// Embree-traced, codec-v2 coded visibility frame per eye every frame) with a moving head, and the host-side costs
// around it (decode, upload, the frame step). `dhr_ms` runs it with the shipped options, `dhr_full_ms` and
// `dhr_edges_ms` with other warps (bench/client_bench.cpp's file comment says what each key measures).
#pragma once
#include "coded_visibility_source.hpp"
#include "frame/frame_coordinator.hpp"
#include "math/pose.hpp"
#include "math/projection.hpp"
#include "render/client_scene.hpp"
#include "trace/visibility_tracer.hpp"
#include "vk/buffer.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace dhr::bench {

// Display and scene time of frame i (90 Hz from 0): a moving scene advances with the frames.
inline int64_t frame_time_ns(uint32_t i) { return static_cast<int64_t>(i) * 11'111'111; }

// Frame i of `total`: the head turns at 60 degrees/s about the vertical (centred on the bookmark's view over the
// run) and drifts 0.5 mm per frame sideways, so no view (and no traced camera) repeats.
FramePose moving_pose(const Pose& head, const Fov& fov, uint32_t i, uint32_t total);

// dhr-xrclient's coordinator options when no option is given (xrclient/plan/include/plan/shipped_defaults.hpp) on
// a device (`discrete_gpu`: its render path), except for one GPU slot: every frame is waited for, as the other
// configurations'.
// `soft_scene`: Scene::has_soft_lights (--warp auto's rule).
client::CoordinatorOptions shipped_options(bool discrete_gpu, bool soft_scene);

// A client frame loop as dhr-xrclient runs it, with its host-side costs; its JSON keys start with `name`.
class ClientLoop {
 public:
  ClientLoop(std::string name, const vk::Context& context, const render::ClientScene& scene, Extent size,
             server::VisibilityTracer& tracer, const TracedFormat& format, const client::CoordinatorOptions& options,
             const Pose& head, const Fov& fov, uint32_t total, int64_t scene_lead_ns = 0);

  const std::string& name() const { return name_; }
  // Frame i: returns each eye's GPU ms; keeps the host times of frames from `first_kept` on. Throws when the frame
  // fails.
  std::vector<double> run(uint32_t i, uint32_t first_kept);
  void report(nlohmann::ordered_json& out) const;

 private:
  // The warp pass writes each source it reads (this eye's newest; with the warp's ingredients, the other eye's
  // newest and this eye's previous) into a host-visible buffer: the same byte copies, timed on their own.
  void measure_upload(uint32_t e);

  std::string name_;
  const vk::Context& context_;
  render::WarpSettings warp_;
  CodedVisibilitySource source_;
  client::FrameCoordinator coordinator_;
  client::FrameSink sink_;  // nothing: the images stay in the eye pipelines
  client::FrameRecord last_;
  Pose head_;
  Fov fov_;
  uint32_t total_;
  std::array<vk::Buffer, 3> upload_;
  std::vector<double> traced_depth_ms_, decode_ms_, payload_bytes_, upload_ms_, known_frac_, shadow_frac_;
  std::vector<double> edge_marks_ms_;  // the edge band's marks of the uploaded buffers (host, per eye)
  uint32_t hard_bits_ = 0;             // the bits the marks cover (hard fields); 0: the warp makes none
  bool marks_due() const { return warp_.bilinear && warp_.edge_band > 0 && hard_bits_ != 0; }
  std::vector<double> record_ms_, record_wall_ms_;
  std::vector<double> shadow_update_ms_, shadow_update_lights_;  // per frame (eye 0 carries the re-render)
  uint64_t traced_depth_frames_ = 0;
  uint64_t older_frames_ = 0;
  uint64_t forward_frames_ = 0;
  uint64_t eye_frames_ = 0;
};

}  // namespace dhr::bench
