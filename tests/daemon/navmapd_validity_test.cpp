// SPDX-License-Identifier: Apache-2.0
// navmapd's frame validity and metadata end to end (docs/frame-protocol.md "Frame validity",
// "Metadata block"): a replay that stops turns the frames stale_pose with a growing pose age; a
// store copy with damaged tiles under the camera and a damaged road graph makes them degraded,
// naming both. The daemon works the states out from what happens to it; the test only reads the
// frames a display would get.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "navmap/ipc/client/stream_client.h"
#include "navmap/map/tile_store.h"
#include "navmapd_process.h"
#include "test_paths.h"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using navmap::ipc::FrameMeta;
using navmap::ipc::FrameValidity;

constexpr double kLat = 42.50770;  // where writeStandingLog's vehicle stands
constexpr double kLon = 1.52190;

struct Seen {
    FrameValidity validity;
    std::optional<FrameMeta> meta;
};

/// The frames of the cluster stream, with their validity and metadata, for `window`.
std::vector<Seen> framesFor(const fs::path& frame_socket, std::chrono::milliseconds window) {
    navmap::ipc::StreamRequest request;
    request.profile = *navmap::ipc::defaultStreamProfile("cluster");
    request.meta = true;
    std::vector<Seen> seen;
    auto client = navmap::ipc::StreamClient::connectUnix(frame_socket.string(), request);
    EXPECT_TRUE(client.ok()) << client.error().message;
    if (!client) return seen;
    navmap::ipc::ReceivedFrame f;
    const auto until = std::chrono::steady_clock::now() + window;
    while (std::chrono::steady_clock::now() < until) {
        auto got = client.value()->next(f, 100ms);
        EXPECT_TRUE(got.ok()) << got.error().message;
        if (!got) break;
        if (got.value()) seen.push_back({f.header.validity, f.meta});
    }
    return seen;
}

std::string daemonArgs(const fs::path& dir, const fs::path& store) {
    return "--store " + store.string() + " --noop --no-labels --profiles cluster --http-port 0 --log-level info" +
           " --control-socket " + (dir / "control.sock").string() + " --frame-socket " + (dir / "frames.sock").string();
}

void flipByte(const fs::path& file, std::uint64_t at) {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekg(static_cast<std::streamoff>(at));
    char c = 0;
    f.get(c);
    f.seekp(static_cast<std::streamoff>(at));
    f.put(static_cast<char>(c ^ 0x01));
}

/// A copy of the default store whose tiles under (kLat, kLon) at the two finest levels and whose
/// road graph each have a flipped byte (a checksum mismatch: failed to load, never retried).
fs::path storeWithDamageUnderTheVehicle(const fs::path& dir, int* damaged) {
    const fs::path src = navmap::test::binaryDir() / "andorra.navmap";
    fs::path out = dir / "damaged.navmap";
    fs::copy_file(src, out);
    const auto store = navmap::map::TileStore::open(src);
    const auto at = store->projection().forward(kLat, kLon);
    const auto& scheme = store->scheme();
    for (int level = scheme.leafLevel() - 1; level <= scheme.leafLevel(); ++level) {
        const auto id = scheme.tileAt(level, at);
        if (!id || store->blobOffset(*id) == 0) continue;
        flipByte(out, store->blobOffset(*id) + store->storedSize(*id) / 2);
        ++*damaged;
    }
    const auto& info = store->info();
    flipByte(out, info.graph_offset + info.graph_stored_size / 2);
    return out;
}

}  // namespace

TEST(NavmapdValidity, AReplayThatStopsTurnsTheFramesStaleWithTheAgeOfThePose) {
    const fs::path store = navmap::test::binaryDir() / "andorra.navmap";
    ASSERT_TRUE(fs::exists(store)) << store << " (target navmap_default_store)";
    navmap::test::ScratchDir s("navmapd-stale");
    navmap::test::writeStandingLog(s.dir / "standing.candump", {{kLat, kLon}}, 4000);
    std::ofstream(s.dir / "navmapd.toml") << "[input]\nreplay_loop = false\n[stream]\nstale_pose_ms = 500\n";
    navmap::test::NavmapdProcess d(NAVMAPD_PATH,
                                   "--config " + (s.dir / "navmapd.toml").string() + " " + daemonArgs(s.dir, store) +
                                       " --replay " + (s.dir / "standing.candump").string(),
                                   s.dir / "navmapd.log", s.dir / "frames.sock");
    ASSERT_TRUE(fs::exists(s.dir / "frames.sock")) << d.output();
    // 4 s of fixes at 10 Hz, then nothing: watch the stream across the end of the replay.
    const auto seen = framesFor(s.dir / "frames.sock", 7s);
    ASSERT_GT(seen.size(), 10U) << d.output();
    std::size_t fresh = 0, first_stale = seen.size();
    for (std::size_t i = 0; i < seen.size(); ++i) {
        const auto& v = seen[i].validity;
        ASSERT_EQ(v.version, navmap::ipc::kFrameValidityVersion);
        const bool stale = (v.flags & navmap::ipc::kValidityStalePose) != 0;
        if (v.fresh() && v.pose_age_ms < 500) ++fresh;
        if (stale && v.pose_age_ms != navmap::ipc::kPoseAgeNone && first_stale == seen.size()) first_stale = i;
        // A stale frame is one whose fix is older than stale_pose_ms, and only that.
        if (v.pose_age_ms != navmap::ipc::kPoseAgeNone) {
            EXPECT_EQ(stale, v.pose_age_ms > 500) << v.pose_age_ms;
        }
        ASSERT_TRUE(seen[i].meta.has_value()) << "frame " << i;
    }
    EXPECT_GT(fresh, 0U) << "while the replay runs the frames are fresh";
    ASSERT_LT(first_stale, seen.size()) << "after the replay the frames turn stale_pose";
    // After the replay the age grows with the time since the last fix, and the pose is where
    // the vehicle last was.
    const auto& last = seen.back();
    EXPECT_NE(last.validity.flags & navmap::ipc::kValidityStalePose, 0);
    EXPECT_GT(last.validity.pose_age_ms, seen[first_stale].validity.pose_age_ms + 500);
    ASSERT_TRUE(last.meta->has_pose);
    EXPECT_NEAR(last.meta->lat_deg, kLat, 2e-4);
    EXPECT_NEAR(last.meta->lon_deg, kLon, 2e-4);
    EXPECT_GE(last.meta->heading_deg, 0.0);
    EXPECT_LT(last.meta->heading_deg, 360.0);
    EXPECT_FALSE(last.meta->has_next) << "no route";
    EXPECT_FALSE(last.meta->lanes_known);
    EXPECT_EQ(last.meta->speed_limit_kmh, 0) << "unknown";
    EXPECT_EQ(d.stop(), 0) << d.output();
}

TEST(NavmapdValidity, DamagedTilesUnderTheCameraAndADamagedGraphMakeTheFramesDegraded) {
    navmap::test::ScratchDir s("navmapd-degraded");
    int damaged = 0;
    const fs::path store = storeWithDamageUnderTheVehicle(s.dir, &damaged);
    ASSERT_GT(damaged, 0);
    navmap::test::writeStandingLog(s.dir / "standing.candump", {{kLat, kLon}}, 60000);
    navmap::test::NavmapdProcess d(NAVMAPD_PATH,
                                   daemonArgs(s.dir, store) + " --replay " + (s.dir / "standing.candump").string(),
                                   s.dir / "navmapd.log", s.dir / "frames.sock");
    ASSERT_TRUE(fs::exists(s.dir / "frames.sock")) << d.output();
    // The start-up wait for the tiles under the camera (15 s) runs out: the damaged ones never come.
    const auto seen = framesFor(s.dir / "frames.sock", 22s);
    ASSERT_GT(seen.size(), 5U) << d.output();
    for (const auto& f : seen) {
        const auto& v = f.validity;
        EXPECT_NE(v.flags & navmap::ipc::kValidityDegraded, 0) << navmap::ipc::validityText(v);
        EXPECT_NE(v.degraded & navmap::ipc::kDegradedTilesFailed, 0) << navmap::ipc::degradedText(v.degraded);
        EXPECT_NE(v.degraded & navmap::ipc::kDegradedRoadGraphOff, 0) << navmap::ipc::degradedText(v.degraded);
        EXPECT_EQ(v.degraded & navmap::ipc::kDegradedOrthoimageOff, 0) << "the ground is the land cover";
        ASSERT_TRUE(f.meta.has_value());
        EXPECT_EQ(f.meta->current_street, "") << "no graph: no map-matched road";
    }
    EXPECT_NE(d.output().find("checksum mismatch (corrupt tile)"), std::string::npos) << d.output();
    EXPECT_EQ(d.stop(), 0) << d.output();
}
