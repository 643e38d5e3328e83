// dhr-eval end to end, through its command-line contract: a few frames at a low resolution on the default
// scene and the shipped synthetic 6-DoF trace; checks the metrics are sane and ordered as physics says.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>
#include <unistd.h>

#include "image/png_reader.hpp"
#include "plan/shipped_defaults.hpp"
#include "session/shipped_defaults.hpp"

#include "eval_cli_helpers.hpp"

namespace {

using namespace dhr::eval_test;

CliRun small_run(const fs::path& out) {
  return run_small(out, " --frames 8 --rtt-ms 0,50,100 --method stale,paper,paper+pred");
}

class EvalCliTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(temp_dir("main"));
    run_ = new CliRun(small_run(*dir_));
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
    delete run_;
  }
  static fs::path* dir_;
  static CliRun* run_;
};
fs::path* EvalCliTest::dir_ = nullptr;
CliRun* EvalCliTest::run_ = nullptr;

TEST_F(EvalCliTest, WritesEverySettingWithTheContractKeys) {
  ASSERT_EQ(run_->exit_code, 0) << run_->output;
  const json results = read_results(*dir_);
  ASSERT_TRUE(results.is_array());
  EXPECT_EQ(results.size(), 9u);
  for (const json& r : results) {
    for (const char* key : {"method", "rtt_ms", "x_max", "guard", "frames", "bit_error", "visibility_error", "ssim", "psnr",
                            "flip", "unknown_frac", "client_ms", "server_ms", "server_rays_per_pixel", "bytes_per_frame",
                            "response_ms"}) {
      EXPECT_TRUE(r.contains(key)) << key;
    }
    EXPECT_EQ(r["frames"].get<int>(), 8);
    EXPECT_GE(r["bit_error"].get<double>(), 0.0);
    EXPECT_LE(r["bit_error"].get<double>(), 1.0);
    EXPECT_GT(r["ssim"].get<double>(), 0.0);
    EXPECT_LE(r["ssim"].get<double>(), 1.0);
    EXPECT_GE(r["unknown_frac"].get<double>(), 0.0);
    EXPECT_LE(r["unknown_frac"].get<double>(), 1.0);
    EXPECT_GT(r["bytes_per_frame"].get<double>(), 0.0);
    EXPECT_GT(r["server_ms"].get<double>(), 0.0);
    EXPECT_GT(r["client_ms"].get<double>(), 0.0);
  }
  EXPECT_TRUE(fs::exists(*dir_ / "results.csv"));
  EXPECT_TRUE(fs::exists(*dir_ / "run.json"));
}

TEST_F(EvalCliTest, ZeroDelayIsExact) {
  ASSERT_EQ(run_->exit_code, 0) << run_->output;
  for (const auto& [key, r] : by_setting(read_results(*dir_))) {
    if (r["rtt_ms"].get<double>() != 0.0) continue;
    EXPECT_EQ(r["bit_error"].get<double>(), 0.0) << key;
    EXPECT_EQ(r["ssim"].get<double>(), 1.0) << key;
    EXPECT_TRUE(r["psnr"].is_null()) << key << ": identical images have infinite PSNR";
    EXPECT_EQ(r["unknown_frac"].get<double>(), 0.0) << key;
    EXPECT_EQ(r["response_ms"].get<double>(), 0.0) << key;
  }
}

// FLIP of the displayed image against the ground truth: 0 when identical, growing as the stale buffer ages.
TEST_F(EvalCliTest, FlipIsZeroAtZeroDelayAndGrowsWithTheStaleBuffersAge) {
  ASSERT_EQ(run_->exit_code, 0) << run_->output;
  std::map<std::string, json> r = by_setting(read_results(*dir_));
  for (const auto& [key, result] : r) {
    ASSERT_TRUE(result["flip"].is_number()) << key;
    EXPECT_GE(result["flip"].get<double>(), 0.0) << key;
    EXPECT_LE(result["flip"].get<double>(), 1.0) << key;
    if (result["rtt_ms"].get<double>() == 0.0) {
      EXPECT_EQ(result["flip"].get<double>(), 0.0) << key;
    }
  }
  const auto flip = [&](const std::string& key) { return r.at(key)["flip"].get<double>(); };
  EXPECT_LT(flip("stale@0"), flip("stale@50"));
  EXPECT_LT(flip("stale@50"), flip("stale@100"));
  EXPECT_LT(flip("paper@100"), flip("stale@100"));
}

TEST_F(EvalCliTest, ErrorGrowsWithDelayAndTheWarpBeatsTheStaleBuffer) {
  ASSERT_EQ(run_->exit_code, 0) << run_->output;
  std::map<std::string, json> r = by_setting(read_results(*dir_));
  const auto bits = [&](const std::string& key) { return r.at(key)["bit_error"].get<double>(); };
  EXPECT_LT(bits("stale@0"), bits("stale@50"));
  EXPECT_LT(bits("stale@50"), bits("stale@100"));
  EXPECT_LE(bits("paper@100"), bits("stale@100"));
  EXPECT_LT(r.at("stale@100")["ssim"].get<double>(), r.at("paper@100")["ssim"].get<double>());
  // The response time covers the round trip, rounded up to whole frames.
  EXPECT_GE(r.at("paper@100")["response_ms"].get<double>(), 100.0);
  EXPECT_LT(r.at("paper@100")["response_ms"].get<double>(), 100.0 + 2 * 11.2);
}

// With hard lights only, |k shown - k exact| is a wrong bit: visibility_error counts bit_error's wrong bits, over
// the surface pixels instead of every display pixel (the room shows some background at these poses).
TEST_F(EvalCliTest, VisibilityErrorIsTheBitErrorWithHardLights) {
  ASSERT_EQ(run_->exit_code, 0) << run_->output;
  bool some_error = false;
  for (const auto& [key, r] : by_setting(read_results(*dir_))) {
    const double surface = r["surface_frac"].get<double>();
    ASSERT_GT(surface, 0.5) << key;
    ASSERT_LE(surface, 1.0) << key;
    EXPECT_NEAR(r["visibility_error"].get<double>() * surface, r["bit_error"].get<double>(), 1e-7) << key;
    ASSERT_EQ(r["visibility_error_per_light"].size(), r["bit_error_per_light"].size()) << key;
    for (size_t l = 0; l < r["bit_error_per_light"].size(); ++l) {
      EXPECT_NEAR(r["visibility_error_per_light"][l].get<double>() * surface, r["bit_error_per_light"][l].get<double>(),
                  1e-7)
          << key << " light " << l;
    }
    some_error |= r["bit_error"].get<double>() > 0.0;
    EXPECT_EQ(r["soft_rays_per_pair"].get<double>(), 0.0) << key;
  }
  EXPECT_TRUE(some_error);
}

TEST_F(EvalCliTest, TwoRunsGiveIdenticalMetrics) {
  ASSERT_EQ(run_->exit_code, 0) << run_->output;
  const fs::path again = temp_dir("again");
  const CliRun second = small_run(again);
  ASSERT_EQ(second.exit_code, 0) << second.output;
  const json a = read_results(*dir_), b = read_results(again);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    for (const char* key : {"method", "rtt_ms", "bit_error", "bit_error_per_light", "visibility_error", "ssim", "psnr", "flip",
                            "unknown_frac", "bytes_per_frame", "response_ms", "frames_behind"}) {
      EXPECT_EQ(a[i][key], b[i][key]) << i << " " << key;
    }
  }
  fs::remove_all(again);
}

// The whole simulation runs on virtual time, network impairments, handshake and heartbeats included.
TEST(EvalCliDeterminismTest, ImpairedRunsWithModelledServerTimeRepeatExactly) {
  const auto run_once = [](const fs::path& out) {
    return run_small(out, " --frames 10 --rtt-ms 50 --method paper,paper+pred --jitter-ms 10 --loss 0.1 --server-ms 15"
                          " --seed 7");
  };
  const fs::path first = temp_dir("impaired_a"), second = temp_dir("impaired_b");
  const CliRun a_run = run_once(first), b_run = run_once(second);
  ASSERT_EQ(a_run.exit_code, 0) << a_run.output;
  ASSERT_EQ(b_run.exit_code, 0) << b_run.output;
  const json a = read_results(first), b = read_results(second);
  ASSERT_EQ(a.size(), 2u);
  ASSERT_EQ(b.size(), 2u);
  for (size_t i = 0; i < a.size(); ++i) {
    for (const auto& [key, value] : a[i].items()) {
      if (key == "client_ms" || key == "server_ms" || key == "encode_ms" || key == "decode_ms" || key == "warp_ms" ||
          key == "traced_depth_ms") {
        continue;  // host or GPU time
      }
      EXPECT_EQ(value, b[i][key]) << i << " " << key;
    }
    EXPECT_GT(a[i]["datagrams_lost"].get<int>(), 0) << "10 % loss over a whole run loses some datagrams";
  }
  fs::remove_all(first);
  fs::remove_all(second);
}

// --server-ms is virtual time the service spends per traced frame: with no network delay the visibility
// of frame n arrives that much later, and the response time grows by it (rounded up to whole frames).
TEST(EvalCliServerTimeTest, ModelledServerTimeDelaysTheResponse) {
  const fs::path out = temp_dir("server_ms");
  const CliRun r = run_small(out, " --frames 8 --rtt-ms 0 --method paper --server-ms 20");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json results = read_results(out);
  ASSERT_EQ(results.size(), 1u);
  const double response = results[0]["response_ms"].get<double>();
  EXPECT_GE(response, 20.0);
  EXPECT_LT(response, 20.0 + 11.2);
  EXPECT_GE(results[0]["frames_behind"].get<double>(), 2.0);
  EXPECT_GT(results[0]["bit_error"].get<double>(), 0.0) << "the visibility is two frames old";
  fs::remove_all(out);
}

TEST_F(EvalCliTest, ReportWritesMarkdownAndPlots) {
  ASSERT_EQ(run_->exit_code, 0) << run_->output;
  const CliRun report = run_cli("report " + dir_->string());
  ASSERT_EQ(report.exit_code, 0) << report.output;
  std::ifstream md(*dir_ / "report.md");
  const std::string text((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("| paper+pred | 100 |"), std::string::npos) << text;
  if (std::system("command -v gnuplot >/dev/null 2>&1") == 0) {
    EXPECT_TRUE(fs::exists(*dir_ / "ssim_vs_frames.svg"));
    EXPECT_TRUE(fs::exists(*dir_ / "pareto.svg"));
    EXPECT_TRUE(fs::exists(*dir_ / "rays_vs_visibility_error.svg"));
  }
  EXPECT_NE(text.find("visibility error"), std::string::npos) << text;
}

// Lights with an extent: the truth is each light's fraction, converged; the client shows levels (k = level / 7).
TEST(EvalCliSoftTest, SoftLightsAreJudgedByTheirFractions) {
  const fs::path out = temp_dir("soft");
  const std::string area = std::string(DHR_SOURCE_DIR) + "/assets/scenes/default_room_area.gltf";
  const CliRun r = run_small(out, " --frames 8 --rtt-ms 0,50,100 --method stale,paper+pred,local", area);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::map<std::string, json> rows = by_setting(read_results(out));
  ASSERT_EQ(rows.size(), 9u);
  const auto k = [&](const std::string& key) { return rows.at(key)["visibility_error"].get<double>(); };
  for (const char* key : {"stale@0", "paper+pred@0"}) {
    // Exact up to the levels' quantization (at most 1/14 per soft pair) and the server's sampling noise.
    EXPECT_GT(k(key), 0.0) << key;
    EXPECT_LT(k(key), 1.0 / 14.0) << key;
    EXPECT_GT(rows.at(key)["soft_rays_per_pair"].get<double>(), 1.0) << key << ": the server samples the extents";
    EXPECT_GT(rows.at(key)["server_rays_per_pixel"].get<double>(), 1.0) << key;
  }
  EXPECT_LT(k("stale@0"), k("stale@50"));
  EXPECT_LT(k("stale@50"), k("stale@100"));
  EXPECT_LE(k("paper+pred@100"), k("stale@100"));
  EXPECT_EQ(rows.at("local@100")["server_rays_per_pixel"].get<double>(), 0.0);
  EXPECT_GT(k("local@100"), k("stale@0"));
  std::ifstream run_json(out / "run.json");
  const json meta = json::parse(run_json);
  EXPECT_EQ(meta["soft_lights"].get<int>(), 2);
  EXPECT_GT(meta["truth_samples"].get<int>(), 32);
  // The server sampling more (TracerOptions::soft): more rays, an estimate nearer the truth at 0 ms.
  const fs::path more = temp_dir("soft_more");
  const CliRun m =
      run_small(more, " --frames 8 --rtt-ms 0 --method stale --soft-first-samples 32 --soft-samples 256", area);
  ASSERT_EQ(m.exit_code, 0) << m.output;
  const json more_row = read_results(more).at(0);
  EXPECT_GT(more_row["soft_rays_per_pair"].get<double>(), 4.0 * rows.at("stale@0")["soft_rays_per_pair"].get<double>());
  EXPECT_LT(more_row["visibility_error"].get<double>(), k("stale@0"));
  fs::remove_all(more);
  fs::remove_all(out);
}

// More than 32 lights (--lights 48 on the default room): they share light slots, the run offers them in the Hello,
// the truth is the exhaustive trace of the fields. At zero delay the server's methods are exact; `local` is the
// headset alone, which has no shadow maps for so many lights: every light unshadowed, exactly unshadowed_bit_error;
// at 100 ms the shipped default is far closer to the truth than that.
TEST(EvalCliManyLightsTest, LightSlotsAreEvaluatedAgainstTheUnshadowedHeadset) {
  const fs::path out = temp_dir("many_lights");
  const CliRun r = run_small(out, " --lights 48 --frames 6 --rtt-ms 0,100 --method paper,default,local");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("--method local is the headset without shadows"), std::string::npos) << r.output;
  std::ifstream run_file(out / "run.json");
  const json run = json::parse(run_file);
  EXPECT_TRUE(run["light_slots"].get<bool>());
  EXPECT_EQ(run["scene_lights"].get<int>(), 48);
  EXPECT_LT(run["lights"].get<int>(), 32);  // the fields: slots
  const double unshadowed = run["unshadowed_bit_error"].get<double>();
  EXPECT_GT(unshadowed, 0.0);  // the room's furniture shadows some lights somewhere
  const auto results = by_setting(read_results(out));
  ASSERT_EQ(results.size(), 6u);
  EXPECT_EQ(results.at("paper@0")["bit_error"].get<double>(), 0.0);
  EXPECT_EQ(results.at("default@0")["bit_error"].get<double>(), 0.0);
  for (const char* local : {"local@0", "local@100"})
    EXPECT_NEAR(results.at(local)["bit_error"].get<double>(), unshadowed, 1e-7) << local;
  EXPECT_LT(results.at("default@100")["bit_error"].get<double>(), unshadowed);
  EXPECT_LT(results.at("default@100")["flip"].get<double>(), results.at("local@100")["flip"].get<double>());
  // Refused with exit 2: bad counts and ranges, and a scene whose lights have an extent (the area room).
  const std::string area_scene = std::string(DHR_SOURCE_DIR) + "/assets/scenes/default_room_area.gltf";
  const std::vector<std::pair<std::string, std::string>> refusals{
      {kScene, "--lights 300"}, {kScene, "--lights 0"}, {kScene, "--lights 40 --light-range nan"},
      {kScene, "--lights 40 --light-range -1"}, {area_scene, "--lights 40"}};
  for (const auto& [scene, bad] : refusals) {
    const CliRun refused = run_cli("run --scene " + scene + " --trace " + kTrace + " --out " + out.string() +
                                   " --frames 2 --no-progress " + bad);
    EXPECT_EQ(refused.exit_code, 2) << scene << " " << bad << ": " << refused.output;
  }
  fs::remove_all(out);
}

TEST(EvalCliBadInputTest, RejectsBadInputWithOneLineErrors) {
  const fs::path out = temp_dir("bad");
  CliRun r = run_cli("run --scene /nonexistent.gltf --trace " + kTrace + " --out " + out.string() + " --no-progress");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("dhr-eval: "), std::string::npos) << r.output;
  r = run_cli("run --scene " + kScene + " --trace " + kTrace + " --out " + out.string() + " --rtt-ms 10,abc");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--rtt-ms"), std::string::npos) << r.output;
  r = run_cli("run --scene " + kScene + " --trace " + kTrace + " --out " + out.string() + " --method warp");
  EXPECT_EQ(r.exit_code, 2);
  for (const char* bad : {"full-no-warp", "full-no-depth-no-depth", "local-no-depth", "fullx",
                          "full-no-depth-depth-scale-2", "full-depth-scale-1", "full-depth-scale-", "full-depth-scale-99",
                          "full-edge-band-9", "full-edge-band-", "full-edge-band-12", "full-edge-band-1-depth-scale-2",
                          "local-edge-band-1", "full-no-depth-depth-splat", "full-depth-splat-depth-scale-2",
                          "full-depth-splat-depth-splat", "local-depth-splat", "full-no-soft-refin",
                          "full-no-soft-refine-no-soft-refine"}) {
    r = run_cli("run --scene " + kScene + " --trace " + kTrace + " --out " + out.string() + " --method " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.output.find("full-no-<ingredient>"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("motion, soft-refine)"), std::string::npos) << r.output;  // every ingredient named
  }
  r = run_cli("run --scene " + kScene + " --trace " + kTrace + " --out " + out.string() +
              " --frames 4 --eye-size 32x24 --rtt-ms 0 --method full --snapshot-frame 4 --no-progress");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--snapshot-frame 4: the run measures 4 frames"), std::string::npos) << r.output;
  for (const char* crop : {"--snapshot-frame 1 --snapshot-crop 30,20,8,8", "--snapshot-frame 1 --snapshot-crop 1,2,3",
                           "--snapshot-crop 0,0,8,8"}) {  // outside the 32x24 eye, malformed, no frame to crop
    r = run_cli("run --scene " + kScene + " --trace " + kTrace + " --out " + out.string() +
                " --frames 4 --eye-size 32x24 --rtt-ms 0 --method full --no-progress " + crop);
    EXPECT_EQ(r.exit_code, 2) << crop << "\n" << r.output;
  }
  r = run_cli("run --scene " + kScene + " --trace " + kTrace + " --out " + out.string() +
              " --frames 4 --eye-size 32x24 --rtt-ms 0 --no-progress --soft-first-samples 8 --soft-samples 4");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--soft-first-samples is above --soft-samples"), std::string::npos) << r.output;
  r = run_cli("run --scene " + kScene + " --trace " + kTrace + " --out " + out.string() + " --truth-samples 0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--truth-samples"), std::string::npos) << r.output;
  r = run_cli("run --scene " + kScene + " --trace " + kTrace + " --out " + out.string() + " --eye-size 0x0");
  EXPECT_EQ(r.exit_code, 2);
  r = run_cli("run --scene " + kScene + " --trace /nonexistent.csv --out " + out.string() + " --no-progress");
  EXPECT_EQ(r.exit_code, 2);  // an unusable input file (docs/exit-codes.md)
  r = run_cli("report /nonexistent-dir");
  EXPECT_EQ(r.exit_code, 2);
  // Usage errors of any subcommand exit with 2 (a missing option, a value out of range); --help with 0.
  r = run_cli("compare --shown " + out.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--scene is required"), std::string::npos) << r.output;
  r = run_cli("compare --scene " + kScene + " --shown " + out.string() + " --tolerance 300");
  EXPECT_EQ(r.exit_code, 2);
  r = run_cli("run --scene " + kScene + " --out " + out.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(run_cli("compare --help").exit_code, 0);
  fs::remove_all(out);
}

}  // namespace
