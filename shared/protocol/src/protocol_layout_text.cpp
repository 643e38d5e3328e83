// The layout as text: docs/protocol.md's table form and tools/wireshark/dhr.lua's layout section.
#include "protocol/protocol_layout.hpp"

#include "protocol/protocol.hpp"

#include <sstream>

namespace dhr {
namespace {

std::string quoted(std::string_view s) { return "\"" + std::string(s) + "\""; }

void markdown_block(std::ostringstream& out, const std::string& heading, const LayoutBlock& block) {
  out << heading << block.size;
  if (!block.tail.empty()) out << " + " << block.tail;
  out << " bytes\n\n| offset | type | field |\n|---:|---|---|\n";
  for (const LayoutField& f : block.fields)
    out << "| " << f.offset << " | " << f.type << " | " << f.name << ": " << f.doc << " |\n";
  out << "\n";
}

void lua_fields(std::ostringstream& out, const LayoutBlock& block, const char* indent) {
  for (const LayoutField& f : block.fields)
    out << indent << "{ " << f.offset << ", " << quoted(f.type) << ", " << quoted(f.name) << " },\n";
}

}  // namespace

std::string layout_markdown(const ProtocolLayout& layout) {
  std::ostringstream out;
  markdown_block(out, "## Header: ", layout.header);
  markdown_block(out, "## View: ", layout.view);
  for (const LayoutBlock& m : layout.messages)
    markdown_block(out, "### " + m.name + " (type " + std::to_string(m.type) + ", " + m.direction + "): ", m);
  return out.str();
}

std::string layout_lua(const ProtocolLayout& layout) {
  std::ostringstream out;
  out << kLuaLayoutBegin << ": written by `dhr-protocol-layout --update-wireshark tools/wireshark/dhr.lua` from\n"
      << "-- shared/protocol/include/protocol/wire_layout.hpp (ProtocolLayout.WiresharkLayoutIsCurrent checks it).\n"
      << "-- Per field: { offset, wire type, name }; offsets from the datagram's start (the View's from its own).\n";
  out << "local VERSION = " << int{kProtocolVersion} << "\nlocal MAX_DATAGRAM = " << kMaxDatagramSize
      << "\nlocal SEAL_TAG = " << kSealOverhead << "\n";
  out << "local HEADER = { size = " << layout.header.size << ", fields = {\n";
  lua_fields(out, layout.header, "  ");
  out << "} }\nlocal VIEW = { size = " << layout.view.size << ", fields = {\n";
  lua_fields(out, layout.view, "  ");
  out << "} }\nlocal MESSAGES = {\n";
  for (const LayoutBlock& m : layout.messages) {
    out << "  [" << int{m.type} << "] = { name = " << quoted(m.name) << ", size = " << m.size;
    if (!m.tail.empty()) out << ", tail_length = " << quoted(m.tail_length_field);
    out << ", fields = {\n";
    lua_fields(out, m, "    ");
    out << "  } },\n";
  }
  out << "}\n" << kLuaLayoutEnd << "\n";
  return out.str();
}

}  // namespace dhr
