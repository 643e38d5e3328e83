// shaders/include/shaders/light_eval.h must stay valid GLSL as well as C++: compile a compute shader that
// uses every function with glslang (the same compiler the build uses for the project's shaders).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace {

TEST(LightEvalGlsl, CompilesWithGlslang) {
  const auto dir = std::filesystem::temp_directory_path() / ("dhr_light_eval_glsl_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto src = dir / "light_eval_check.comp";
  std::ofstream(src) << R"(#version 460
#extension GL_GOOGLE_include_directive : require
#include "shaders/light_eval.h"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Lights { PackedLight lights[]; };
layout(std430, binding = 1) writeonly buffer Result { vec4 result[]; };
void main() {
  const vec3 p = vec3(float(gl_GlobalInvocationID.x), 0.0f, 0.0f);
  const vec3 n = vec3(0.0f, 1.0f, 0.0f);
  vec3 e = vec3(0.0f);
  int tests = 0;
  for (int i = 0; i < lights.length(); ++i) {
    vec3 l;
    float d;
    const int t = light_test(lights[i], p, n, l, d);
    tests += t;
    if (t == kLightContributes) e += light_irradiance(lights[i], l, d) * light_cosine(n, l);
  }
  result[gl_GlobalInvocationID.x] = vec4(e, float(tests));
}
)";
  const std::string command = std::string(DHR_GLSLANG) + " -V --target-env vulkan1.2 --quiet -I" DHR_SOURCE_DIR
                              "/shaders/include -o " + (dir / "out.spv").string() + " " + src.string();
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  EXPECT_TRUE(std::filesystem::exists(dir / "out.spv"));
  std::filesystem::remove_all(dir);
}

}  // namespace
