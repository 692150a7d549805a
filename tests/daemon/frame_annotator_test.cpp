// SPDX-License-Identifier: Apache-2.0
// A frame's validity from the daemon's state (daemon/frame_annotator.h, docs/frame-protocol.md
// "Frame validity"): the pose's age against stale_pose_ms, each degraded reason, off route.
#include <gtest/gtest.h>

#include "frame_annotator.h"

using namespace navmap;
using namespace navmap::daemon;

namespace {

EstimatedPose poseAged(double seconds) {
    EstimatedPose p;
    p.valid = true;
    p.since_fix_s = seconds;
    return p;
}

}  // namespace

TEST(FrameValidity, ThePoseAgeDecidesStalePoseAtTheConfiguredLimit) {
    FrameHealth health;
    health.stale_pose_ms = 1000;
    auto v = frameValidity(poseAged(0.2), health, false, 0, 0);
    EXPECT_EQ(v.version, ipc::kFrameValidityVersion);
    EXPECT_TRUE(v.fresh());
    EXPECT_EQ(v.pose_age_ms, 200U);
    v = frameValidity(poseAged(1.0), health, false, 0, 0);
    EXPECT_TRUE(v.fresh()) << "exactly the limit is not older than it";
    v = frameValidity(poseAged(1.2), health, false, 0, 0);
    EXPECT_EQ(v.flags, ipc::kValidityStalePose);
    EXPECT_EQ(v.pose_age_ms, 1200U);
    health.stale_pose_ms = 2000;
    EXPECT_TRUE(frameValidity(poseAged(1.2), health, false, 0, 0).fresh());
    // No fix yet: stale, with no age.
    v = frameValidity(EstimatedPose{}, health, false, 0, 0);
    EXPECT_EQ(v.flags, ipc::kValidityStalePose);
    EXPECT_EQ(v.pose_age_ms, ipc::kPoseAgeNone);
    // Following a tunnel's road without fixes (docs/vehicle-state.md "Tunnels"): the age goes on,
    // the flag stays off until the estimator itself calls the pose stale.
    health.stale_pose_ms = 1000;
    EstimatedPose tunnel = poseAged(30.0);
    tunnel.follows_graph = true;
    v = frameValidity(tunnel, health, false, 0, 0);
    EXPECT_TRUE(v.fresh());
    EXPECT_EQ(v.pose_age_ms, 30000U);
    tunnel.stale = true;  // out of the tunnel, still without a fix
    EXPECT_EQ(frameValidity(tunnel, health, false, 0, 0).flags, ipc::kValidityStalePose);
}

TEST(FrameValidity, EachDegradedReasonAndOffRouteAreTheirOwnBits) {
    FrameHealth health;
    auto v = frameValidity(poseAged(0.1), health, false, 3, 0);
    EXPECT_EQ(v.flags, ipc::kValidityDegraded);
    EXPECT_EQ(v.degraded, ipc::kDegradedTilesMissing);
    v = frameValidity(poseAged(0.1), health, false, 0, 1);
    EXPECT_EQ(v.degraded, ipc::kDegradedTilesFailed);
    health.road_graph_off = true;
    health.orthoimage_off = true;
    v = frameValidity(poseAged(0.1), health, true, 0, 0);
    EXPECT_EQ(v.flags, ipc::kValidityDegraded | ipc::kValidityOffRoute);
    EXPECT_EQ(v.degraded, ipc::kDegradedRoadGraphOff | ipc::kDegradedOrthoimageOff);
    EXPECT_EQ(ipc::validityText(v), "degraded+off_route");
    EXPECT_EQ(ipc::degradedText(v.degraded), "road_graph_off+orthoimage_off");
}
