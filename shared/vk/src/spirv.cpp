#include "vk/spirv.hpp"

#include <stdexcept>
#include <string>

namespace dhr::vk {

const SpirvModule& find_spirv(std::span<const SpirvModule> modules, std::string_view name) {
  for (const SpirvModule& m : modules) {
    if (name == m.name) return m;
  }
  throw std::runtime_error("embedded SPIR-V module '" + std::string(name) + "' not found");
}

}  // namespace dhr::vk
