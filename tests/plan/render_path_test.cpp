// --render-path's rule (plan/render_path.hpp): which passes an eye takes on which device.
#include "plan/render_path.hpp"
#include "plan/shipped_defaults.hpp"

#include <gtest/gtest.h>

namespace dhr::client {
namespace {

TEST(RenderPath, AutoTakesTheForwardPassExceptOnADiscreteGpu) {
  EXPECT_TRUE(forward_pass_for(RenderPath::kAuto, false));   // lavapipe, an integrated (headset) GPU
  EXPECT_FALSE(forward_pass_for(RenderPath::kAuto, true));   // a discrete GPU: the deferred passes
  EXPECT_TRUE(forward_pass_for(RenderPath::kForward, true));
  EXPECT_TRUE(forward_pass_for(RenderPath::kForward, false));
  EXPECT_FALSE(forward_pass_for(RenderPath::kDeferred, false));
  EXPECT_FALSE(forward_pass_for(RenderPath::kDeferred, true));
  EXPECT_EQ(shipped::kRenderPath, RenderPath::kAuto);
}

TEST(RenderPath, NamesParseBackAndNothingElseParses) {
  for (const RenderPath p : {RenderPath::kAuto, RenderPath::kForward, RenderPath::kDeferred}) {
    EXPECT_EQ(parse_render_path(to_string(p)), p);
  }
  EXPECT_EQ(parse_render_path(""), std::nullopt);
  EXPECT_EQ(parse_render_path("Forward"), std::nullopt);
  EXPECT_EQ(parse_render_path("forward "), std::nullopt);
}

}  // namespace
}  // namespace dhr::client
