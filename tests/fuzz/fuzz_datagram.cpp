// Fuzz target: decode_datagram / decode_header on arbitrary bytes.
// Properties: no crash or sanitizer report; both decoders agree on header errors; an accepted datagram
// has exactly encoded_size() bytes, re-encodes to the same bytes (except the quaternions, see below),
// stops being accepted when cut short by one byte or lengthened by one, and the re-encoding is itself
// accepted and stable.
//
// Why the quaternions are the exception: the decoder renormalizes the orientation in double (within the
// 1e-3 norm tolerance) and the encoder rounds it back to float, so the 16 quaternion bytes of each view
// may move by up to ~1e-3 on the first round trip and by at most one float step on later ones.
#include "protocol/protocol.hpp"
#include "protocol/protocol_layout.hpp"
#include "fuzz_support.hpp"

#include <cmath>
#include <cstring>
#include <vector>

namespace {

using dhr::DecodeError;

// Offsets of the 16 quaternion bytes of every view (and a NodeTransform's rotation) in an encoded message of this
// type (from the layout): the decoder renormalizes them.
std::vector<size_t> quaternion_offsets(dhr::MessageType type) {
  const dhr::ProtocolLayout& layout = dhr::protocol_layout();
  size_t in_view = 0;
  for (const dhr::LayoutField& f : layout.view.fields)
    if (f.name == "orientation") in_view = f.offset;
  std::vector<size_t> offsets;
  for (const dhr::LayoutBlock& m : layout.messages) {
    if (m.type != static_cast<uint8_t>(type)) continue;
    for (const dhr::LayoutField& f : m.fields) {
      if (f.type == "View") offsets.push_back(f.offset + in_view);
      if (f.name == "rotation") offsets.push_back(f.offset);
    }
  }
  return offsets;
}

float load_f32(const uint8_t* p) {
  const uint32_t bits = static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 |
                        static_cast<uint32_t>(p[2]) << 16 | static_cast<uint32_t>(p[3]) << 24;
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

bool in_quaternion(size_t i, const std::vector<size_t>& offsets) {
  for (size_t o : offsets)
    if (i >= o && i < o + 16) return true;
  return false;
}

// a and b equal outside the quaternion fields; inside, each float within `tolerance`.
void check_same_but_quaternions(const std::vector<uint8_t>& a, const uint8_t* b, const std::vector<size_t>& offsets,
                                float tolerance) {
  for (size_t i = 0; i < a.size(); ++i)
    if (!in_quaternion(i, offsets)) DHR_FUZZ_CHECK_MSG(a[i] == b[i], "re-encoded byte differs");
  for (size_t o : offsets)
    for (size_t k = 0; k < 4; ++k) {
      const float x = load_f32(a.data() + o + 4 * k), y = load_f32(b + o + 4 * k);
      DHR_FUZZ_CHECK(std::isfinite(x) && std::isfinite(y));
      DHR_FUZZ_CHECK_MSG(std::fabs(x - y) <= tolerance, "quaternion moved more than the tolerance");
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dhr::DatagramHeader header;
  const DecodeError header_error = dhr::decode_header(std::span<const uint8_t>(data, size), header);
  dhr::Datagram datagram;
  const DecodeError error = dhr::decode_datagram(data, size, datagram);
  DHR_FUZZ_CHECK(static_cast<size_t>(error) < dhr::kDecodeErrorCount);
  DHR_FUZZ_CHECK(dhr::to_string(error) != nullptr);
  if (header_error != DecodeError::kNone) {
    DHR_FUZZ_CHECK_MSG(error == header_error, "decode_datagram and decode_header disagree");
    return 0;
  }
  if (error != DecodeError::kNone) return 0;

  // Accepted.
  const dhr::MessageType type = dhr::message_type(datagram.message);
  DHR_FUZZ_CHECK(type == header.type);
  DHR_FUZZ_CHECK(datagram.session_token == header.session_token && datagram.sequence == header.sequence);
  DHR_FUZZ_CHECK(size <= dhr::kMaxDatagramSize);
  DHR_FUZZ_CHECK(dhr::encoded_size(datagram.message) == size);
  if (const auto* shard = std::get_if<dhr::VisibilityShard>(&datagram.message)) {
    DHR_FUZZ_CHECK(shard->payload_size >= 1 && shard->payload_size <= dhr::kMaxShardPayload);
    DHR_FUZZ_CHECK(shard->shard_index < shard->shard_count);
    DHR_FUZZ_CHECK(uint64_t{shard->first_pixel} + shard->pixel_count <=
                   uint64_t{shard->buffer_width} * shard->buffer_height);
  }

  // Cut short or lengthened by one byte: rejected.
  dhr::Datagram scratch;
  DHR_FUZZ_CHECK_MSG(dhr::decode_datagram(data, size - 1, scratch) != DecodeError::kNone, "truncation accepted");
  std::vector<uint8_t> longer(data, data + size);
  longer.push_back(0);
  DHR_FUZZ_CHECK_MSG(dhr::decode_datagram(longer, scratch) != DecodeError::kNone, "trailing byte accepted");

  // Re-encoding.
  const std::vector<size_t> quats = quaternion_offsets(type);
  const std::vector<uint8_t> again = dhr::encode_datagram(datagram);
  DHR_FUZZ_CHECK_MSG(again.size() == size, "re-encoding has another size");
  check_same_but_quaternions(again, data, quats, 2e-3f);
  dhr::Datagram second;
  DHR_FUZZ_CHECK_MSG(dhr::decode_datagram(again, second) == DecodeError::kNone, "re-encoding rejected");
  const std::vector<uint8_t> third = dhr::encode_datagram(second);
  DHR_FUZZ_CHECK(third.size() == size);
  check_same_but_quaternions(third, again.data(), quats, 1.2e-7f);  // one float step near 1
  return 0;
}
