// VisibilitySource over the DHR protocol client (xrclient/link/visibility_client.hpp). The transport (a UDP
// endpoint, an impaired sender, a simulated link) is owned elsewhere; `bytes_received` reports what it
// received from the server, for the summary's bits per frame.
#pragma once
#include <functional>

#include "frame/visibility_source.hpp"
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
  void send_pose(const FramePose& pose) override {
    client_->send_pose(pose);
  }
  bool take_newest(uint32_t eye, VisibilityFrame& out) override;
  std::optional<int64_t> response_ns(uint64_t frame) const override { return client_->response_ns(frame); }
  VisibilitySourceStats stats() const override;

 private:
  VisibilityClient* client_;
  std::function<uint64_t()> bytes_received_;
  uint64_t taken_ = 0;
};

}  // namespace dhr::client
