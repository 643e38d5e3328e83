// The world-space offset that puts the OpenXR head at a camera bookmark (xr/world_origin.hpp): views located in the
// offset space are T * view, with T turning about +Y only.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/quaternion.hpp>

#include "xr/world_origin.hpp"

namespace {

using dhr::xr::head_of_views;
using dhr::xr::world_offset_for_start;

XrPosef pose(glm::dquat q, glm::dvec3 p) {
  XrPosef out{};
  out.orientation = {static_cast<float>(q.x), static_cast<float>(q.y), static_cast<float>(q.z), static_cast<float>(q.w)};
  out.position = {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
  return out;
}
glm::dquat q_of(const XrPosef& p) { return {p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z}; }
glm::dvec3 p_of(const XrPosef& p) { return {p.position.x, p.position.y, p.position.z}; }

// A pose in the reference space seen from a space whose pose in the reference space is `space`.
XrPosef in_space(const XrPosef& space, const XrPosef& in_reference) {
  const glm::dquat inv = glm::inverse(q_of(space));
  return pose(inv * q_of(in_reference), inv * (p_of(in_reference) - p_of(space)));
}

glm::dvec3 forward(const XrPosef& p) { return q_of(p) * glm::dvec3(0, 0, -1); }

TEST(WorldOrigin, TheHeadLandsAtTheStartWithItsHeadingAndKeepsItsPitch) {
  const glm::dvec3 y(0, 1, 0), x(1, 0, 0);
  // The tracked head: turned 30 degrees left and pitched 10 degrees down, off the reference origin.
  const XrPosef head = pose(glm::angleAxis(glm::radians(30.0), y) * glm::angleAxis(glm::radians(-10.0), x), {0.1, 1.6, 0.2});
  // The bookmark: at (2, 1.5, -1), looking along +X and 20 degrees down.
  const XrPosef start = pose(glm::angleAxis(glm::radians(-90.0), y) * glm::angleAxis(glm::radians(-20.0), x), {2.0, 1.5, -1.0});
  const XrPosef space = world_offset_for_start(head, start);
  const XrPosef moved = in_space(space, head);
  EXPECT_NEAR(moved.position.x, 2.0, 1e-5);
  EXPECT_NEAR(moved.position.y, 1.5, 1e-5);
  EXPECT_NEAR(moved.position.z, -1.0, 1e-5);
  const glm::dvec3 f = forward(moved);
  EXPECT_NEAR(std::atan2(-f.x, -f.z), glm::radians(-90.0), 1e-5);  // the bookmark's heading: +X
  EXPECT_NEAR(std::asin(f.y), glm::radians(-10.0), 1e-5);           // the head's own pitch, not the bookmark's
  // Up stays up: the offset turns about +Y only.
  const glm::dvec3 up = q_of(space) * y;
  EXPECT_NEAR(up.y, 1.0, 1e-6);
}

TEST(WorldOrigin, LaterHeadMotionIsRigidlyCarriedAlong) {
  const glm::dvec3 y(0, 1, 0);
  const XrPosef head = pose(glm::angleAxis(glm::radians(45.0), y), {0.0, 1.7, 0.0});
  const XrPosef start = pose(glm::dquat(1, 0, 0, 0), {3.0, 1.6, 4.0});
  const XrPosef space = world_offset_for_start(head, start);
  // The head steps 0.5 m along its own forward: in the new space it steps 0.5 m along the bookmark's forward (-Z).
  const XrPosef stepped = pose(q_of(head), p_of(head) + 0.5 * forward(head));
  const XrPosef moved = in_space(space, stepped);
  EXPECT_NEAR(moved.position.x, 3.0, 1e-5);
  EXPECT_NEAR(moved.position.z, 3.5, 1e-5);
}

TEST(WorldOrigin, HeadOfViewsIsTheMidpointWithTheLeftOrientation) {
  const XrPosef left = pose(glm::angleAxis(0.3, glm::dvec3(0, 1, 0)), {-0.03, 1.6, 0.0});
  const XrPosef right = pose(glm::angleAxis(0.3, glm::dvec3(0, 1, 0)), {0.03, 1.6, 0.0});
  const XrPosef head = head_of_views(left, right);
  EXPECT_NEAR(head.position.x, 0.0, 1e-7);
  EXPECT_NEAR(head.position.y, 1.6, 1e-6);
  EXPECT_NEAR(head.orientation.w, left.orientation.w, 1e-7);
}

TEST(WorldOrigin, ANonFiniteHeadGivesAnOffsetTheFrameLoopRefuses) {
  const XrPosef head = pose(glm::dquat(1, 0, 0, 0), {std::nan(""), 1.6, 0});
  const XrPosef start = pose(glm::dquat(1, 0, 0, 0), {1, 1, 1});
  EXPECT_FALSE(dhr::xr::finite_pose(world_offset_for_start(head, start)));
  EXPECT_TRUE(dhr::xr::finite_pose(world_offset_for_start(pose(glm::dquat(1, 0, 0, 0), {0, 1.6, 0}), start)));
}

TEST(WorldOrigin, LookingStraightDownKeepsTheHeading) {
  const XrPosef down = pose(glm::angleAxis(glm::radians(-90.0), glm::dvec3(1, 0, 0)), {0, 1.6, 0});
  const XrPosef start = pose(glm::dquat(1, 0, 0, 0), {1, 1, 1});
  const XrPosef space = world_offset_for_start(down, start);
  for (float c : {space.orientation.x, space.orientation.y, space.orientation.z}) EXPECT_FALSE(std::isnan(c));
  EXPECT_NEAR(in_space(space, down).position.x, 1.0, 1e-5);
}

}  // namespace
