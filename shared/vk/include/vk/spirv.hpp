// Embedded SPIR-V modules, produced at build time by dhr_add_shader_library (cmake/DhrShaders.cmake).
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace dhr::vk {

struct SpirvModule {
  const char* name;       // shader file name, e.g. "smoke.rgen"
  const uint32_t* words;  // SPIR-V code
  size_t word_count;
};

// Returns the module called `name`; throws std::runtime_error naming it when absent.
const SpirvModule& find_spirv(std::span<const SpirvModule> modules, std::string_view name);

}  // namespace dhr::vk
