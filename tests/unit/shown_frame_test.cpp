// views.jsonl lines (traces/shown_frame.hpp): a written line reads back to the same bits; malformed lines are
// rejected with the reason; a file's bad line is named by number. Also the PNG reader the comparison uses.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <unistd.h>

#include "image/png_reader.hpp"
#include "image/png_writer.hpp"
#include "traces/shown_frame.hpp"

namespace {

namespace fs = std::filesystem;
using dhr::ShownFrame;

ShownFrame sample_frame() {
  ShownFrame f;
  f.frame = 200;
  f.eye_size = {160, 120};
  f.traced = dhr::TracedFormat{f.eye_size, dhr::GuardBand{5, 4}};
  f.scene_hash = 0xfedcba9876543210ull;
  f.render_path = "forward";
  f.warp = "paper";
  f.view = "shaded";
  f.scene_time_ns = 2'345'678'901;
  for (int e = 0; e < 2; ++e) {
    dhr::ShownEye& eye = f.eyes[e];
    eye.view.pose.position = {0.1 + 0.063 * e, 1.6000000000000003, -2.0 / 3.0};
    eye.view.pose.orientation = glm::normalize(glm::dquat(0.9, 0.1, -0.3 + 0.01 * e, 0.05));
    eye.view.fov = dhr::Fov{-0.742f, 0.7f, 0.779f, -0.77f};
    eye.file = e == 0 ? "frame_000200_left.png" : "frame_000200_right.png";
    eye.has_visibility = true;
    eye.visibility_frame = 197;
    eye.age = 3;
    eye.complete = e == 0;
  }
  return f;
}

TEST(ShownFrame, RoundTripKeepsEveryBit) {
  const ShownFrame f = sample_frame();
  const std::string line = dhr::shown_frame_json(f);
  EXPECT_EQ(line.find('\n'), std::string::npos);
  std::string error;
  const auto back = dhr::parse_shown_frame(line, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->frame, f.frame);
  EXPECT_EQ(back->eye_size, f.eye_size);
  ASSERT_TRUE(back->traced);
  EXPECT_EQ(*back->traced, *f.traced);
  EXPECT_EQ(back->scene_hash, f.scene_hash);
  EXPECT_NE(line.find("\"scene_hash\":\"fedcba9876543210\""), std::string::npos) << line;
  EXPECT_EQ(back->render_path, "forward");
  EXPECT_EQ(back->warp, "paper");
  EXPECT_EQ(back->view, "shaded");
  EXPECT_EQ(back->scene_time_ns, f.scene_time_ns);
  for (int e = 0; e < 2; ++e) {
    const dhr::ShownEye& a = f.eyes[e];
    const dhr::ShownEye& b = back->eyes[e];
    EXPECT_EQ(b.view.pose.position, a.view.pose.position);  // bit for bit
    EXPECT_EQ(b.view.pose.orientation, a.view.pose.orientation);
    EXPECT_EQ(b.view.fov.angle_left, a.view.fov.angle_left);
    EXPECT_EQ(b.view.fov.angle_down, a.view.fov.angle_down);
    EXPECT_EQ(b.file, a.file);
    EXPECT_EQ(b.has_visibility, a.has_visibility);
    EXPECT_EQ(b.visibility_frame, a.visibility_frame);
    EXPECT_EQ(b.age, a.age);
    EXPECT_EQ(b.complete, a.complete);
  }
}

TEST(ShownFrame, WithoutASessionTheGuardIsNull) {
  ShownFrame f = sample_frame();
  f.traced.reset();
  f.scene_hash.reset();
  const std::string line = dhr::shown_frame_json(f);
  EXPECT_NE(line.find("\"guard_per_side\":null"), std::string::npos) << line;
  EXPECT_NE(line.find("\"scene_hash\":null"), std::string::npos) << line;
  const auto back = dhr::parse_shown_frame(line, nullptr);
  ASSERT_TRUE(back);
  EXPECT_FALSE(back->traced);
  EXPECT_FALSE(back->scene_hash);
}

// Replaces the first occurrence of `from` in a good line.
std::string edited(const std::string& from, const std::string& to) {
  std::string line = dhr::shown_frame_json(sample_frame());
  const size_t at = line.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) line.replace(at, from.size(), to);
  return line;
}

void expect_rejected(const std::string& line, const std::string& phrase) {
  std::string error;
  EXPECT_FALSE(dhr::parse_shown_frame(line, &error)) << line;
  EXPECT_NE(error.find(phrase), std::string::npos) << "error: " << error << "\nline: " << line;
}

TEST(ShownFrame, EveryWarpTheClientWritesIsRead) {
  for (const char* warp : {"paper", "full", "edges", "edges-depth"}) {
    std::string error;
    const auto f = dhr::parse_shown_frame(edited("\"warp\":\"paper\"", std::string("\"warp\":\"") + warp + "\""), &error);
    ASSERT_TRUE(f.has_value()) << warp << ": " << error;
    EXPECT_EQ(f->warp, warp);
  }
}

TEST(ShownFrame, MalformedLinesAreRejectedWithTheReason) {
  expect_rejected("", "not valid JSON");
  expect_rejected("{\"frame\": 1", "not valid JSON");
  expect_rejected("[1, 2]", "frame: not an object");
  expect_rejected(edited("\"frame\":200", "\"frame\":-1"), "\"frame\" is not a non-negative integer");
  expect_rejected(edited("\"frame\":200", "\"frame\":\"200\""), "\"frame\" is not a non-negative integer");
  expect_rejected(edited("\"eye_size\":[160,120]", "\"eye_size\":[0,120]"), "\"eye_size\" is not [width, height]");
  expect_rejected(edited("\"eye_size\":[160,120]", "\"eye_size\":[99999,120]"), "\"eye_size\"");
  expect_rejected(edited("\"render_path\":\"forward\"", "\"render_path\":\"magic\""), "unknown \"render_path\"");
  expect_rejected(edited("\"warp\":\"paper\"", "\"warp\":\"none\""), "unknown \"warp\"");
  expect_rejected(edited("\"guard_per_side\":[5,4]", "\"guard_per_side\":[5]"), "\"guard_per_side\"");
  expect_rejected(edited("\"guard_per_side\":[5,4]", "\"guard_per_side\":[5000,4]"), "larger than 4096");
  expect_rejected(edited("\"eyes\":[", "\"eyes\":[{},"), "\"eyes\" is not an array of two eyes");
  expect_rejected(edited("\"fedcba9876543210\"", "\"fedcba98765432100\""), "\"scene_hash\" is not null or 1-16 hex");
  expect_rejected(edited("\"fedcba9876543210\"", "\"0x12\""), "\"scene_hash\"");
  expect_rejected(edited("\"fedcba9876543210\"", "12"), "\"scene_hash\"");
  expect_rejected(edited("\"fedcba9876543210\"", "\"\""), "\"scene_hash\"");
  expect_rejected(edited("\"position\":[0.1,", "\"position\":[\"x\","), "not a finite number");
  expect_rejected(edited("\"position\":[", "\"position\":[1e999,"), "not valid JSON");  // out of double's range
  expect_rejected(edited("\"orientation\":[", "\"orientation\":[0,0,0,0,"), "\"orientation\" is not an array of 4");
  expect_rejected(edited("\"file\":\"frame_000200_left.png\"", "\"file\":\"../secret.png\""), "plain file name");
  expect_rejected(edited("\"file\":\"frame_000200_left.png\"", "\"file\":\"/etc/passwd\""), "plain file name");
  expect_rejected(edited("\"file\":\"frame_000200_left.png\"", "\"file\":\"\""), "plain file name");
  expect_rejected(edited("\"age\":3", "\"age\":true"), "\"age\" is not a non-negative integer");
  expect_rejected(edited("\"complete\":true", "\"complete\":1"), "\"complete\" is not true or false");
  expect_rejected(edited(",\"visibility_frame\":197", ""), "left eye: no \"visibility_frame\"");
  expect_rejected(edited("\"scene_time_ns\":2345678901", "\"scene_time_ns\":-1"), "\"scene_time_ns\"");
  expect_rejected(edited("\"scene_time_ns\":2345678901", "\"scene_time_ns\":0.5"), "\"scene_time_ns\"");
}

TEST(ShownFrame, ALineWithoutASceneTimeShowsTheRestPose) {
  const auto f = dhr::parse_shown_frame(edited(",\"scene_time_ns\":2345678901", ""), nullptr);
  ASSERT_TRUE(f);
  EXPECT_EQ(f->scene_time_ns, 0);
}

TEST(ShownFrame, UnusableViewsAreRejected) {
  // A zero quaternion and a field of view that is not one (left >= right).
  std::string line = dhr::shown_frame_json(sample_frame());
  const size_t q = line.find("\"orientation\":[");
  const size_t q_end = line.find(']', q);
  std::string zero = line;
  zero.replace(q, q_end - q + 1, "\"orientation\":[0,0,0,0]");
  expect_rejected(zero, "left eye:");
  const size_t f = line.find("\"fov\":[");
  const size_t f_end = line.find(']', f);
  std::string flipped = line;
  flipped.replace(f, f_end - f + 1, "\"fov\":[0.7,-0.7,0.7,-0.7]");
  expect_rejected(flipped, "left eye:");
}

class ShownFrameFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           (std::string("dhr_shown_frame_") + info->name() + "_" + std::to_string(static_cast<long long>(::getpid())));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(ShownFrameFiles, AFileIsReadLineByLineAndABadLineIsNamed) {
  const std::string good = dhr::shown_frame_json(sample_frame());
  const std::string path = (dir_ / "views.jsonl").string();
  std::ofstream(path) << good << "\n\n" << good << "\n";
  std::string error;
  const auto frames = dhr::read_shown_frames(path, &error);
  ASSERT_TRUE(frames) << error;
  EXPECT_EQ(frames->size(), 2u);

  std::ofstream(path) << good << "\n{\"frame\": 3}\n";
  EXPECT_FALSE(dhr::read_shown_frames(path, &error));
  EXPECT_NE(error.find("views.jsonl:2: frame: no \"eye_size\""), std::string::npos) << error;

  EXPECT_FALSE(dhr::read_shown_frames((dir_ / "missing.jsonl").string(), &error));
  EXPECT_NE(error.find("cannot open"), std::string::npos) << error;
}

TEST_F(ShownFrameFiles, PngReaderReadsWhatTheWriterWrote) {
  const uint32_t w = 7, h = 5;
  std::vector<uint8_t> rgb(w * h * 3), grey(w * h);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<uint8_t>(i * 37 % 256);
  for (size_t i = 0; i < grey.size(); ++i) grey[i] = static_cast<uint8_t>(i * 11);
  const std::string colour = (dir_ / "c.png").string(), mono = (dir_ / "g.png").string();
  ASSERT_FALSE(dhr::write_png(colour, w, h, 3, rgb));
  ASSERT_FALSE(dhr::write_png(mono, w, h, 1, grey));
  std::string error;
  const auto c = dhr::read_png_rgb(colour, &error);
  ASSERT_TRUE(c) << error;
  EXPECT_EQ(c->width, w);
  EXPECT_EQ(c->height, h);
  EXPECT_EQ(c->rgb, rgb);
  const auto g = dhr::read_png_rgb(mono, &error);
  ASSERT_TRUE(g) << error;
  ASSERT_EQ(g->rgb.size(), rgb.size());
  for (size_t i = 0; i < grey.size(); ++i) {
    EXPECT_EQ(g->rgb[i * 3], grey[i]);
    EXPECT_EQ(g->rgb[i * 3 + 2], grey[i]);
  }
  // Too many pixels, not a PNG, a truncated PNG, no file: a reason each.
  EXPECT_FALSE(dhr::read_png_rgb(colour, &error, 34));
  EXPECT_NE(error.find("unsupported size 7x5"), std::string::npos) << error;
  const std::string text = (dir_ / "t.png").string();
  std::ofstream(text) << "not a png at all";
  EXPECT_FALSE(dhr::read_png_rgb(text, &error));
  EXPECT_NE(error.find("not a PNG"), std::string::npos) << error;
  const auto size = fs::file_size(colour);
  fs::copy_file(colour, dir_ / "cut.png");
  fs::resize_file(dir_ / "cut.png", size / 2);
  EXPECT_FALSE(dhr::read_png_rgb((dir_ / "cut.png").string(), &error));
  EXPECT_FALSE(dhr::read_png_rgb((dir_ / "none.png").string(), &error));
  EXPECT_NE(error.find("cannot open"), std::string::npos) << error;
}

}  // namespace
