// VisibilityClient receive side: newest wins per eye, partial frames with row_valid, late and duplicate
// shards, and bad datagrams of every kind counted and dropped with bounded memory.
#include "client_harness.hpp"

#include <random>

namespace dhr::client::test {
namespace {

// Which rows the given shards cover completely: what row_valid must say after receiving just those.
std::vector<uint8_t> rows_covered_fully(const std::vector<VisibilityShard>& shards, const std::vector<size_t>& sent) {
  std::vector<uint32_t> pixels(kBufH, 0);
  for (const size_t i : sent) {
    const VisibilityShard& s = shards[i];
    for (uint32_t p = s.first_pixel; p < s.first_pixel + s.pixel_count; ++p) ++pixels[p / kBufW];
  }
  std::vector<uint8_t> rows(kBufH, 0);
  for (uint32_t y = 0; y < kBufH; ++y) rows[y] = pixels[y] == kBufW ? 1 : 0;
  return rows;
}

void expect_rows_equal(const VisibilityFrame& v, const VisibilityBuffer& expected) {
  ASSERT_EQ(v.buffer.width, expected.width);
  ASSERT_EQ(v.buffer.height, expected.height);
  for (uint32_t y = 0; y < expected.height; ++y) {
    if (!v.row_valid[y]) continue;
    for (uint32_t x = 0; x < expected.width; ++x) ASSERT_EQ(v.buffer.get(x, y), expected.get(x, y)) << x << "," << y;
  }
}

TEST(ClientReceive, CompleteFrameIsPublishedWithItsViewAndExactContent) {
  Harness h;
  h.connect();
  ASSERT_TRUE(h.client.send_pose(FramePose{1, 0, views_for(1)}));
  const int64_t sent = h.clock.now_ns();  // the links have no delay: delivered at the send time
  h.send_frame(1, Eye::kLeft);
  h.run_for(kMs);
  VisibilityFrame v;
  ASSERT_TRUE(h.client.take_newest(Eye::kLeft, v));
  EXPECT_EQ(v.frame_number, 1u);
  EXPECT_TRUE(v.complete);
  EXPECT_EQ(v.rows_valid, kBufH);
  EXPECT_EQ(v.buffer, buffer_for(1, Eye::kLeft));
  EXPECT_EQ(v.view.pose.position, view_for(1, Eye::kLeft).pose.position);
  EXPECT_EQ(v.scene_time_ns, scene_time_for(1));
  EXPECT_EQ(v.received_ns, sent);
  EXPECT_FALSE(h.client.take_newest(Eye::kLeft, v));  // nothing newer
  EXPECT_FALSE(h.client.take_newest(Eye::kRight, v));
}

// Every shard of a frame names the scene time it was traced for: one that names another is rejected (inconsistent
// frame) and counted, and the frame still completes from the others at the first shard's scene time.
TEST(ClientReceive, AShardAtAnotherSceneTimeThanItsFrameIsRejected) {
  Harness h;
  h.connect();
  ASSERT_TRUE(h.client.send_pose(FramePose{1, 0, views_for(1)}));
  const std::vector<VisibilityShard> shards = shards_for(1, Eye::kLeft);
  ASSERT_GE(shards.size(), 2u);
  h.send_shard(shards[0]);
  VisibilityShard odd = shards[1];
  odd.scene_time_ns += 1;
  h.send_shard(odd);
  h.run_for(kMs);
  EXPECT_EQ(h.client.stats().shards_rejected, 1u);
  EXPECT_EQ(h.client.stats().rejections[DecodeError::kInconsistentFrame], 1u);
  for (size_t i = 1; i < shards.size(); ++i) h.send_shard(shards[i]);
  h.run_for(kMs);
  VisibilityFrame v;
  ASSERT_TRUE(h.client.take_newest(Eye::kLeft, v));
  EXPECT_TRUE(v.complete);
  EXPECT_EQ(v.scene_time_ns, scene_time_for(1));
}

TEST(ClientReceive, NewestWinsPerEyeAndFrameNumbersNeverGoBack) {
  Harness h;
  h.connect();
  for (uint64_t f = 1; f <= 4; ++f) ASSERT_TRUE(h.client.send_pose(FramePose{f, 0, views_for(f)}));
  ASSERT_GT(shards_for(2, Eye::kLeft).size(), 2u);
  h.send_frame(2, Eye::kLeft);
  h.send_frame(3, Eye::kLeft);
  h.send_frame(1, Eye::kRight);
  h.send_frame(1, Eye::kLeft);  // older than the newest complete left frame: late
  h.run_for(kMs);
  VisibilityFrame left, right;
  ASSERT_TRUE(h.client.take_newest(Eye::kLeft, left));
  EXPECT_EQ(left.frame_number, 3u);
  EXPECT_EQ(left.buffer, buffer_for(3, Eye::kLeft));
  ASSERT_TRUE(h.client.take_newest(Eye::kRight, right));
  EXPECT_EQ(right.frame_number, 1u);
  EXPECT_EQ(right.buffer, buffer_for(1, Eye::kRight));

  h.send_frame(2, Eye::kLeft);  // late again
  h.send_frame(4, Eye::kRight);
  h.run_for(kMs);
  EXPECT_FALSE(h.client.take_newest(Eye::kLeft, left));
  ASSERT_TRUE(h.client.take_newest(Eye::kRight, right));
  EXPECT_EQ(right.frame_number, 4u);
  const ClientNetStats s = h.client.stats();
  EXPECT_EQ(s.shards_late, shards_for(1, Eye::kLeft).size() + shards_for(2, Eye::kLeft).size());
  EXPECT_EQ(s.frames_completed, 4u);
  EXPECT_EQ(s.frames_published_complete, 4u);
  EXPECT_EQ(s.frames_overwritten, 1u);  // left 2, replaced by left 3 before it was taken
  EXPECT_EQ(s.frames_taken, 3u);
  EXPECT_EQ(s.newest_frame_complete[0], 3u);
  EXPECT_EQ(s.newest_frame_complete[1], 4u);
}

TEST(ClientReceive, IncompleteFrameIsPublishedWhenItGoesQuietWithRowValid) {
  Harness h;
  h.connect();
  ASSERT_TRUE(h.client.send_pose(FramePose{1, 0, views_for(1)}));
  const auto shards = shards_for(1, Eye::kLeft);
  ASSERT_GE(shards.size(), 4u);
  std::vector<size_t> sent;
  for (size_t i = 0; i < shards.size(); ++i)
    if (i != 1) sent.push_back(i);
  for (const size_t i : sent) h.send_shard(shards[i]);
  h.run_for(5 * kMs);
  VisibilityFrame v;
  EXPECT_FALSE(h.client.take_newest(Eye::kLeft, v));  // not quiet long enough yet (20 ms)
  h.run_for(20 * kMs);
  ASSERT_TRUE(h.client.take_newest(Eye::kLeft, v));
  EXPECT_EQ(v.frame_number, 1u);
  EXPECT_FALSE(v.complete);
  EXPECT_EQ(v.row_valid, rows_covered_fully(shards, sent));
  EXPECT_LT(v.rows_valid, kBufH);
  EXPECT_GT(v.rows_valid, 0u);
  expect_rows_equal(v, buffer_for(1, Eye::kLeft));
  h.run_for(50 * kMs);
  EXPECT_FALSE(h.client.take_newest(Eye::kLeft, v));  // nothing more arrived: not published again

  // The missing shard arrives after all: the frame is published again, complete.
  h.send_shard(shards[1]);
  h.run_for(kMs);
  ASSERT_TRUE(h.client.take_newest(Eye::kLeft, v));
  EXPECT_EQ(v.frame_number, 1u);
  EXPECT_TRUE(v.complete);
  EXPECT_EQ(v.buffer, buffer_for(1, Eye::kLeft));
  const ClientNetStats s = h.client.stats();
  EXPECT_EQ(s.frames_published_partial, 1u);
  EXPECT_EQ(s.frames_published_complete, 1u);
}

TEST(ClientReceive, IncompleteFrameIsPublishedWhenANewerFrameStarts) {
  Harness h;
  h.connect();
  for (uint64_t f = 1; f <= 2; ++f) ASSERT_TRUE(h.client.send_pose(FramePose{f, 0, views_for(f)}));
  const auto first = shards_for(1, Eye::kRight);
  const auto second = shards_for(2, Eye::kRight);
  std::vector<size_t> sent;
  for (size_t i = 0; i + 1 < first.size(); ++i) sent.push_back(i);  // the last shard is lost
  for (const size_t i : sent) h.send_shard(first[i]);
  h.send_shard(second[0]);  // no quiet time in between
  h.run_for(kMs);
  VisibilityFrame v;
  ASSERT_TRUE(h.client.take_newest(Eye::kRight, v));
  EXPECT_EQ(v.frame_number, 1u);
  EXPECT_FALSE(v.complete);
  EXPECT_EQ(v.row_valid, rows_covered_fully(first, sent));
  expect_rows_equal(v, buffer_for(1, Eye::kRight));

  for (size_t i = 1; i < second.size(); ++i) h.send_shard(second[i]);
  h.send_shard(first.back());  // too late now: frame 2 completed
  h.run_for(kMs);
  ASSERT_TRUE(h.client.take_newest(Eye::kRight, v));
  EXPECT_EQ(v.frame_number, 2u);
  EXPECT_TRUE(v.complete);
  EXPECT_EQ(h.client.stats().shards_late, 1u);
  EXPECT_EQ(h.client.stats().frames_superseded, 1u);  // frame 1, released incomplete when frame 2 completed
}

TEST(ClientReceive, DuplicatesAreCountedAtShardAndDatagramLevel) {
  Harness h;
  h.connect();
  ASSERT_TRUE(h.client.send_pose(FramePose{1, 0, views_for(1)}));
  const auto shards = shards_for(1, Eye::kLeft);
  h.send_shard(shards[0]);
  const std::vector<uint8_t> copy = encode_datagram(Datagram{kToken, h.server_sequence - 1, shards[0]});
  h.server_send_raw(copy);  // the same datagram again (as a duplicating link delivers it)
  for (size_t i = 1; i < shards.size(); ++i) h.send_shard(shards[i]);
  h.send_shard(shards[2]);  // re-sent after completion (a new datagram, same shard)
  h.run_for(kMs);
  const ClientNetStats s = h.client.stats();
  EXPECT_EQ(s.shards_received, shards.size() + 2);
  EXPECT_EQ(s.shards_accepted, shards.size());
  EXPECT_EQ(s.shards_duplicate, 2u);
  EXPECT_EQ(s.server_datagrams_duplicate, 1u);
  EXPECT_EQ(s.server_datagrams_missing, 0u);
  EXPECT_EQ(s.server_datagrams_unique, shards.size() + 2);  // Welcome + shards + the re-sent shard
}

TEST(ClientReceive, BadDatagramsAreCountedByReasonAndDropped) {
  Harness h;
  h.connect();
  ASSERT_TRUE(h.client.send_pose(FramePose{3, 0, views_for(3)}));
  const auto shards = shards_for(3, Eye::kLeft);
  const std::vector<uint8_t> good = encode_datagram(Datagram{kToken, 100, shards[0]});

  h.server_send_raw(std::vector<uint8_t>(good.begin(), good.begin() + 50));  // truncated
  std::vector<uint8_t> big = good;
  big.resize(kMaxDatagramSize + 1, 0);
  h.server_send_raw(big);  // oversize
  std::vector<uint8_t> junk(200);
  std::mt19937 rng(5);
  for (auto& b : junk) b = static_cast<uint8_t>(rng());
  h.server_send_raw(junk);  // bad magic
  std::vector<uint8_t> wrong_version = good;
  wrong_version[4] = 9;
  h.server_send_raw(wrong_version);
  h.send_shard(shards[0], kToken ^ 1);  // another session's token: foreign
  VisibilityShard future = shards_for(4, Eye::kLeft)[0];  // frame 4 was never requested
  h.send_shard(future);
  VisibilityShard mismatched = shards[0];
  mismatched.buffer_width = kBufW - 1;  // not the session's size
  h.send_shard(mismatched);
  h.server_send(PoseUpdate{});  // a client message
  h.run_for(kMs);

  const ClientNetStats s = h.client.stats();
  EXPECT_EQ(s.rejections[DecodeError::kTruncated], 1u);
  EXPECT_EQ(s.rejections[DecodeError::kOversize], 1u);
  EXPECT_EQ(s.rejections[DecodeError::kBadMagic], 1u);
  EXPECT_EQ(s.rejections[DecodeError::kWrongVersion], 1u);
  EXPECT_EQ(s.rejections[DecodeError::kFutureFrame], 1u);
  EXPECT_EQ(s.rejections[DecodeError::kSessionMismatch], 1u);
  EXPECT_EQ(s.datagrams_rejected, 4u);
  EXPECT_EQ(s.shards_rejected, 2u);
  EXPECT_EQ(s.datagrams_foreign, 1u);
  EXPECT_EQ(s.datagrams_unexpected, 1u);
  EXPECT_EQ(s.datagrams_received,
            s.datagrams_rejected + s.datagrams_foreign + s.datagrams_unexpected + s.datagrams_handled);
  EXPECT_TRUE(h.client.connected());  // garbage does not end the session
  EXPECT_FALSE(h.client.failed());
  VisibilityFrame v;
  EXPECT_FALSE(h.client.take_newest(Eye::kLeft, v));
  for (const auto& shard : shards) h.send_shard(shard);  // the real frame still gets through
  h.run_for(kMs);
  ASSERT_TRUE(h.client.take_newest(Eye::kLeft, v));
  EXPECT_EQ(v.buffer, buffer_for(3, Eye::kLeft));
}

TEST(ClientReceive, MutatedDatagramsNeverCrashAndMemoryStaysBounded) {
  Harness h;
  h.connect();
  std::mt19937_64 rng(11);
  uint64_t frame = 0;
  for (int round = 0; round < 200; ++round) {
    ++frame;
    ASSERT_TRUE(h.client.send_pose(FramePose{frame, 0, views_for(frame)}));
    const Eye eye = (round % 2) ? Eye::kLeft : Eye::kRight;
    for (const VisibilityShard& shard : shards_for(frame, eye)) {
      std::vector<uint8_t> bytes = encode_datagram(Datagram{kToken, h.server_sequence++, shard});
      if (rng() % 4 == 0) continue;  // lost
      if (rng() % 3 == 0) {
        const size_t flips = 1 + rng() % 4;
        for (size_t i = 0; i < flips; ++i) bytes[rng() % bytes.size()] ^= static_cast<uint8_t>(1u << (rng() % 8));
      }
      if (rng() % 10 == 0) bytes.resize(rng() % bytes.size());
      h.server_send_raw(bytes);
    }
    h.run_for(3 * kMs);
    VisibilityFrame v;
    h.client.take_newest(Eye::kLeft, v);
    h.client.take_newest(Eye::kRight, v);
  }
  const ClientNetStats s = h.client.stats();
  EXPECT_GT(s.datagrams_rejected + s.shards_rejected, 0u);
  EXPECT_GT(s.frames_completed, 0u);
  EXPECT_EQ(s.datagrams_received,
            s.datagrams_rejected + s.datagrams_foreign + s.datagrams_unexpected + s.datagrams_handled);
  EXPECT_GT(s.reassembler_memory_bytes, 0u);
  EXPECT_LE(s.reassembler_memory_bytes, h.client.memory_bound_bytes());
}

}  // namespace
}  // namespace dhr::client::test
