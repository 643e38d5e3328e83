// The wire layout as data, derived from the field lists in protocol/wire_layout.hpp: each block's fields
// with their offsets and wire types. docs/protocol.md's byte tables and tools/wireshark/dhr.lua's layout
// tables are checked against it (tests/unit/protocol_layout_test.cpp); dhr-protocol-layout prints it.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace dhr {

struct LayoutField {
  size_t offset = 0;  // messages: from the datagram's start; the header and the View: from their own start
  std::string type;   // "u8", "u16 x2" (an array), "View", "u8[n]" (the tail: n bytes, n in a length field)
  std::string name;
  std::string doc;
};

struct LayoutBlock {
  std::string name;       // "Header", "View", or the message's name
  uint8_t type = 0;       // the message type id; 0 for the header and the View
  std::string direction;  // "client -> server", "server -> client" or "both ways"; empty for the header, View
  size_t size = 0;        // bytes without the tail (a message's include the header)
  std::string tail;               // the tail's length symbol ("n"); empty without a tail
  std::string tail_length_field;  // the field holding the tail's length
  size_t tail_max = 0;            // the largest tail accepted
  std::vector<LayoutField> fields;
};

struct ProtocolLayout {
  LayoutBlock header;
  LayoutBlock view;
  std::vector<LayoutBlock> messages;  // grouped by direction, in wire_layout.hpp's order
};

const ProtocolLayout& protocol_layout();

// Markdown tables in docs/protocol.md's form (`| offset | type | field |`, the doc strings as the field).
std::string layout_markdown(const ProtocolLayout& layout);

// The layout section of tools/wireshark/dhr.lua, from its kLuaLayoutBegin line to its kLuaLayoutEnd line.
inline constexpr std::string_view kLuaLayoutBegin = "-- BEGIN LAYOUT";
inline constexpr std::string_view kLuaLayoutEnd = "-- END LAYOUT";
std::string layout_lua(const ProtocolLayout& layout);

}  // namespace dhr
