#include "log/log.hpp"

#include <gtest/gtest.h>

TEST(Log, LevelRoundTrips) {
  const auto saved = dhr::log::level();
  dhr::log::set_level(dhr::log::Level::kError);
  EXPECT_EQ(dhr::log::level(), dhr::log::Level::kError);
  testing::internal::CaptureStderr();
  dhr::log::info("hidden %d", 1);
  dhr::log::error("shown %d", 2);
  const std::string out = testing::internal::GetCapturedStderr();
  EXPECT_EQ(out, "[dhr error] shown 2\n");
  dhr::log::set_level(saved);
}
