// SPDX-License-Identifier: Apache-2.0
// navmapd with two stores mounted, 800 km apart: Andorra and a copy of it in northern France. A
// replayed drive jumps from one to the other and back; the daemon draws both without restarting
// and without a gap in its frames.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "navmap/ipc/client/frame_png.h"
#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/control/control_client.h"
#include "navmap/map/compile/compiler.h"
#include "navmapd_process.h"
#include "synth_region.h"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

constexpr double kLat = 42.50770, kLon = 1.52190;  // Andorra la Vella
constexpr double kShift = 7.2;                     // degrees north: 800 km

/// Pixels that differ from their right neighbour by more than 24 in a channel: roads, buildings,
/// area borders and relief give many, a plain ground few.
/// NAVMAP_STORES_DUMP=<dir>: the frames the test compares, as PNG files.
void dump(const navmap::ipc::ReceivedFrame& f, const std::string& name) {
    const char* dir = std::getenv("NAVMAP_STORES_DUMP");
    if (!dir) return;
    const auto written =
        navmap::ipc::writeFramePng((fs::path(dir) / (name + ".png")).string(), f.header, f.pixels.data());
    if (!written) ADD_FAILURE() << written.message();
}

double edgeShare(const navmap::ipc::ReceivedFrame& f) {
    std::size_t edges = 0, n = 0;
    for (std::uint32_t y = f.header.height / 3; y < f.header.height; y += 2) {
        const std::uint8_t* row = &f.pixels[static_cast<std::size_t>(y) * f.header.stride];
        for (std::uint32_t x = 0; x + 1 < f.header.width; x += 2, ++n) {
            for (int c = 0; c < 3; ++c) {
                if (std::abs(int(row[4 * x + c]) - int(row[4 * x + 4 + c])) > 24) {
                    ++edges;
                    break;
                }
            }
        }
    }
    return static_cast<double>(edges) / static_cast<double>(n);
}

class NavmapdStores : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        s_dir = fs::temp_directory_path() / ("navmapd-stores-" + std::to_string(::getpid()));
        fs::remove_all(s_dir);
        fs::create_directories(s_dir / "north");
        navmap::map::tools::SynthRegionOptions r;
        r.osm = fs::path(NAVMAP_DATA_DIR) / "andorra-2021-04-14.osm.pbf";
        r.dem = fs::path(NAVMAP_DATA_DIR) / "N42E001.hgt";
        r.out_dir = s_dir / "north";
        r.shift_lat_deg = kShift;
        const auto region = navmap::map::tools::synthesizeRegion(r);
        navmap::map::CompileOptions c;
        c.osm = region.osm;
        c.dems = region.dems;
        c.out = s_dir / "north.navmap";
        (void)navmap::map::compileStore(c);
    }
    static void TearDownTestSuite() { fs::remove_all(s_dir); }

    struct Run {
        /// Per place (0 Andorra, 1 north, 2 between), the frame in the middle of its longest run of
        /// frames (the status is sampled about once a second: a run's ends may be the next place's).
        std::array<std::vector<navmap::ipc::ReceivedFrame>, 3> runs;
        std::array<std::size_t, 3> frames{};
        double longest_gap_s = 0;
        std::array<double, 3> max_scale_error_pct{};  ///< |status frame.scale_error_pct| per place
        std::array<double, 3> max_match{};            ///< best position.match_confidence per place
        nlohmann::json last_status;
        std::string log;
    };
    /// navmapd on `stores` with `stops` replayed, a cluster client reading frames for `seconds`,
    /// each frame filed by where the status put the vehicle when it arrived: in Andorra, 800 km
    /// north, or between them.
    static Run run(const std::string& name, const std::string& stores,
                   const std::vector<std::pair<double, double>>& stops, int seconds) {
        const fs::path dir = s_dir / name;
        fs::create_directories(dir);
        navmap::test::writeStandingLog(dir / "drive.candump", stops, 9000);
        navmap::test::NavmapdProcess d(NAVMAPD_PATH,
                                       stores + " --replay " + (dir / "drive.candump").string() + " --control-socket " +
                                           (dir / "c.sock").string() + " --frame-socket " + (dir / "f.sock").string() +
                                           " --http-port 0 --profiles cluster --no-labels --log-level info",
                                       dir / "navmapd.log", dir / "f.sock");
        Run out;
        navmap::ipc::StreamRequest req;
        req.profile = *navmap::ipc::defaultStreamProfile("cluster");
        auto client = navmap::ipc::StreamClient::connectUnix((dir / "f.sock").string(), req);
        auto control = navmap::ipc::ControlClient::connect((dir / "c.sock").string());
        if (!client || !control) {
            out.log = d.output();
            return out;
        }
        double lat = kLat;
        auto poll = [&] {
            auto st = control.value().request(R"({"cmd":"get_status"})");
            if (!st) return;
            const auto j = nlohmann::json::parse(st.value(), nullptr, false);
            if (j.is_object() && j.contains("status")) {
                out.last_status = j["status"];
                const auto pos = out.last_status.value("position", nlohmann::json::object());
                if (pos.value("valid", false) && out.last_status.contains("frame")) {
                    lat = pos["lat"].get<double>();
                    const int at = lat > kLat + 0.9 * kShift ? 1 : lat > kLat + 0.1 * kShift ? 2 : 0;
                    out.max_scale_error_pct[at] =
                        std::max(out.max_scale_error_pct[at],
                                 std::abs(out.last_status["frame"]["scale_error_pct"].get<double>()));
                    out.max_match[at] = std::max(out.max_match[at], pos["match_confidence"].get<double>());
                }
            }
        };
        navmap::ipc::ReceivedFrame f;
        std::vector<navmap::ipc::ReceivedFrame> run;
        int last_place = -1;
        Clock::time_point last_frame{}, last_poll{};
        const auto until = Clock::now() + std::chrono::seconds(seconds);
        while (Clock::now() < until) {
            if (Clock::now() - last_poll > 300ms) {
                poll();
                last_poll = Clock::now();
            }
            auto got = client.value()->next(f, 50ms);
            if (!got) break;
            if (!got.value()) continue;
            const auto now = Clock::now();
            if (last_frame != Clock::time_point{})
                out.longest_gap_s =
                    std::max(out.longest_gap_s, std::chrono::duration<double>(now - last_frame).count());
            last_frame = now;
            const int place = lat > kLat + 0.9 * kShift ? 1 : lat > kLat + 0.1 * kShift ? 2 : 0;
            ++out.frames[place];
            if (place != last_place) run.clear();
            last_place = place;
            run.push_back(f);
            if (run.size() > out.runs[place].size()) out.runs[place] = run;
        }
        poll();
        out.log = d.output();
        return out;
    }
    static inline fs::path s_dir;
};

}  // namespace

TEST_F(NavmapdStores, ADriveJumpingBetweenTwoStoresIsDrawnInBothWithoutAStall) {
    const std::string stores =
        std::string("--store ") + NAVMAP_DEFAULT_STORE + " --mount " + (s_dir / "north.navmap").string();
    // 9 s in Andorra, 9 s in the north, 9 s halfway between where no store has data, looped.
    const Run both = run("both", stores, {{kLat, kLon}, {kLat + kShift, kLon}, {kLat + kShift / 2, kLon}}, 40);
    ASSERT_GT(both.frames[0], 10u) << both.log;
    ASSERT_GT(both.frames[1], 10u) << both.log;
    // The daemon's status lists both stores, and tiles were read from each.
    const auto& st = both.last_status;
    ASSERT_TRUE(st["stores"].is_array()) << st.dump();
    ASSERT_EQ(st["stores"].size(), 2u) << st.dump();
    EXPECT_GT(st["stores"][0]["tiles_loaded"].get<std::uint64_t>(), 0u) << st.dump();
    EXPECT_GT(st["stores"][1]["tiles_loaded"].get<std::uint64_t>(), 0u) << st.dump();
    EXPECT_NE(both.log.find("mounted store " + (s_dir / "north.navmap").string()), std::string::npos) << both.log;
    // Frames kept coming across the jumps: no gap of a second.
    EXPECT_LT(both.longest_gap_s, 1.0) << both.log;
    // The map is drawn in the north: the last frame there has as much detail as one in Andorra
    // (the same streets), where ground with no store under it is bare.
    ASSERT_GT(both.runs[2].size(), 5u) << both.log;
    auto middle = [&](int place) -> const navmap::ipc::ReceivedFrame& {
        return both.runs[place][both.runs[place].size() / 2];
    };
    const double south = edgeShare(middle(0)), north = edgeShare(middle(1)), bare = edgeShare(middle(2));
    dump(middle(0), "andorra");
    dump(middle(1), "north");
    dump(middle(2), "between");
    std::printf("edge share: Andorra %.4f, north %.4f, between the stores %.4f; longest gap %.3f s\n", south, north,
                bare, both.longest_gap_s);
    EXPECT_GT(north, 0.5 * south);
    EXPECT_LT(bare, 0.25 * north);

    // The map frame followed the vehicle: re-centred at each jump, true to scale within 0.5 %
    // wherever it stood (in Andorra's frame the north is drawn 14 % too large).
    EXPECT_GE(st["frame"]["recentred"].get<int>(), 2) << st.dump();
    for (int place = 0; place < 3; ++place) EXPECT_LE(both.max_scale_error_pct[place], 0.5) << place;
    EXPECT_NE(both.log.find("map frame re-centred on"), std::string::npos) << both.log;
    // Map matching has the roads of both stores: the stop's street is a candidate in the north as
    // in Andorra (with the first store's graph alone, no road there: confidence 0).
    EXPECT_GT(both.max_match[0], 0.0);
    EXPECT_GT(both.max_match[1], 0.5 * both.max_match[0]);

    // Drawn in a frame around the vehicle, the north looks as it does with its store alone, in
    // that store's own frame: the same ground at the same scale.
    // The vehicle arrives as in the drive above (the fixes jump there: it takes the fixes' course).
    const Run alone = run("north-alone", std::string("--store ") + (s_dir / "north.navmap").string(),
                          {{kLat + kShift / 2, kLon}, {kLat + kShift, kLon}}, 20);
    ASSERT_GT(alone.runs[1].size(), 10u) << alone.log;
    const auto& own = alone.runs[1][alone.runs[1].size() * 3 / 4];
    const auto& mounted = both.runs[1][both.runs[1].size() * 3 / 4];
    dump(own, "north-alone");
    ASSERT_EQ(own.header.width, mounted.header.width);
    ASSERT_EQ(own.header.height, mounted.header.height);
    double diff = 0;
    for (std::uint32_t y = 0; y < own.header.height; ++y) {
        for (std::uint32_t x = 0; x < own.header.width; ++x) {
            for (int c = 0; c < 3; ++c) {
                const std::size_t i = static_cast<std::size_t>(y) * own.header.stride + 4 * x + c;
                diff += std::abs(int(own.pixels[i]) - int(mounted.pixels[i]));
            }
        }
    }
    diff /= 3.0 * own.header.width * own.header.height;
    std::printf("north: mean difference to the north store alone %.2f (of 255)\n", diff);
    EXPECT_LT(diff, 3.0);
}
