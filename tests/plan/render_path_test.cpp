// --render-path's rule (plan/render_path.hpp): which passes an eye takes on which device; the shipped edge band's
// size rule (plan/shipped_defaults.hpp).
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

// The shipped edge band: 3 traced pixels per 240 rows of the eye (the band is an angle), within 1 to 8.
TEST(ShippedEdgeBand, ScalesWithTheEyeHeightWithinItsLimits) {
  EXPECT_EQ(shipped::edge_band(Extent{320, 240}), 3u);
  EXPECT_EQ(shipped::edge_band(Extent{640, 480}), 6u);
  EXPECT_EQ(shipped::edge_band(Extent{960, 720}), 8u);      // 9, capped
  EXPECT_EQ(shipped::edge_band(Extent{1832, 1920}), 8u);
  EXPECT_EQ(shipped::edge_band(Extent{160, 120}), 2u);      // 1.5 rounds up
  EXPECT_EQ(shipped::edge_band(Extent{64, 48}), 1u);        // 0.6: at least 1
  EXPECT_EQ(shipped::edge_band(Extent{8, 8}), 1u);
  EXPECT_EQ(shipped::edge_band(Extent{320, 240}), shipped::kEdgeBand);
}

}  // namespace
}  // namespace dhr::client
