// VisibilitySource over the DHR protocol client (xrclient/link/visibility_client.hpp). The transport (a UDP
// endpoint, an impaired sender, a simulated link) is owned elsewhere; `bytes_received` reports what it
// received from the server, for the summary's bits per frame.
#pragma once
#include <functional>

#include "frame/visibility_source.hpp"
#include "link/node_script.hpp"
#include "link/visibility_client.hpp"

namespace dhr::client {

class NetworkVisibilitySource final : public VisibilitySource {
 public:
  NetworkVisibilitySource(VisibilityClient& client, std::function<uint64_t()> bytes_received = {})
      : client_(&client), bytes_received_(std::move(bytes_received)) {}

  void tick() override { client_->tick(); }
  std::optional<VisibilityFormat> format() const override;
  bool failed() const override { return client_->failed(); }
  std::string failure() const override { return client_->failure(); }
  // With a node script: the transforms due by the pose's scene time go out first (the server traces that pose with
  // them).
  void send_pose(const FramePose& pose) override {
    if (node_script_) node_script_->play(pose.scene_time_ns, *client_);
    client_->send_pose(pose);
  }
  // dhr-xrclient --node-script (nullptr: none); the player must outlive the source.
  void set_node_script(NodeScriptPlayer* player) { node_script_ = player; }
  bool take_newest(uint32_t eye, VisibilityFrame& out) override;
  std::optional<int64_t> response_ns(uint64_t frame) const override { return client_->response_ns(frame); }
  VisibilitySourceStats stats() const override;

 private:
  VisibilityClient* client_;
  std::function<uint64_t()> bytes_received_;
  NodeScriptPlayer* node_script_ = nullptr;
  uint64_t taken_ = 0;
};

}  // namespace dhr::client
