// Client-side reassembly: loss, reordering, duplicates, newest-frame-wins, late shards, bounded memory.
#include "codec/codec.hpp"
#include "codec/codec_v2.hpp"
#include "codec/reassembly.hpp"
#include "metrics/visibility_synthetic.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <vector>

namespace dhr {
namespace {

constexpr uint32_t kW = 320, kH = 180, kLights = 3;

View view_for(uint64_t frame) {
  View v;
  v.pose.position = {0.001 * static_cast<double>(frame), 1.6, 0.0};
  return v;
}

struct Frame {
  VisibilityBuffer buffer;
  std::vector<VisibilityShard> shards;
};

Frame make_frame(uint64_t frame, Eye eye = Eye::kLeft, uint32_t w = kW, uint32_t h = kH) {
  Frame f;
  f.buffer = make_room_visibility(w, h, kLights, frame);
  EncodeOptions options;
  options.max_payload = 300;  // more shards per frame make loss patterns more interesting
  f.shards = make_visibility_shards(f.buffer, frame, eye, view_for(frame), options);
  for (VisibilityShard& s : f.shards) s.scene_time_ns = static_cast<int64_t>(frame) * 11'000'000;  // as the server
  EXPECT_GT(f.shards.size(), 4u);
  return f;
}

ReassemblerConfig config(size_t in_flight = 4) {
  ReassemblerConfig c;
  c.width = kW;
  c.height = kH;
  c.light_count = kLights;
  c.max_frames_in_flight = in_flight;
  return c;
}

// Rows that every received shard fully covers are valid; rows touched by a missing shard are not.
void expect_rows_match(const ReassembledFrame& got, const Frame& f, const std::set<size_t>& missing) {
  std::vector<uint8_t> expected_valid(kH, 1);
  for (size_t i : missing) {
    const VisibilityShard& s = f.shards[i];
    for (size_t y = s.first_pixel / kW; y <= (s.first_pixel + s.pixel_count - 1) / kW; ++y) expected_valid[y] = 0;
  }
  EXPECT_EQ(got.visibility.row_valid, expected_valid);
  uint32_t valid = 0;
  for (uint32_t y = 0; y < kH; ++y) {
    if (!got.visibility.row_valid[y]) continue;
    ++valid;
    for (uint32_t x = 0; x < kW; ++x) ASSERT_EQ(got.visibility.buffer.get(x, y), f.buffer.get(x, y)) << x << "," << y;
  }
  EXPECT_EQ(got.visibility.rows_valid, valid);
}

TEST(Reassembly, InOrderShardsCompleteTheFrame) {
  VisibilityReassembler r(config());
  const Frame f = make_frame(1);
  EXPECT_EQ(r.latest(Eye::kLeft), nullptr);
  for (size_t i = 0; i < f.shards.size(); ++i) {
    const InsertResult res = r.insert(f.shards[i]);
    EXPECT_EQ(res.status, i + 1 == f.shards.size() ? InsertStatus::kCompleted : InsertStatus::kAccepted);
  }
  const ReassembledFrame* got = r.latest_complete(Eye::kLeft);
  ASSERT_NE(got, nullptr);
  EXPECT_EQ(got, r.latest(Eye::kLeft));
  EXPECT_TRUE(got->complete());
  EXPECT_EQ(got->visibility.frame_number, 1u);
  EXPECT_EQ(got->visibility.buffer, f.buffer);
  EXPECT_EQ(got->visibility.rows_valid, kH);
  EXPECT_EQ(got->visibility.view.pose.position, view_for(1).pose.position);
  EXPECT_EQ(got->visibility.scene_time_ns, 11'000'000);
  EXPECT_EQ(got->shards_received, f.shards.size());
  EXPECT_EQ(r.latest(Eye::kRight), nullptr);
  EXPECT_EQ(r.stats().frames_completed, 1u);
}

TEST(Reassembly, ReorderingAndDuplicatesAreHandled) {
  VisibilityReassembler r(config());
  const Frame f = make_frame(2);
  // Newest shard first. (Was (i * 7 + 3) % n sorted and reversed: the same order, but no permutation when n is a
  // multiple of 7, as on arm64, where the synthetic room gives this frame 14 shards.)
  std::vector<size_t> order(f.shards.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = order.size() - 1 - i;
  size_t duplicates = 0;
  for (size_t k = 0; k < order.size(); ++k) {
    const InsertResult first = r.insert(f.shards[order[k]]);
    EXPECT_TRUE(first.status == InsertStatus::kAccepted || first.status == InsertStatus::kCompleted);
    const InsertResult again = r.insert(f.shards[order[k]]);
    EXPECT_EQ(again.status, InsertStatus::kDuplicate);
    ++duplicates;
  }
  ASSERT_NE(r.latest_complete(Eye::kLeft), nullptr);
  EXPECT_EQ(r.latest_complete(Eye::kLeft)->visibility.buffer, f.buffer);
  EXPECT_EQ(r.stats().shards_duplicate, duplicates);
}

TEST(Reassembly, LostShardsCostOnlyTheirRegions) {
  VisibilityReassembler r(config());
  const Frame f = make_frame(3);
  const std::set<size_t> missing = {1, f.shards.size() / 2, f.shards.size() - 1};
  for (size_t i = 0; i < f.shards.size(); ++i)
    if (!missing.count(i)) {
      EXPECT_EQ(r.insert(f.shards[i]).status, InsertStatus::kAccepted);
    }
  EXPECT_EQ(r.latest_complete(Eye::kLeft), nullptr);
  const ReassembledFrame* got = r.latest(Eye::kLeft);
  ASSERT_NE(got, nullptr);
  EXPECT_FALSE(got->complete());
  EXPECT_EQ(got->shards_received, f.shards.size() - missing.size());
  expect_rows_match(*got, f, missing);
  EXPECT_GT(got->visibility.rows_valid, kH / 2);
  std::vector<std::pair<uint32_t, uint32_t>> expected_ranges;
  for (size_t i = 0; i < f.shards.size(); ++i)
    if (!missing.count(i))
      expected_ranges.emplace_back(f.shards[i].first_pixel, f.shards[i].first_pixel + f.shards[i].pixel_count);
  EXPECT_EQ(got->received_ranges, expected_ranges);
  // The missing shards arrive late (but before a newer frame completes): the frame completes.
  for (size_t i : missing) r.insert(f.shards[i]);
  ASSERT_NE(r.latest_complete(Eye::kLeft), nullptr);
  EXPECT_EQ(r.latest_complete(Eye::kLeft)->visibility.buffer, f.buffer);
}

TEST(Reassembly, NewestFrameWinsAndLateShardsAreDropped) {
  VisibilityReassembler r(config());
  const Frame f5 = make_frame(5), f6 = make_frame(6), f7 = make_frame(7);
  // Frame 5 arrives partly, frame 7 completely, then the rest of 5 and all of 6 straggle in.
  for (size_t i = 0; i < f5.shards.size() / 2; ++i) r.insert(f5.shards[i]);
  for (const auto& s : f7.shards) r.insert(s);
  ASSERT_NE(r.latest_complete(Eye::kLeft), nullptr);
  EXPECT_EQ(r.latest_complete(Eye::kLeft)->visibility.frame_number, 7u);
  EXPECT_EQ(r.latest(Eye::kLeft)->visibility.frame_number, 7u);
  EXPECT_EQ(r.stats().frames_superseded, 1u);  // frame 5 released incomplete
  for (size_t i = f5.shards.size() / 2; i < f5.shards.size(); ++i)
    EXPECT_EQ(r.insert(f5.shards[i]).status, InsertStatus::kLate);
  for (const auto& s : f6.shards) EXPECT_EQ(r.insert(s).status, InsertStatus::kLate);
  EXPECT_EQ(r.insert(f7.shards[0]).status, InsertStatus::kDuplicate);
  EXPECT_EQ(r.latest_complete(Eye::kLeft)->visibility.buffer, f7.buffer);
  EXPECT_EQ(r.stats().shards_late, f5.shards.size() - f5.shards.size() / 2 + f6.shards.size());
}

TEST(Reassembly, NewerIncompleteFramesCoexistWithTheNewestComplete) {
  VisibilityReassembler r(config());
  const Frame f1 = make_frame(1), f2 = make_frame(2), f3 = make_frame(3);
  for (const auto& s : f1.shards) r.insert(s);
  for (size_t i = 0; i + 1 < f3.shards.size(); ++i) r.insert(f3.shards[i]);  // 3 lacks its last shard
  for (size_t i = 1; i < f2.shards.size(); ++i) r.insert(f2.shards[i]);      // 2 lacks its first shard
  EXPECT_EQ(r.latest_complete(Eye::kLeft)->visibility.frame_number, 1u);
  EXPECT_EQ(r.latest(Eye::kLeft)->visibility.frame_number, 3u);
  // 2 completes: 1 is released, 3 stays.
  EXPECT_EQ(r.insert(f2.shards[0]).status, InsertStatus::kCompleted);
  EXPECT_EQ(r.latest_complete(Eye::kLeft)->visibility.frame_number, 2u);
  EXPECT_EQ(r.latest(Eye::kLeft)->visibility.frame_number, 3u);
  EXPECT_EQ(r.insert(f1.shards[0]).status, InsertStatus::kLate);
  EXPECT_EQ(r.insert(f3.shards.back()).status, InsertStatus::kCompleted);
  EXPECT_EQ(r.latest_complete(Eye::kLeft)->visibility.buffer, f3.buffer);
}

TEST(Reassembly, MemoryIsBoundedWhateverArrives) {
  VisibilityReassembler r(config(3));
  const Frame base = make_frame(1);
  size_t memory_after_warmup = 0;
  // 200 frames, each with only its first shard: never complete, each new one evicts the oldest.
  for (uint64_t frame = 1; frame <= 200; ++frame) {
    VisibilityShard s = base.shards[0];
    s.frame_number = frame;
    EXPECT_EQ(r.insert(s).status, InsertStatus::kAccepted);
    if (frame == 3) memory_after_warmup = r.memory_bytes();
    if (frame > 3) {
      EXPECT_EQ(r.memory_bytes(), memory_after_warmup);
    }
  }
  EXPECT_EQ(r.stats().frames_evicted, 197u);
  EXPECT_LE(r.memory_bytes(), (2 * 3 + 1) * (kW * kH + kH * 6 + 4096 * 1));
  // Frame 197 was evicted: its shards are now older than every held frame.
  VisibilityShard old = base.shards[1];
  old.frame_number = 197;
  EXPECT_EQ(r.insert(old).status, InsertStatus::kLate);
  // A newer frame still gets in.
  old.frame_number = 201;
  EXPECT_EQ(r.insert(old).status, InsertStatus::kAccepted);
}

TEST(Reassembly, EyesAreIndependent) {
  VisibilityReassembler r(config());
  const Frame left = make_frame(10, Eye::kLeft), right = make_frame(8, Eye::kRight);
  for (const auto& s : left.shards) r.insert(s);
  for (const auto& s : right.shards) EXPECT_NE(r.insert(s).status, InsertStatus::kLate);
  EXPECT_EQ(r.latest_complete(Eye::kLeft)->visibility.frame_number, 10u);
  EXPECT_EQ(r.latest_complete(Eye::kRight)->visibility.frame_number, 8u);
  EXPECT_EQ(r.latest_complete(Eye::kRight)->visibility.buffer, right.buffer);
}

TEST(Reassembly, InvalidShardsAreRejectedWithoutSideEffects) {
  VisibilityReassembler r(config());
  const Frame f = make_frame(4);
  auto expect_reject = [&](const VisibilityShard& s, DecodeError e) {
    const InsertResult res = r.insert(s);
    EXPECT_EQ(res.status, InsertStatus::kRejected);
    EXPECT_EQ(res.error, e) << to_string(res.error);
  };
  VisibilityShard s = f.shards[0];
  s.buffer_width = kW + 1;
  expect_reject(s, DecodeError::kSessionMismatch);
  s = f.shards[0];
  s.mask_bits = MaskWidth::k16;
  expect_reject(s, DecodeError::kSessionMismatch);
  s = f.shards[0];
  s.shard_count = 65535;
  expect_reject(s, DecodeError::kSessionMismatch);  // beyond the codec bound for this size
  s = f.shards[0];
  s.eye = static_cast<Eye>(3);
  expect_reject(s, DecodeError::kBadValue);
  s = f.shards[0];
  s.first_pixel = kW * kH - 1;
  expect_reject(s, DecodeError::kBadValue);
  s = f.shards[0];
  s.scene_time_ns = -1;  // built in-process: checked as the decoder would
  expect_reject(s, DecodeError::kBadValue);
  s = f.shards[0];
  s.payload[0] ^= 0x07;  // unknown chunk kind
  expect_reject(s, DecodeError::kBadPayload);
  EXPECT_EQ(r.latest(Eye::kLeft), nullptr);  // nothing was started by the rejected shards

  r.insert(f.shards[0]);
  s = f.shards[1];
  s.shard_count = static_cast<uint16_t>(s.shard_count + 1);
  expect_reject(s, DecodeError::kInconsistentFrame);
  s = f.shards[1];
  s.view.pose.position.x += 1e-9;
  expect_reject(s, DecodeError::kInconsistentFrame);
  s = f.shards[1];
  s.scene_time_ns = f.shards[0].scene_time_ns + 1;  // traced at another scene time than the frame's first shard
  expect_reject(s, DecodeError::kInconsistentFrame);
  s = f.shards[0];
  s.shard_index = 1;  // same region as shard 0 under another index
  expect_reject(s, DecodeError::kInconsistentFrame);
  s = f.shards[1];
  s.payload[s.payload_size - 1] ^= 0xFF;
  s.payload_size = static_cast<uint16_t>(s.payload_size - 1);  // truncated payload
  expect_reject(s, DecodeError::kBadPayload);
  EXPECT_EQ(r.latest(Eye::kLeft)->shards_received, 1u);
  EXPECT_EQ(r.latest(Eye::kLeft)->visibility.rows_valid, f.shards[0].pixel_count / kW);

  r.set_newest_requested_frame(4);
  s = f.shards[1];
  s.frame_number = 5;
  expect_reject(s, DecodeError::kFutureFrame);
  EXPECT_EQ(r.stats().shards_rejected, 13u);
  EXPECT_EQ(r.stats().rejections[DecodeError::kInconsistentFrame], 4u);
  // The frame still completes from the genuine shards.
  for (size_t i = 1; i < f.shards.size(); ++i) r.insert(f.shards[i]);
  ASSERT_NE(r.latest_complete(Eye::kLeft), nullptr);
  EXPECT_EQ(r.latest_complete(Eye::kLeft)->visibility.buffer, f.buffer);
}

TEST(Reassembly, RejectsUnusableConfigurations) {
  ReassemblerConfig c = config();
  c.width = 0;
  EXPECT_THROW(VisibilityReassembler{c}, std::invalid_argument);
  c = config();
  c.light_count = 33;
  EXPECT_THROW(VisibilityReassembler{c}, std::invalid_argument);
  c = config(1);
  EXPECT_THROW(VisibilityReassembler{c}, std::invalid_argument);
}

// A lossy, reordering, duplicating (and optionally corrupting) link: whatever the reassembler reports
// must be true, and without corruption every row it calls valid must be bit-exact.
void run_impaired_stream(bool corrupt) {
  VisibilityReassembler r(config(4));
  std::map<uint64_t, Frame> frames;
  uint64_t state = corrupt ? 2025 : 2024;
  auto next = [&state] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<uint32_t>(state >> 33);
  };
  std::vector<VisibilityShard> in_flight;
  size_t memory_cap = 0;
  for (uint64_t frame = 1; frame <= 40; ++frame) {
    Frame& f = frames.emplace(frame, make_frame(frame % 6)).first->second;  // few distinct contents
    for (auto& s : f.shards) {
      s.frame_number = frame;
      s.view = view_for(frame);
    }
    for (const auto& s : f.shards) {
      if (next() % 10 == 0) continue;  // 10 % loss
      in_flight.push_back(s);
      if (next() % 20 == 0) in_flight.push_back(s);  // 5 % duplication
      if (corrupt && next() % 30 == 0) {
        VisibilityShard bad = s;
        bad.payload[next() % bad.payload_size] ^= static_cast<uint8_t>(1u << (next() % 8));
        in_flight.push_back(bad);
      }
    }
    // Deliver a random two thirds now and the rest later (reordering across frames).
    std::vector<VisibilityShard> keep;
    for (auto& s : in_flight) {
      if (next() % 3 != 0) {
        r.insert(s);
      } else {
        keep.push_back(s);
      }
    }
    in_flight.swap(keep);
    if (const ReassembledFrame* c = r.latest_complete(Eye::kLeft)) {
      EXPECT_TRUE(c->complete());
      EXPECT_EQ(c->visibility.rows_valid, kH);
      if (!corrupt) {
        EXPECT_EQ(c->visibility.buffer, frames.at(c->visibility.frame_number).buffer) << "frame " << c->visibility.frame_number;
      }
    }
    if (const ReassembledFrame* l = r.latest(Eye::kLeft)) {
      uint32_t valid = 0;
      for (uint8_t v : l->visibility.row_valid) valid += v;
      EXPECT_EQ(valid, l->visibility.rows_valid);
      EXPECT_LE(l->pixels_received, size_t{kW} * kH);
      const VisibilityBuffer& original = frames.at(l->visibility.frame_number).buffer;
      for (uint32_t y = 0; y < kH && !corrupt; ++y) {
        if (!l->visibility.row_valid[y]) continue;
        for (uint32_t x = 0; x < kW; ++x) {
          ASSERT_EQ(l->visibility.buffer.get(x, y), original.get(x, y));
        }
      }
    }
    memory_cap = std::max(memory_cap, r.memory_bytes());
  }
  EXPECT_LE(memory_cap, (2 * 4 + 1) * (size_t{kW} * kH + 64 * 1024));
  EXPECT_GT(r.stats().frames_completed, 2u);
  EXPECT_GT(r.stats().shards_late + r.stats().frames_evicted + r.stats().frames_superseded, 0u);
  if (corrupt) {
    EXPECT_GT(r.stats().shards_rejected, 0u);
  }
}

TEST(Reassembly, ImpairedStreamIsExactWhereValid) { run_impaired_stream(false); }
TEST(Reassembly, CorruptingStreamKeepsInvariants) { run_impaired_stream(true); }

// Codec v2 shards: intra frames complete and become references; an inter frame decodes against the exact
// frame it names; a frame the reassembler does not hold (never received whole, or pushed out of the ring)
// is rejected with kMissingReference and nothing of it is shown.
TEST(Reassembly, V2InterShardsDecodeOnlyAgainstAHeldReference) {
  ReassemblerConfig c = config();
  c.reference_frames = 2;
  VisibilityReassembler r(c);
  const auto v2_shards = [](const VisibilityBuffer& b, uint64_t frame, const VisibilityBuffer* ref, uint64_t ref_frame) {
    std::vector<EncodedShard> encoded;
    const V2Reference reference{ref, ref_frame};
    EncodeOptions options;
    options.max_payload = 200;
    EXPECT_TRUE(encode_visibility_v2(b, frame, ref != nullptr ? &reference : nullptr, options, encoded));
    return shards_as_messages(b, frame, Eye::kLeft, view_for(frame), encoded);
  };
  const VisibilityBuffer f1 = make_room_visibility(kW, kH, kLights, 1);
  for (const VisibilityShard& s : v2_shards(f1, 1, nullptr, 0)) ASSERT_NE(r.insert(s).status, InsertStatus::kRejected);
  ASSERT_NE(r.latest_complete(Eye::kLeft), nullptr);
  EXPECT_EQ(r.newest_reference(Eye::kLeft), std::optional<uint64_t>(1));
  EXPECT_FALSE(r.newest_reference(Eye::kRight).has_value());

  // Frame 2 against frame 1: decodes exactly.
  VisibilityBuffer f2 = f1;
  for (uint32_t y = 40; y < 80; ++y)
    for (uint32_t x = 100; x < 180; ++x) f2.set(x, y, 5);
  InsertStatus last = InsertStatus::kRejected;
  for (const VisibilityShard& s : v2_shards(f2, 2, &f1, 1)) last = r.insert(s).status;
  EXPECT_EQ(last, InsertStatus::kCompleted);
  EXPECT_EQ(r.latest_complete(Eye::kLeft)->visibility.buffer, f2);

  // Frame 3 against frame 0, which never arrived: every shard rejected, nothing published.
  const uint64_t rejected_before = r.stats().rejections[DecodeError::kMissingReference];
  const auto orphans = v2_shards(f2, 3, &f1, 0);
  for (const VisibilityShard& s : orphans) {
    const InsertResult res = r.insert(s);
    EXPECT_EQ(res.status, InsertStatus::kRejected);
    EXPECT_EQ(res.error, DecodeError::kMissingReference);
  }
  EXPECT_EQ(r.stats().rejections[DecodeError::kMissingReference], rejected_before + orphans.size());
  EXPECT_EQ(r.latest(Eye::kLeft)->visibility.frame_number, 2u);

  // Frames 3 and 4 complete: with a ring of 2, frame 1 is no longer held.
  for (uint64_t f = 3; f <= 4; ++f)
    for (const VisibilityShard& s : v2_shards(f2, f, nullptr, 0)) r.insert(s);
  const auto too_old = v2_shards(f2, 5, &f1, 1);
  EXPECT_EQ(r.insert(too_old.front()).error, DecodeError::kMissingReference);
  EXPECT_EQ(r.newest_reference(Eye::kLeft), std::optional<uint64_t>(4));
  // After reset() (a new session) no reference survives.
  r.reset();
  EXPECT_FALSE(r.newest_reference(Eye::kLeft).has_value());
}

}  // namespace
}  // namespace dhr
