#include "net/latest_slot.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

namespace dhr::net {
namespace {

TEST(LatestSlot, EmptySlotHasNothingToFetch) {
  LatestSlot<int> slot;
  EXPECT_FALSE(slot.fetch());
  EXPECT_FALSE(slot.has_value());
  int out = 7;
  EXPECT_FALSE(slot.take(out));
  EXPECT_EQ(out, 7);
  EXPECT_EQ(slot.published_count(), 0u);
}

TEST(LatestSlot, NewestWinsAndOverwritesAreCounted) {
  LatestSlot<int> slot;
  slot.publish(1);
  slot.publish(2);
  slot.publish(3);
  ASSERT_TRUE(slot.fetch());
  EXPECT_TRUE(slot.has_value());
  EXPECT_EQ(slot.read_buffer(), 3);
  EXPECT_EQ(slot.published_count(), 3u);
  EXPECT_EQ(slot.overwritten_count(), 2u);
  // Nothing newer: the reader keeps what it has.
  EXPECT_FALSE(slot.fetch());
  EXPECT_EQ(slot.read_buffer(), 3);
  slot.publish(4);
  ASSERT_TRUE(slot.fetch());
  EXPECT_EQ(slot.read_buffer(), 4);
  EXPECT_EQ(slot.overwritten_count(), 2u);
}

TEST(LatestSlot, TakeSwapsTheNewestValueOut) {
  LatestSlot<std::vector<int>> slot;
  slot.publish({1, 2, 3});
  std::vector<int> out = {9};
  ASSERT_TRUE(slot.take(out));
  EXPECT_EQ(out, (std::vector<int>{1, 2, 3}));
  EXPECT_FALSE(slot.take(out));
  EXPECT_EQ(out, (std::vector<int>{1, 2, 3}));
}

TEST(LatestSlot, WriterBuffersAreRecycledWithoutReallocation) {
  LatestSlot<std::vector<uint8_t>> slot;
  // Steady state: three buffers rotate, each keeps the capacity it grew to.
  for (int round = 0; round < 6; ++round) {
    std::vector<uint8_t>& buffer = slot.write_buffer();
    buffer.resize(1000);
    buffer.assign(1000, static_cast<uint8_t>(round));
    slot.publish();
    ASSERT_TRUE(slot.fetch());
    EXPECT_EQ(slot.read_buffer().size(), 1000u);
    EXPECT_EQ(slot.read_buffer()[999], round);
  }
  for (int round = 0; round < 3; ++round) {
    EXPECT_GE(slot.write_buffer().capacity(), 1000u);
    slot.publish();
    slot.fetch();
  }
}

struct Frame {
  uint64_t number = 0;
  std::vector<uint64_t> data;  // every element equals number: a torn read would show
};

TEST(LatestSlot, ConcurrentWriterAndReaderSeeWholeIncreasingValues) {
  constexpr uint64_t kFrames = 200'000;
  LatestSlot<Frame> slot;
  std::atomic<bool> reader_failed{false};
  uint64_t fetched = 0;
  uint64_t last_seen = 0;

  std::thread reader([&] {
    while (last_seen < kFrames) {
      if (!slot.fetch()) {
        std::this_thread::yield();
        continue;
      }
      const Frame& frame = slot.read_buffer();
      ++fetched;
      bool whole = frame.data.size() == 16;
      for (uint64_t value : frame.data) whole = whole && value == frame.number;
      if (!whole || frame.number <= last_seen) {
        reader_failed = true;
        return;
      }
      last_seen = frame.number;
    }
  });
  for (uint64_t n = 1; n <= kFrames; ++n) {
    Frame& frame = slot.write_buffer();
    frame.number = n;
    frame.data.assign(16, n);
    slot.publish();
  }
  reader.join();
  EXPECT_FALSE(reader_failed.load());
  EXPECT_EQ(last_seen, kFrames);  // the newest value always reaches the reader
  EXPECT_EQ(slot.published_count(), kFrames);
  // Every published value was either fetched or overwritten unseen.
  EXPECT_EQ(fetched + slot.overwritten_count(), kFrames);
}

}  // namespace
}  // namespace dhr::net
