// dhr-eval's methods through its command line: `local` and `full` with their fill counts, `default` equal to what
// dhr-xrclient and dhr-server ship (and, with --warp auto, testing depth where lights have an extent), and the
// traced depth splatted from each setting's own previous frame (-depth-splat).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <string>

#include "eval_cli_helpers.hpp"
#include "image/png_reader.hpp"
#include "plan/shipped_defaults.hpp"
#include "session/shipped_defaults.hpp"

namespace {

using namespace dhr::eval_test;

// local (the client's shadow maps only) and full (every ingredient) with an ablation: the fill counts are
// written, local never uses the server, full fills what its own eye's buffer cannot, and at zero delay full
// is exact (its lookups land on the centres of pixels traced for the very same rays).
TEST(EvalCliMethodsTest, LocalAndFullWriteTheirFillCounts) {
  const fs::path out = temp_dir("methods");
  const CliRun r = run_small(out, " --frames 6 --rtt-ms 0,100 --method paper+pred,local,full,"
                                  "full-no-shadow-first-no-pred --shadow-size 256 --snapshot-frame 2 "
                                  "--snapshot-crop 8,6,32,24");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto results = by_setting(read_results(out));
  ASSERT_EQ(results.size(), 8u);
  for (const auto& [key, res] : results) {
    for (const char* k : {"filled_other_eye_frac", "filled_shadow_map_frac", "unfilled_frac", "disoccluded_frac",
                          "edges_shadow_map_frac", "shadow_overrides_frac", "traced_depth_ms", "warp_ms"}) {
      EXPECT_TRUE(res.contains(k)) << key << " " << k;
    }
  }
  const json& local = results.at("local@100");
  EXPECT_EQ(local["no_data_frac"].get<double>(), 1.0);
  EXPECT_GT(local["filled_shadow_map_frac"].get<double>(), 0.5);
  EXPECT_EQ(local["unfilled_frac"].get<double>(), 0.0);
  EXPECT_EQ(local["bytes_per_frame"].get<double>(), 0.0);  // no server
  EXPECT_EQ(local["server_ms"].get<double>(), 0.0);
  const json& full = results.at("full@100");
  EXPECT_EQ(full["unfilled_frac"].get<double>(), 0.0);  // the shadow maps fill whatever the buffers cannot
  EXPECT_LE(full["bit_error"].get<double>(), results.at("paper+pred@100")["bit_error"].get<double>());
  EXPECT_EQ(results.at("full@0")["bit_error"].get<double>(), 0.0);
  EXPECT_TRUE(results.contains("full-no-shadow-first-no-pred@100"));
  EXPECT_TRUE(fs::exists(out / "snapshots" / "full_rtt100_guard64x36_eye0.png"));
  EXPECT_TRUE(fs::exists(out / "snapshots" / "exact_guard64x36_eye1.png"));
  EXPECT_TRUE(fs::exists(out / "snapshots" / "local_rtt100_guard64x36_wrong_bits_eye0.png"));
  // --snapshot-crop: one picture per round trip, exact and four methods side by side, wrong bits below.
  for (const char* rtt : {"0", "100"}) {
    const fs::path crop = out / "snapshots" / (std::string("crop_rtt") + rtt + "_guard64x36_eye0.png");
    ASSERT_TRUE(fs::exists(crop)) << crop;
    std::string error;
    const auto picture = dhr::read_png_rgb(crop.string(), &error);
    ASSERT_TRUE(picture.has_value()) << error;
    EXPECT_GE(picture->width, 5u * 32u * 7u);  // five columns of the 32-pixel crop scaled 7x (240 / 32)
    EXPECT_GE(picture->height, 2u * 24u * 7u);
  }
  fs::remove_all(out);
}

// dhr-eval's `default` is exactly what dhr-server and dhr-xrclient do without options: one setting per round trip
// on the client's own guard band, with every deterministic field equal to the named method those defaults amount
// to (whatever the --guard and --x-max lists say for the other methods).
TEST(EvalCliMethodsTest, DefaultIsWhatShips) {
  std::string equivalent;
  // The test's scene has hard lights only (--warp auto resolves for it as dhr-xrclient does).
  const dhr::client::WarpChoice warp = dhr::client::resolve_warp(dhr::client::shipped::kWarp, false);
  if (warp != dhr::client::WarpChoice::kPaper) {
    // Ingredients in dhr-eval's naming order (bilinear, depth, other-eye, shadow-fill, shadow-edges, shadow-first,
    // pred, adaptive-fov, older, neighbour).
    const bool depth = warp != dhr::client::WarpChoice::kEdges;
    const bool edges = warp != dhr::client::WarpChoice::kFull;
    equivalent = "full";
    if (!depth) equivalent += "-no-depth";
    if (edges) equivalent += "-no-other-eye-no-shadow-first";
    if (!dhr::server::shipped::kPredict) equivalent += "-no-pred";
    if (!dhr::server::shipped::kAdaptiveFov) equivalent += "-no-adaptive-fov";
    if (edges) equivalent += "-no-older-no-neighbour";
    if (depth && dhr::client::shipped::kDepthScale > 1) {
      equivalent += "-depth-scale-" + std::to_string(dhr::client::shipped::kDepthScale);
    }
    if (depth && dhr::client::shipped::kTracedDepth == dhr::client::TracedDepth::kSplat) equivalent += "-depth-splat";
  } else {
    equivalent = dhr::server::shipped::kPredict ? "paper+pred" : "paper";
  }
  ASSERT_EQ(dhr::client::shipped::kSchedule, dhr::client::Schedule::kNewest) << "the test compares x_max 'all' rows";
  const fs::path out = temp_dir("default");
  const CliRun r = run_small(out, " --frames 6 --rtt-ms 0,100 --guard 0,64x36 --x-max 2,all --method default" +
                                       std::string(equivalent == "paper" ? "" : ",paper") + "," + equivalent);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::map<std::string, json> rows;  // method@rtt for guard 64x36 and x_max all (-1)
  size_t defaults = 0;
  for (const json& row : read_results(out)) {
    if (row["method"] == "default") {
      ++defaults;
      EXPECT_EQ(row["guard"], "64x36") << row.dump();
    }
    if (row["guard"] == "64x36" && row["x_max"] == -1)
      rows[row["method"].get<std::string>() + "@" + std::to_string(row["rtt_ms"].get<int>())] = row;
  }
  EXPECT_EQ(defaults, 2u);  // one per round trip
  for (const char* rtt : {"@0", "@100"}) {
    ASSERT_TRUE(rows.count(std::string("default") + rtt)) << rtt;
    ASSERT_TRUE(rows.count(equivalent + rtt)) << equivalent << rtt;
    json a = rows.at(std::string("default") + rtt), b = rows.at(equivalent + rtt);
    for (const char* host : {"method", "client_ms", "server_ms", "encode_ms", "decode_ms", "client_gpu_timed", "warp_ms",
                             "traced_depth_ms"}) {
      a.erase(host);
      b.erase(host);
    }
    EXPECT_EQ(a, b) << "default vs " << equivalent << rtt;
  }
  fs::remove_all(out);
}

// In a moving scene each setting re-renders its own shadow maps (which faces, and when, depend on what its frames
// show: DHR's take turns where they only fill, `local`'s re-render every stale face each frame): `default` gives the
// same row beside `local` as alone, as a client's would.
TEST(EvalCliMethodsTest, EachSettingHasItsOwnShadowMapsInAMovingScene) {
  const std::string scene = std::string(DHR_SHARED_DATA_DIR) + "/scenes/living_room_moving.glb";
  if (!fs::exists(scene)) GTEST_SKIP() << scene << " is absent (../shared/data)";
  const fs::path alone = temp_dir("moving_alone"), beside = temp_dir("moving_beside");
  const CliRun a = run_small(alone, " --frames 8 --rtt-ms 100 --method default", scene);
  ASSERT_EQ(a.exit_code, 0) << a.output;
  const CliRun b = run_small(beside, " --frames 8 --rtt-ms 100 --method local,default", scene);
  ASSERT_EQ(b.exit_code, 0) << b.output;
  json x = by_setting(read_results(alone)).at("default@100"), y = by_setting(read_results(beside)).at("default@100");
  for (const char* host : {"client_ms", "server_ms", "encode_ms", "decode_ms", "client_gpu_timed", "warp_ms",
                           "traced_depth_ms", "connect_ms"}) {
    x.erase(host);
    y.erase(host);
  }
  EXPECT_GT(x["bit_error"].get<double>(), 0.0);
  EXPECT_EQ(x, y);
  fs::remove_all(alone);
  fs::remove_all(beside);
}

// --warp auto (what ships) in a scene with a light that has an extent: the depth test against the splatted traced
// depth, as `--warp edges-depth --traced-depth splat` (its traced depth is timed); in the hard-lit room above, none.
TEST(EvalCliMethodsTest, DefaultTestsDepthWhereLightsHaveAnExtent) {
  if (dhr::client::shipped::kWarp != dhr::client::WarpChoice::kAuto) GTEST_SKIP() << "--warp auto does not ship";
  const fs::path out = temp_dir("default_soft");
  const CliRun r = run_small(out, " --frames 4 --rtt-ms 100 --method default",
                             std::string(DHR_SOURCE_DIR) + "/assets/scenes/default_room_area.gltf");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::map<std::string, json> rows = by_setting(read_results(out));
  EXPECT_GT(rows.at("default@100")["traced_depth_ms"].get<double>(), 0.0);
  fs::remove_all(out);
}

// -depth-splat: the traced depth from each setting's own previous frame (its own renderer), no raster pass; exact
// at zero delay like full, and its splat timed from the second frame on.
TEST(EvalCliMethodsTest, DepthSplatRunsOnItsOwnFrames) {
  const fs::path out = temp_dir("splat");
  const CliRun r = run_small(out, " --frames 4 --rtt-ms 0,100 --method full,full-depth-splat,"
                                  "full-depth-scale-2-depth-splat-edge-band-0");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto results = by_setting(read_results(out));
  ASSERT_EQ(results.size(), 6u);
  EXPECT_EQ(results.at("full-depth-splat@0")["bit_error"].get<double>(), 0.0);
  EXPECT_GT(results.at("full-depth-splat@100")["traced_depth_ms"].get<double>(), 0.0);
  EXPECT_TRUE(results.contains("full-depth-scale-2-depth-splat-edge-band-0@100"));
  fs::remove_all(out);
}

}  // namespace
