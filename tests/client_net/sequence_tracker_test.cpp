// SequenceTracker: duplicates and gaps in the peer's datagram sequence numbers, wrap-around, restart.
#include "link/sequence_tracker.hpp"

#include <gtest/gtest.h>

namespace dhr::client {
namespace {

using R = SequenceTracker::Result;

TEST(SequenceTracker, CountsDuplicatesAndGapsWithReordering) {
  SequenceTracker t(64);
  EXPECT_EQ(t.add(10), R::kNew);
  EXPECT_EQ(t.add(12), R::kNew);
  EXPECT_EQ(t.missing(), 1u);  // 11
  EXPECT_EQ(t.add(11), R::kNew);  // reordered, not lost
  EXPECT_EQ(t.missing(), 0u);
  EXPECT_EQ(t.add(11), R::kDuplicate);
  EXPECT_EQ(t.add(9), R::kNew);  // older than the first seen, still in the window
  EXPECT_EQ(t.add(20), R::kNew);
  EXPECT_EQ(t.missing(), 7u);  // 13..19
  EXPECT_EQ(t.unique(), 5u);
  EXPECT_EQ(t.duplicates(), 1u);
}

TEST(SequenceTracker, OldNumbersBeyondTheWindowAreNotClassified) {
  SequenceTracker t(64);
  t.add(0);
  t.add(1000);
  EXPECT_EQ(t.add(0), R::kTooOld);
  EXPECT_EQ(t.add(999), R::kNew);
  EXPECT_EQ(t.add(999), R::kDuplicate);
  EXPECT_EQ(t.too_old(), 1u);
}

TEST(SequenceTracker, WrapsAroundAndRestartsPerSession) {
  SequenceTracker t(128);
  t.add(0xFFFFFFFEu);
  t.add(0xFFFFFFFFu);
  EXPECT_EQ(t.add(1), R::kNew);  // 0 is missing
  EXPECT_EQ(t.add(0xFFFFFFFFu), R::kDuplicate);
  EXPECT_EQ(t.missing(), 1u);
  t.restart();
  EXPECT_EQ(t.add(0), R::kNew);  // a new session counts from 0 again
  EXPECT_EQ(t.add(0), R::kDuplicate);
  EXPECT_EQ(t.missing(), 1u);  // carried from the first session
  EXPECT_EQ(t.unique(), 4u);
}

}  // namespace
}  // namespace dhr::client
