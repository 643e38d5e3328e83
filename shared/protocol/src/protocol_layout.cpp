// protocol_layout(): the field lists of protocol/wire_layout.hpp described as data.
#include "protocol/protocol_layout.hpp"

#include "protocol/protocol.hpp"

#include <tuple>

namespace dhr {
namespace {

using namespace wire;

template <class F>
void describe_field(const F& f, size_t& offset, LayoutBlock& block) {
  std::string type;
  if constexpr (F::kFieldKind == FieldKind::kScalar) {
    type = wire_name(F::kType);
    if (F::kCount > 1) type += " x" + std::to_string(F::kCount);
  } else if constexpr (F::kFieldKind == FieldKind::kTailLength) {
    type = wire_name(F::kType);
    block.tail_length_field = f.name;
  } else if constexpr (F::kFieldKind == FieldKind::kNested) {
    type = f.type_name;
  } else {
    type = "u8[" + std::string(f.symbol) + "]";
    block.tail = f.symbol;
  }
  block.fields.push_back(LayoutField{offset, type, std::string(f.name), std::string(f.doc)});
  offset += fixed_field_size<F>();
}

template <class Fields>
LayoutBlock describe(std::string_view name, const Fields& fields, size_t origin) {
  LayoutBlock block;
  block.name = name;
  size_t offset = origin;
  std::apply([&](const auto&... f) { (describe_field(f, offset, block), ...); }, fields);
  block.size = offset;
  return block;
}

template <class Layout>
LayoutBlock describe_message(const Layout& layout) {
  LayoutBlock block = describe(layout.name, layout.fields, kHeaderSize);
  block.type = static_cast<uint8_t>(layout.type);
  block.direction = direction_name(layout.direction);
  if constexpr (kHasTail<decltype(layout.fields)>) block.tail_max = tail_max_length(layout);
  return block;
}

ProtocolLayout make_layout() {
  ProtocolLayout layout;
  layout.header = describe("Header", kHeaderFields, 0);
  layout.view = describe("View", kViewFields, 0);
  std::apply([&](const auto&... m) { (layout.messages.push_back(describe_message(m)), ...); }, kMessageLayouts);
  return layout;
}

}  // namespace

const ProtocolLayout& protocol_layout() {
  static const ProtocolLayout layout = make_layout();
  return layout;
}

}  // namespace dhr
