// Test fixtures: a Context with the Khronos validation layer on; every test must end with zero
// validation errors, counted after the Context is destroyed (so leaked handles fail the test too).
#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <optional>
#include <string>

#include "vk/context.hpp"

namespace dhr::vk::test {

// True when the user asked for a real GPU (DHR_VK_DEVICE=gpu): lavapipe-specific checks are skipped.
inline bool gpu_requested() {
  const char* env = std::getenv("DHR_VK_DEVICE");
  return env != nullptr && std::string(env) == "gpu";
}

// Sets an environment variable for the scope, restoring the previous value afterwards.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value != nullptr) {
      setenv(name, value, 1);
    } else {
      unsetenv(name);
    }
  }
  ~ScopedEnv() {
    if (old_) {
      setenv(name_.c_str(), old_->c_str(), 1);
    } else {
      unsetenv(name_.c_str());
    }
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  std::string name_;
  std::optional<std::string> old_;
};

class VulkanTest : public ::testing::Test {
 protected:
  virtual ContextOptions options() const {
    ContextOptions o;
    o.app_name = "dhr_vulkan_tests";
    o.validation = true;
    return o;
  }

  void SetUp() override {
    errors_before_ = process_validation_error_count();
    try {
      context_ = Context::create(options());
    } catch (const std::exception& e) {
      FAIL() << "Context::create failed: " << e.what();
    }
    ASSERT_TRUE(context_->validation_enabled())
        << "the tests need VK_LAYER_KHRONOS_validation (apt-get install vulkan-validationlayers)";
  }

  void TearDown() override {
    context_.reset();
    EXPECT_EQ(process_validation_error_count() - errors_before_, 0u) << "Vulkan validation errors (see log)";
  }

  Context& ctx() { return *context_; }

  std::unique_ptr<Context> context_;
  uint32_t errors_before_ = 0;
};

class RayTracingTest : public VulkanTest {
 protected:
  ContextOptions options() const override {
    ContextOptions o = VulkanTest::options();
    o.require_ray_tracing = true;
    return o;
  }
};

}  // namespace dhr::vk::test
