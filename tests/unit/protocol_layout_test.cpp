// The wire layout is listed once (protocol/wire_layout.hpp); everything else that states it is checked
// against protocol_layout(): the size constants and the encoder, docs/protocol.md's byte tables, and the
// Wireshark dissector's layout section (tools/wireshark/dhr.lua).
#include "protocol/protocol.hpp"
#include "protocol/protocol_layout.hpp"
#include "protocol_fixtures.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace dhr {
namespace {

std::string read_text(const std::string& relative) {
  std::ifstream in(std::string(DHR_SOURCE_DIR) + "/" + relative);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(' ');
  const size_t b = s.find_last_not_of(' ');
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// One section of docs/protocol.md: its stated size and its `| offset | type | field |` table's first two
// columns, "offset type" per row.
struct DocBlock {
  std::string heading;
  size_t size = 0;
  std::string tail;       // "n" in "42 + n bytes"
  std::string type;       // "type 1", messages only
  std::string direction;  // messages only
  std::vector<std::string> rows;
};

std::map<std::string, DocBlock> doc_blocks(const std::vector<std::string>& lines) {
  static const std::regex kBlockHeading(R"(^## (Header|View) \((\d+) bytes.*)");
  static const std::regex kMessageHeading(
      R"(^### (\w+) \((type \d+), (client -> server|server -> client|both ways)[,)].*: (\d+)(?: \+ (\w+))? bytes.*)");
  std::map<std::string, DocBlock> blocks;
  DocBlock* current = nullptr;
  bool in_table = false;
  for (const std::string& line : lines) {
    std::smatch m;
    if (line.starts_with("#")) {
      current = nullptr;
      in_table = false;
      if (std::regex_match(line, m, kBlockHeading)) {
        current = &blocks[m[1]];
        current->size = std::stoul(m[2]);
      } else if (std::regex_match(line, m, kMessageHeading)) {
        current = &blocks[m[1]];
        current->type = m[2];
        current->direction = m[3];
        current->size = std::stoul(m[4]);
        current->tail = m[5];
      }
      if (current) current->heading = line;
      continue;
    }
    if (!current) continue;
    if (line.starts_with("| offset | type | field |")) {
      in_table = current->rows.empty();  // the section's first table only
      continue;
    }
    if (!in_table) continue;
    if (!line.starts_with("|")) {
      in_table = false;
      continue;
    }
    if (line.starts_with("|---")) continue;
    std::vector<std::string> cells;
    std::istringstream row(line.substr(1));
    for (std::string cell; cells.size() < 2 && std::getline(row, cell, '|');) cells.push_back(trim(cell));
    current->rows.push_back(cells.size() == 2 ? cells[0] + " " + cells[1] : line);
  }
  return blocks;
}

std::vector<std::string> layout_rows(const LayoutBlock& block) {
  std::vector<std::string> rows;
  for (const LayoutField& f : block.fields) rows.push_back(std::to_string(f.offset) + " " + f.type);
  return rows;
}

void expect_doc_matches(const std::map<std::string, DocBlock>& docs, const LayoutBlock& block) {
  SCOPED_TRACE(block.name);
  const auto it = docs.find(block.name);
  ASSERT_NE(it, docs.end()) << "docs/protocol.md has no section for " << block.name
                            << " (`## Header (N bytes`, `## View (N bytes`, "
                               "`### Name (type T, direction...): N bytes`)";
  const DocBlock& doc = it->second;
  EXPECT_EQ(doc.size, block.size) << doc.heading;
  EXPECT_EQ(doc.tail, block.tail) << doc.heading;
  if (block.type != 0) {
    EXPECT_EQ(doc.type, "type " + std::to_string(block.type)) << doc.heading;
    EXPECT_EQ(doc.direction, block.direction) << doc.heading;
  }
  // "offset type" per row; `dhr-protocol-layout --markdown` prints the expected tables.
  EXPECT_EQ(doc.rows, layout_rows(block));
}

TEST(ProtocolLayout, DocsTablesMatchTheFieldList) {
  const std::string text = read_text("docs/protocol.md");
  ASSERT_FALSE(text.empty());
  const auto docs = doc_blocks(lines_of(text));
  const ProtocolLayout& layout = protocol_layout();
  expect_doc_matches(docs, layout.header);
  expect_doc_matches(docs, layout.view);
  for (const LayoutBlock& m : layout.messages) expect_doc_matches(docs, m);
  EXPECT_EQ(docs.size(), 2 + layout.messages.size()) << "docs/protocol.md documents a message the list lacks";
}

TEST(ProtocolLayout, WiresharkLayoutIsCurrent) {
  const std::vector<std::string> lines = lines_of(read_text("tools/wireshark/dhr.lua"));
  std::string section;
  bool inside = false;
  for (const std::string& line : lines) {
    if (line.starts_with(kLuaLayoutBegin)) inside = true;
    if (inside) section += line + "\n";
    if (inside && line.starts_with(kLuaLayoutEnd)) break;
  }
  EXPECT_EQ(section, layout_lua(protocol_layout()))
      << "tools/wireshark/dhr.lua's layout section is stale: run "
         "`build/tools/dhr-protocol-layout --update-wireshark tools/wireshark/dhr.lua`";
}

// Bytes of a layout type: "u16", "f32 x4", "View"; a tail ("u8[n]") counts 0.
size_t wire_bytes(const std::string& type) {
  static const std::map<std::string, size_t> kScalar = {{"u8", 1},  {"u16", 2}, {"u32", 4}, {"u64", 8},
                                                        {"i64", 8}, {"f32", 4}, {"f64", 8}};
  if (type == "View") return kViewWireSize;
  if (type.starts_with("u8[")) return 0;
  const size_t x = type.find(" x");
  const size_t count = x == std::string::npos ? 1 : std::stoul(type.substr(x + 2));
  return kScalar.at(type.substr(0, x)) * count;
}

TEST(ProtocolLayout, SizesAreTheListsSizes) {
  const ProtocolLayout& layout = protocol_layout();
  EXPECT_EQ(layout.header.size, kHeaderSize);
  EXPECT_EQ(layout.view.size, kViewWireSize);
  size_t view_bytes = 0;
  for (const LayoutField& f : layout.view.fields) view_bytes += wire_bytes(f.type);
  EXPECT_EQ(view_bytes, kViewWireSize);
  for (const LayoutBlock& block : layout.messages) {
    SCOPED_TRACE(block.name);
    // Fields tile the block: each starts where the previous one ends; a tail starts at the fixed size.
    size_t offset = kHeaderSize;
    for (const LayoutField& f : block.fields) {
      EXPECT_EQ(f.offset, offset) << f.name;
      offset += wire_bytes(f.type);
    }
    EXPECT_EQ(offset, block.size);
    if (block.name == "VisibilityShard") {
      EXPECT_EQ(block.size, kShardFixedSize);
      EXPECT_EQ(block.tail_max, kMaxShardPayload);
    }
    if (block.name == "Hello") {
      EXPECT_EQ(block.tail_max, kMaxSceneIdLength);
    }
  }
  // Every sample message encodes to its fixed size plus its tail.
  for (const Datagram& d : test::sample_datagrams()) {
    const LayoutBlock* block = nullptr;
    for (const LayoutBlock& b : layout.messages)
      if (b.type == static_cast<uint8_t>(message_type(d.message))) block = &b;
    ASSERT_NE(block, nullptr);
    size_t tail = 0;
    if (const auto* h = std::get_if<Hello>(&d.message)) tail = h->scene_id.size();
    if (const auto* s = std::get_if<VisibilityShard>(&d.message)) tail = s->payload_size;
    EXPECT_EQ(encode_datagram(d).size(), block->size + tail) << block->name;
    EXPECT_EQ(encoded_size(d.message), block->size + tail) << block->name;
  }
}

}  // namespace
}  // namespace dhr
