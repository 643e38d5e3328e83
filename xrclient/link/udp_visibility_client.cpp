#include "link/udp_visibility_client.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <thread>

namespace dhr::client {

UdpVisibilityClient::~UdpVisibilityClient() { close(); }

void UdpVisibilityClient::connect(const VisibilityClientConfig& config, const std::string& host, uint16_t port,
                                  const net::ImpairmentParams& impairment) {
  if (client_) throw std::logic_error("visibility client: already connected");
  if (const std::string problem = impairment.validate(); !problem.empty())
    throw std::invalid_argument("network impairment: " + problem);
  if (impairment.active()) impaired_ = std::make_unique<net::ImpairedSender>(to_server_, impairment);
  net::DatagramSender& sender = impaired_ ? static_cast<net::DatagramSender&>(*impaired_) : to_server_;
  // The client exists before the receive thread starts, so the handler never sees it missing.
  client_ = std::make_unique<VisibilityClient>(config, sender, clock_);
  net::ClientEndpointConfig endpoint_config;
  endpoint_config.server_host = host;
  endpoint_config.server_port = port;
  endpoint_config.max_datagram_size = kMaxDatagramSize;
  VisibilityClient* client = client_.get();
  try {
    endpoint_.connect(endpoint_config, [client](const net::ReceivedDatagram& datagram) {
      client->on_datagram(datagram.bytes, datagram.receive_time_ns);
    });
  } catch (...) {
    client_.reset();
    impaired_.reset();
    throw;
  }
}

void UdpVisibilityClient::close() {
  if (!client_ || !endpoint_.running()) return;
  client_->close();
  // A Bye held by the impairment layer would be discarded by stop(): give it its delay (at most 1 s).
  if (impaired_) {
    const net::ImpairmentParams& p = impaired_->params();
    const double hold_ms = p.delay_ms + p.jitter_ms + (p.reorder > 0.0 ? p.reorder_delay_ms : 0.0) + 50.0;
    impaired_->wait_idle(static_cast<int64_t>(std::min(hold_ms, 1000.0) * 1e6));
  }
  // The socket discards what is still queued when it stops: let its I/O thread send it (at most 200 ms).
  const uint64_t handed = impaired_ ? impaired_->stats().forwarded : client_->stats().datagrams_sent;
  for (int i = 0; i < 100; ++i) {
    const net::UdpCounters c = endpoint_.counters();
    if (c.datagrams_sent + c.send_errors >= handed) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  endpoint_.stop();
}

std::optional<net::ImpairedSenderStats> UdpVisibilityClient::impairment_stats() const {
  if (!impaired_) return std::nullopt;
  return impaired_->stats();
}

}  // namespace dhr::client
