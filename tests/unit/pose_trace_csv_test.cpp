// The canonical dhr-trace CSV: round trips, and bad files (written to a temporary directory) rejected with
// the right line number.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <unistd.h>

#include "traces/pose_trace.hpp"

namespace {

namespace fs = std::filesystem;

class TraceFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / (std::string("dhr_pose_trace_") + info->name() + "_" +
                                        std::to_string(static_cast<long long>(::getpid())));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    const fs::path path = dir_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path.string();
  }

  // Reads `text` from a file and expects an error that names the file and line.
  void expect_rejected(const std::string& text, int line, const std::string& phrase,
                       dhr::TraceFormat format = dhr::TraceFormat::kAuto) {
    const std::string path = write("bad.csv", text);
    const dhr::TraceReadResult r = dhr::read_pose_trace(path, format);
    ASSERT_FALSE(r.ok()) << text;
    const std::string where = path + ":" + std::to_string(line) + ": ";
    EXPECT_EQ(r.error.rfind(where, 0), 0u) << "error: " << r.error << "\nexpected it to start with: " << where;
    EXPECT_NE(r.error.find(phrase), std::string::npos) << "error: " << r.error << "\nexpected: " << phrase;
  }

  fs::path dir_;
};

const std::string kHeader = "# dhr-trace v1\nt,x,y,z,qx,qy,qz,qw\n";
const std::string kRow = "0,0,1.6,0,0,0,0,1\n";

dhr::PoseTrace random_trace(bool eyes, bool fov, std::size_t rows) {
  std::mt19937_64 rng(1234);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  dhr::PoseTrace trace;
  trace.has_eye_poses = eyes;
  trace.has_fov = fov;
  trace.comments = {"a comment", "source: test"};
  double t = 12.5;
  auto random_pose = [&] {
    dhr::Pose p;
    p.position = {u(rng) * 10.0, u(rng) * 1e-7, u(rng) * 1e5};
    p.orientation = glm::normalize(glm::dquat(u(rng), u(rng), u(rng), u(rng)));
    return p;
  };
  for (std::size_t i = 0; i < rows; ++i) {
    dhr::TraceSample s;
    t += 0.011 * (u(rng) + 1.0);  // includes steps of (almost) zero
    s.time = t;
    s.head = random_pose();
    if (eyes) s.eye = {random_pose(), random_pose()};
    if (fov) {
      for (dhr::Fov& f : s.fov) {
        f.angle_left = static_cast<float>(-0.5 - 0.3 * std::fabs(u(rng)));
        f.angle_right = static_cast<float>(0.5 + 0.3 * std::fabs(u(rng)));
        f.angle_up = static_cast<float>(0.4 + 0.3 * std::fabs(u(rng)));
        f.angle_down = static_cast<float>(-0.6 - 0.3 * std::fabs(u(rng)));
      }
    }
    trace.samples.push_back(s);
  }
  return trace;
}

void expect_same_pose(const dhr::Pose& a, const dhr::Pose& b) {
  EXPECT_EQ(a.position.x, b.position.x);
  EXPECT_EQ(a.position.y, b.position.y);
  EXPECT_EQ(a.position.z, b.position.z);
  EXPECT_EQ(a.orientation.x, b.orientation.x);
  EXPECT_EQ(a.orientation.y, b.orientation.y);
  EXPECT_EQ(a.orientation.z, b.orientation.z);
  EXPECT_EQ(a.orientation.w, b.orientation.w);
}

// A fuzz finding: comments are written after the "# dhr-trace v1" line, so one that starts with the magic
// word must read back as a comment, not as a second (or unsupported) version line.
TEST_F(TraceFiles, CommentsStartingWithTheMagicWordReadBack) {
  dhr::PoseTrace trace = random_trace(false, false, 3);
  trace.comments = {"dhr-trace v2", "dhr-trace", "dhr-trace v1 copied from another file"};
  const std::string path = (dir_ / "trace.csv").string();
  std::string error;
  ASSERT_TRUE(dhr::write_pose_trace(path, trace, &error)) << error;
  const dhr::TraceReadResult r = dhr::read_pose_trace(path);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.trace->comments, trace.comments);
  EXPECT_EQ(r.trace->samples.size(), 3u);

  // Only the first line names the version; a later one is free text.
  const std::string text = "# provenance\n# dhr-trace v2\nt,x,y,z,qx,qy,qz,qw\n" + kRow;
  const dhr::TraceReadResult later = dhr::read_pose_trace(write("later.csv", text));
  ASSERT_TRUE(later.ok()) << later.error;
  EXPECT_EQ(later.trace->comments, (std::vector<std::string>{"provenance", "dhr-trace v2"}));
}

TEST_F(TraceFiles, RoundTripIsExactForEveryLayout) {
  for (bool eyes : {false, true}) {
    for (bool fov : {false, true}) {
      SCOPED_TRACE(testing::Message() << "eyes " << eyes << " fov " << fov);
      const dhr::PoseTrace trace = random_trace(eyes, fov, 200);
      const std::string path = (dir_ / "trace.csv").string();
      std::string error;
      ASSERT_TRUE(dhr::write_pose_trace(path, trace, &error)) << error;
      const dhr::TraceReadResult r = dhr::read_pose_trace(path);
      ASSERT_TRUE(r.ok()) << r.error;
      EXPECT_EQ(r.format, dhr::TraceFormat::kCanonical);
      const dhr::PoseTrace& back = *r.trace;
      EXPECT_EQ(back.has_eye_poses, eyes);
      EXPECT_EQ(back.has_fov, fov);
      EXPECT_EQ(back.comments, trace.comments);
      EXPECT_TRUE(back.warnings.empty());
      ASSERT_EQ(back.samples.size(), trace.samples.size());
      for (std::size_t i = 0; i < trace.samples.size(); ++i) {
        const dhr::TraceSample& a = trace.samples[i];
        const dhr::TraceSample& b = back.samples[i];
        ASSERT_EQ(a.time, b.time) << i;
        expect_same_pose(a.head, b.head);
        if (eyes) {
          expect_same_pose(a.eye[0], b.eye[0]);
          expect_same_pose(a.eye[1], b.eye[1]);
        }
        if (fov) {
          for (int e = 0; e < 2; ++e) {
            EXPECT_EQ(a.fov[e].angle_left, b.fov[e].angle_left);
            EXPECT_EQ(a.fov[e].angle_right, b.fov[e].angle_right);
            EXPECT_EQ(a.fov[e].angle_up, b.fov[e].angle_up);
            EXPECT_EQ(a.fov[e].angle_down, b.fov[e].angle_down);
          }
        }
      }
      // Writing what was read gives the same bytes.
      EXPECT_EQ(dhr::format_canonical_trace(back), dhr::format_canonical_trace(trace));
    }
  }
}

TEST_F(TraceFiles, StreamingWriterMatchesTheBatchWriter) {
  const dhr::PoseTrace trace = random_trace(true, true, 50);
  const std::string path = (dir_ / "rec.csv").string();
  dhr::PoseTraceWriter writer;
  std::string error;
  ASSERT_TRUE(writer.open(path, true, true, trace.comments, &error)) << error;
  for (const dhr::TraceSample& s : trace.samples) ASSERT_TRUE(writer.append(s, &error)) << error;
  dhr::TraceSample backwards = trace.samples.back();
  backwards.time -= 1.0;
  EXPECT_FALSE(writer.append(backwards, &error));
  EXPECT_NE(error.find("time goes backwards"), std::string::npos) << error;
  dhr::TraceSample zero = trace.samples.back();
  zero.head.orientation = glm::dquat(0.0, 0.0, 0.0, 0.0);
  EXPECT_FALSE(writer.append(zero, &error));
  EXPECT_NE(error.find("zero quaternion"), std::string::npos) << error;
  EXPECT_EQ(writer.rows(), trace.samples.size());
  ASSERT_TRUE(writer.close(&error)) << error;
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, dhr::format_canonical_trace(trace));
}

TEST_F(TraceFiles, AcceptsCommentsBlankLinesCrLfAndSpaces) {
  const std::string text =
      "# dhr-trace v1\r\n# recorded on a test\r\n\r\nt, x, y, z, qx, qy, qz, qw\r\n0, 0, 1.6, 0, 0, 0, 0, 1\r\n"
      "# a note between rows\r\n\r\n0.5,+1,1.6,-2e-3,0,0.7071067811865476,0,0.7071067811865476\r\n";
  const dhr::TraceReadResult r = dhr::read_pose_trace(write("ok.csv", text));
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.trace->samples.size(), 2u);
  EXPECT_EQ(r.trace->samples[1].head.position.x, 1.0);
  EXPECT_EQ(r.trace->samples[1].head.position.z, -2e-3);
  EXPECT_EQ(r.trace->comments.size(), 2u);
}

TEST_F(TraceFiles, RenormalizesQuaternions) {
  const dhr::TraceReadResult r = dhr::read_pose_trace(write("q.csv", kHeader + "0,0,0,0,0,0,0,1.5\n"));
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_DOUBLE_EQ(r.trace->samples[0].head.orientation.w, 1.0);
  ASSERT_EQ(r.trace->warnings.size(), 1u);
  EXPECT_NE(r.trace->warnings[0].find("renormalized"), std::string::npos);
}

TEST_F(TraceFiles, RejectsBadRowsWithFileAndLine) {
  expect_rejected(kHeader + kRow + "0.1,0,1.6,0,0,0,0\n" + kRow, 4, "expected 8 columns, got 7");
  expect_rejected(kHeader + kRow + "0.1,0,1.6,0,0,0,0,1,5\n", 4, "expected 8 columns, got 9");
  expect_rejected(kHeader + kRow + "0.1,0,abc,0,0,0,0,1\n", 4, "column 3 (y): 'abc' is not a number");
  expect_rejected(kHeader + kRow + "0.1,0,1.6 m,0,0,0,0,1\n", 4, "column 3 (y): '1.6 m' is not a number");
  expect_rejected(kHeader + kRow + "0.1,0,,0,0,0,0,1\n", 4, "column 3 (y): empty value");
  expect_rejected(kHeader + kRow + "0.1,inf,0,0,0,0,0,1\n", 4, "column 2 (x): non-finite value 'inf'");
  expect_rejected(kHeader + kRow + "0.1,0,0,0,0,0,0,nan\n", 4, "column 8 (qw): non-finite value 'nan'");
  expect_rejected(kHeader + kRow + "0.1,0,0,1e999,0,0,0,1\n", 4, "column 4 (z): '1e999' is out of range");
  expect_rejected(kHeader + kRow + "0.1,0,0,0,0,0,0,0\n", 4, "zero quaternion");
  expect_rejected(kHeader + kRow + "0.1,0,0,0,0,0,0,0.3\n", 4, "quaternion norm 0.3 is too far from 1");
  expect_rejected(kHeader + kRow + "0.1,0,0,0,2,2,0,1\n", 4, "quaternion norm 3 is too far from 1");
  expect_rejected(kHeader + kRow + "0.1,2e6,0,0,0,0,0,1\n", 4, "position is 2e+06 m from the origin");
  expect_rejected(kHeader + "1,0,0,0,0,0,0,1\n\n0.5,0,0,0,0,0,0,1\n", 5, "time goes backwards (0.5 s after 1 s");
  expect_rejected(kHeader + kRow + "0.1," + std::string(5000, '1') + ",0,0,0,0,0,1\n", 4, "longer than 4096");
  // A cut-short row in the middle is an error even when the file ends with one too.
  expect_rejected(kHeader + kRow + "0.1,0,1.6,0,0,0\n0.2,0,1.6,0,0", 4, "expected 8 columns, got 6");
}

TEST_F(TraceFiles, RejectsBadHeaders) {
  expect_rejected("# dhr-trace v2\nt,x,y,z,qx,qy,qz,qw\n" + kRow, 1, "unsupported trace version 'v2'");
  expect_rejected("# dhr-trace v1\nt,x,y,z,qw,qx,qy,qz\n" + kRow, 2, "not a dhr-trace column header");
  expect_rejected("# dhr-trace v1\nt,x,y,z,qx,qy,qz,qw,lx\n" + kRow, 2, "not a dhr-trace column header");
  const dhr::TraceReadResult empty = dhr::read_pose_trace(write("empty.csv", "# dhr-trace v1\n"));
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.error.find("no column header"), std::string::npos) << empty.error;
  const dhr::TraceReadResult no_rows = dhr::read_pose_trace(write("norows.csv", kHeader));
  ASSERT_FALSE(no_rows.ok());
  EXPECT_NE(no_rows.error.find("no data rows"), std::string::npos) << no_rows.error;
  const dhr::TraceReadResult binary = dhr::read_pose_trace(write("bin.csv", std::string("\x89PNG\r\n\x1a\n\0\0", 10)));
  ASSERT_FALSE(binary.ok());
  EXPECT_NE(binary.error.find("cannot tell the trace format"), std::string::npos) << binary.error;
}

TEST_F(TraceFiles, PerEyeColumnsAreValidated) {
  const std::string header = "t,x,y,z,qx,qy,qz,qw,lfov_left,lfov_right,lfov_up,lfov_down,"
                             "rfov_left,rfov_right,rfov_up,rfov_down\n";
  const dhr::TraceReadResult ok =
      dhr::read_pose_trace(write("fov.csv", header + "0,0,0,0,0,0,0,1,-0.8,0.7,0.75,-0.85,-0.7,0.8,0.75,-0.85\n"));
  ASSERT_TRUE(ok.ok()) << ok.error;
  EXPECT_TRUE(ok.trace->has_fov);
  EXPECT_FALSE(ok.trace->has_eye_poses);
  EXPECT_FLOAT_EQ(ok.trace->samples[0].fov[1].angle_right, 0.8f);
  expect_rejected(header + "0,0,0,0,0,0,0,1,-0.8,0.7,0.75,-0.85,0.9,0.8,0.75,-0.85\n", 2,
                  "right eye: field of view: angle_left must be < angle_right");
  const std::string eyes = "t,x,y,z,qx,qy,qz,qw,lx,ly,lz,lqx,lqy,lqz,lqw,rx,ry,rz,rqx,rqy,rqz,rqw\n";
  expect_rejected(eyes + "0,0,0,0,0,0,0,1,-0.03,0,0,0,0,0,1,0.03,0,0,0,0,0,0\n", 2, "right eye orientation is a zero");
}

TEST_F(TraceFiles, UnterminatedLastLineThatIsIncompleteIsDroppedWithAWarning) {
  // Cut inside a number: qw = 0.9 of 0.99..., the row still parses.
  const dhr::TraceReadResult a = dhr::read_pose_trace(write("a.csv", kHeader + kRow + "0.1,0,1.6,0,0.04,0.04,0.01,0.9"));
  ASSERT_TRUE(a.ok()) << a.error;
  EXPECT_EQ(a.trace->samples.size(), 1u);
  ASSERT_EQ(a.trace->warnings.size(), 1u);
  EXPECT_NE(a.trace->warnings[0].find("a.csv:4: the last line has no line end and is incomplete"), std::string::npos)
      << a.trace->warnings[0];
  // Cut between columns.
  const dhr::TraceReadResult b = dhr::read_pose_trace(write("b.csv", kHeader + kRow + "0.1,0,1.6"));
  ASSERT_TRUE(b.ok()) << b.error;
  EXPECT_EQ(b.trace->samples.size(), 1u);
  EXPECT_NE(b.trace->warnings.at(0).find("expected 8 columns, got 3"), std::string::npos);
  // A complete last line without a line end is kept.
  const dhr::TraceReadResult c = dhr::read_pose_trace(write("c.csv", kHeader + kRow + "0.1,0,1.6,0,0,0,0,1"));
  ASSERT_TRUE(c.ok()) << c.error;
  EXPECT_EQ(c.trace->samples.size(), 2u);
  EXPECT_TRUE(c.trace->warnings.empty());
}

TEST_F(TraceFiles, LimitsAreEnforced) {
  std::string text = kHeader;
  for (int i = 0; i < 20; ++i) text += std::to_string(i) + ",0,0,0,0,0,0,1\n";
  const std::string path = write("big.csv", text);
  dhr::TraceReadOptions rows;
  rows.max_rows = 10;
  const dhr::TraceReadResult r1 = dhr::read_pose_trace(path, dhr::TraceFormat::kCanonical, rows);
  ASSERT_FALSE(r1.ok());
  EXPECT_NE(r1.error.find("big.csv:13: more than 10 data rows"), std::string::npos) << r1.error;
  dhr::TraceReadOptions bytes;
  bytes.max_file_bytes = 100;
  const dhr::TraceReadResult r2 = dhr::read_pose_trace(path, dhr::TraceFormat::kCanonical, bytes);
  ASSERT_FALSE(r2.ok());
  EXPECT_NE(r2.error.find("bytes is more than the reader's limit of 100 bytes"), std::string::npos) << r2.error;
  const dhr::TraceReadResult missing = dhr::read_pose_trace((dir_ / "missing.csv").string());
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error.find("missing.csv: no such file"), std::string::npos) << missing.error;
  const dhr::TraceReadResult directory = dhr::read_pose_trace(dir_.string());
  ASSERT_FALSE(directory.ok());
  EXPECT_NE(directory.error.find("not a regular file"), std::string::npos) << directory.error;
}

// Seeded random damage to valid files of each format: every result is a trace or an error that names the
// file (never a crash, which the sanitizer builds would catch).
TEST(TraceRobustness, RandomlyDamagedFilesGiveTracesOrErrors) {
  const std::string inputs[] = {
      dhr::format_canonical_trace(random_trace(true, true, 6)),
      "timestamp,x,y,z,qx,qy,qz,qw\n637139238387771648, 0.1, 0.07, 0.08, 0, 0, 0, 1\n"
      "637139238387781648, 0.2, 0.07, -0.5, 0, 0.7071067811865476, 0, 0.7071067811865476\n",
      "0,0.076362,-0.0043327,-0.034734,0.99647,-0.01394,0.15188,0.9883\n"
      "0.018,0.077247,-0.0054199,-0.036663,0.99632,-0.016464,0.15353,0.98801\n"};
  std::mt19937 rng(99);
  const char alphabet[] = "0123456789.,-+eE#\n\r tinaxq";
  for (const std::string& input : inputs) {
    for (int round = 0; round < 1500; ++round) {
      std::string text = input;
      const int edits = 1 + static_cast<int>(rng() % 4);
      for (int e = 0; e < edits && !text.empty(); ++e) {
        const std::size_t at = rng() % text.size();
        switch (rng() % 3) {
          case 0: text[at] = alphabet[rng() % (sizeof alphabet - 1)]; break;
          case 1: text.erase(at, 1 + rng() % 8); break;
          default: text.resize(at); break;
        }
      }
      const dhr::TraceReadResult r = dhr::parse_pose_trace(text, "fuzz.csv");
      if (r.ok()) {
        ASSERT_FALSE(r.trace->empty());
        for (const dhr::TraceSample& s : r.trace->samples) ASSERT_FALSE(dhr::validate_pose(s.head).has_value());
      } else {
        ASSERT_EQ(r.error.rfind("fuzz.csv:", 0), 0u) << r.error;
      }
    }
  }
}

TEST(TraceFormatNames, RoundTrip) {
  for (dhr::TraceFormat f : {dhr::TraceFormat::kAuto, dhr::TraceFormat::kCanonical, dhr::TraceFormat::kGul2020Raw,
                             dhr::TraceFormat::kGul2020Interp, dhr::TraceFormat::kNasrabadi2019}) {
    EXPECT_EQ(dhr::parse_trace_format(dhr::trace_format_name(f)), f);
  }
  EXPECT_FALSE(dhr::parse_trace_format("hololens").has_value());
}

}  // namespace
