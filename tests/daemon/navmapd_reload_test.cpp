// SPDX-License-Identifier: Apache-2.0
// SIGHUP: navmapd re-reads its configuration (style, per-profile fps and view) without dropping
// its clients, reports the reload in status and metrics, and refuses a broken file while the old
// configuration keeps running (docs/navmapd.md "Lifecycle").
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/control/control_client.h"
#include "navmapd_process.h"
#include "wait_for.h"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

// One small snail's-view profile: day and night change the map's colours (the HUD's guidance view
// is black in both). Style "auto": [style] mode = "auto" by the sun.
void writeConfig(const fs::path& dir, const char* style, int fps) {
    const std::string s = style;
    std::ofstream(dir / "navmapd.toml") << "[input]\nsource = \"replay\"\nreplay_log = \""
                                        << (dir / "standing.candump").string() << "\"\n"
                                        << (s == "auto" ? "[style]\nmode = \"auto\"\nsource = \"sun\"\n" : "")
                                        << "[render]\n"
                                        << (s == "auto" ? "" : "style = \"" + s + "\"\n") << "labels = false\n"
                                        << "[[profile]]\nname = \"small\"\nwidth = 800\nheight = 240\nfps = " << fps
                                        << "\nview = \"snail\"\n"
                                        << "[control]\nsocket = \"" << (dir / "control.sock").string() << "\"\n"
                                        << "[stream]\nsocket = \"" << (dir / "frames.sock").string()
                                        << "\"\nhttp_port = 0\n";
}

double meanBrightness(const navmap::ipc::ReceivedFrame& f) {
    double sum = 0;
    for (std::uint32_t y = 0; y < f.header.height; ++y) {
        const std::uint8_t* row = &f.pixels[static_cast<std::size_t>(y) * f.header.stride];
        for (std::uint32_t x = 0; x < f.header.width; ++x) sum += row[4 * x] + row[4 * x + 1] + row[4 * x + 2];
    }
    return sum / (3.0 * f.header.width * f.header.height);
}

struct Window {
    int frames = 0;
    double brightness = 0;  // of the last frame
    std::uint64_t first_seq = 0, last_seq = 0;
    bool in_order = true;
};

// Receives for `duration` on `client`; every frame must come with a higher sequence number.
Window receive(navmap::ipc::StreamClient& client, std::chrono::milliseconds duration, std::uint64_t after_seq,
               const navmap::test::NavmapdProcess& d) {
    Window w;
    w.last_seq = after_seq;
    navmap::ipc::ReceivedFrame f;
    const auto until = std::chrono::steady_clock::now() + duration;
    while (std::chrono::steady_clock::now() < until) {
        auto got = client.next(f, 50ms);
        EXPECT_TRUE(got) << "the client lost its connection: " << got.error().message << "\n" << d.output();
        if (!got) break;
        if (!got.value()) continue;
        w.in_order = w.in_order && f.header.sequence > w.last_seq;
        if (w.frames++ == 0) w.first_seq = f.header.sequence;
        w.last_seq = f.header.sequence;
        w.brightness = meanBrightness(f);
    }
    return w;
}

std::string daemonStatus(const fs::path& control_socket) {
    auto control = navmap::ipc::ControlClient::connect(control_socket.string());
    if (!control) return "connect: " + control.error().message;
    auto st = control.value().request(R"({"cmd":"get_status"})");
    return st ? st.value() : "get_status: " + st.error().message;
}

TEST(NavmapdReload, SighupAppliesStyleAndFpsWithoutDroppingClientsAndRefusesABrokenFile) {
    const fs::path dir = fs::temp_directory_path() / ("navmapd-reload-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    navmap::test::writeStandingLog(dir / "standing.candump");
    writeConfig(dir, "day", 4);
    navmap::test::NavmapdProcess d(NAVMAPD_PATH, "--config " + (dir / "navmapd.toml").string() + " --log-level info",
                                   dir / "navmapd.log", dir / "frames.sock");
    ASSERT_TRUE(fs::exists(dir / "frames.sock")) << d.output();

    navmap::ipc::StreamRequest request;
    request.profile = {"small", 800, 240, 30, "snail"};
    auto client = navmap::ipc::StreamClient::connectUnix((dir / "frames.sock").string(), request);
    ASSERT_TRUE(client) << client.error().message;
    auto& c = *client.value();

    (void)receive(c, 1500ms, 0, d);  // tiles load, the camera settles
    const Window day = receive(c, 2500ms, 0, d);
    ASSERT_GT(day.frames, 3) << d.output();
    EXPECT_TRUE(day.in_order);

    // Day -> night and 4 -> 12 fps, on the same connection.
    writeConfig(dir, "night", 12);
    ASSERT_TRUE(d.signal(SIGHUP));
    (void)receive(c, 1000ms, day.last_seq, d);
    const Window night = receive(c, 2500ms, day.last_seq, d);
    ASSERT_GT(night.frames, 3) << d.output();
    EXPECT_TRUE(night.in_order) << "sequence numbers keep increasing over the reload";
    EXPECT_GT(night.first_seq, day.last_seq);
    EXPECT_LT(night.brightness, day.brightness * 0.75) << "day " << day.brightness << ", night " << night.brightness;
    EXPECT_GT(night.frames, day.frames * 3 / 2)
        << "4 fps -> 12 fps: day " << day.frames << " frames, night " << night.frames;
    const std::string st = daemonStatus(dir / "control.sock");
    EXPECT_NE(st.find("\"reloads\":1"), std::string::npos) << st;
    EXPECT_NE(st.find("\"style\":\"night\""), std::string::npos) << st;
    EXPECT_NE(d.output().find("<5>navmapd: reloaded " + (dir / "navmapd.toml").string() + ": style night"),
              std::string::npos)
        << d.output();

    // A broken file is refused with a clear line; the night style at 12 fps keeps running.
    std::ofstream(dir / "navmapd.toml") << "[render]\nstyle = \"dusk\"\n";
    ASSERT_TRUE(d.signal(SIGHUP));
    (void)receive(c, 500ms, night.last_seq, d);
    const Window kept = receive(c, 2000ms, night.last_seq, d);
    EXPECT_GT(kept.frames, 3) << d.output();
    EXPECT_TRUE(kept.in_order);
    EXPECT_NEAR(kept.brightness, night.brightness, 0.1 * night.brightness);
    const std::string out = d.output();
    const auto refused = out.find("<3>navmapd: reload: " + (dir / "navmapd.toml").string() + ":");
    ASSERT_NE(refused, std::string::npos) << out;
    const std::string line = out.substr(refused, out.find('\n', refused) - refused);
    EXPECT_NE(line.find("render.style = \"dusk\": expected day or night (keeping the running configuration)"),
              std::string::npos)
        << line;
    const std::string st2 = daemonStatus(dir / "control.sock");
    EXPECT_NE(st2.find("\"reloads\":1"), std::string::npos) << st2;
    EXPECT_NE(st2.find("\"reload_errors\":1"), std::string::npos) << st2;

    EXPECT_EQ(d.stop(), 0) << d.output();
    fs::remove_all(dir);
}

// A 1,000,000-level table header took navmapd down on SIGHUP (toml++ recursed off the stack);
// such files, a dotted key as deep and more profiles than allowed are refused with one line each,
// counted, and the running configuration keeps rendering (daemon/toml_limits.h).
TEST(NavmapdReload, SighupWithADeepOrHugeFileKeepsTheRunningConfiguration) {
    const fs::path dir = fs::temp_directory_path() / ("navmapd-reload-deep-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    navmap::test::writeStandingLog(dir / "standing.candump");
    writeConfig(dir, "day", 4);
    navmap::test::NavmapdProcess d(NAVMAPD_PATH, "--config " + (dir / "navmapd.toml").string() + " --log-level info",
                                   dir / "navmapd.log", dir / "frames.sock");
    ASSERT_TRUE(fs::exists(dir / "frames.sock")) << d.output();
    const std::string config = (dir / "navmapd.toml").string();
    const auto repeat = [](const std::string& s, std::size_t n) {
        std::string out;
        for (std::size_t i = 0; i < n; ++i) out += s;
        return out;
    };
    const std::string nested =
        "nested more than 32 levels deep (tables, dotted keys, arrays and inline tables together)";
    std::string profiles;
    for (int i = 0; i < 65; ++i) profiles += "[[profile]]\nname = \"p" + std::to_string(i) + "\"\n";
    const std::pair<std::string, std::string> cases[] = {
        {"[" + repeat("a.", 999999) + "a]\n", ":1:2: table header " + nested},
        {"[render]\n" + repeat("a.", 999999) + "a = 1\n", ":2:1: key " + nested},
        {repeat("[[profile]]\nname = \"p\"\n", 20000), ":20001:3: more than 20000 keys, tables and array elements"},
        {profiles, ":129:1: 65 profiles, more than 64"},
    };
    std::size_t refused = 0;
    for (const auto& [text, error] : cases) {
        std::ofstream(dir / "navmapd.toml", std::ios::trunc) << text;
        ASSERT_TRUE(d.signal(SIGHUP));
        ++refused;
        const std::string line = "<3>navmapd: reload: " + config + error + " (keeping the running configuration)\n";
        const auto seen = [&] {
            const std::string out = d.output();
            std::size_t n = 0;
            for (auto at = out.find("<3>navmapd: reload: "); at != std::string::npos;
                 at = out.find("<3>navmapd: reload: ", at + 1))
                ++n;
            return n == refused && out.find(line) != std::string::npos;
        };
        EXPECT_TRUE(navmap::test::waitFor(seen, 10s)) << line << d.output().substr(0, 2000);
    }
    const std::string st = daemonStatus(dir / "control.sock");
    EXPECT_NE(st.find("\"reload_errors\":4"), std::string::npos) << st;
    EXPECT_NE(st.find("\"style\":\"day\""), std::string::npos) << st;

    // Still rendering the running profile for a client that asks for it.
    navmap::ipc::StreamRequest request;
    request.profile = {"small", 800, 240, 30, "snail"};
    auto client = navmap::ipc::StreamClient::connectUnix((dir / "frames.sock").string(), request);
    ASSERT_TRUE(client) << client.error().message;
    EXPECT_GT(receive(*client.value(), 6000ms, 0, d).frames, 0) << d.output().substr(0, 2000);
    EXPECT_EQ(d.stop(), 0) << d.output().substr(0, 2000);
    fs::remove_all(dir);
}

// [style] mode = "auto" by the sun, the sun's clock set with --sun-time: the vehicle stands in
// Andorra la Vella (42.508 N, 1.522 E), where 2024-12-21 20:00 UT is night (the sun at -39
// degrees). set_style day wins and fades the map up; set_style auto gives the night back.
TEST(NavmapdDayNight, TheSunAtTheSimulatedTimeChoosesAndSetStyleWins) {
    const fs::path dir = fs::temp_directory_path() / ("navmapd-daynight-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    navmap::test::writeStandingLog(dir / "standing.candump");
    writeConfig(dir, "auto", 8);
    navmap::test::NavmapdProcess d(
        NAVMAPD_PATH,
        "--config " + (dir / "navmapd.toml").string() + " --sun-time 2024-12-21T20:00:00Z --log-level info",
        dir / "navmapd.log", dir / "frames.sock");
    ASSERT_TRUE(fs::exists(dir / "frames.sock")) << d.output();
    navmap::ipc::StreamRequest request;
    request.profile = {"small", 800, 240, 30, "snail"};
    auto client = navmap::ipc::StreamClient::connectUnix((dir / "frames.sock").string(), request);
    ASSERT_TRUE(client) << client.error().message;
    auto& c = *client.value();
    const Window night = receive(c, 3000ms, 0, d);
    ASSERT_GT(night.frames, 3) << d.output();
    const auto status = [&] { return daemonStatus(dir / "control.sock"); };
    ASSERT_TRUE(navmap::test::waitFor([&] { return status().find("\"reason\":\"sun\"") != std::string::npos; }, 5s))
        << status();
    std::string st = status();
    EXPECT_NE(st.find("\"mode\":\"auto\""), std::string::npos) << st;
    EXPECT_NE(st.find("\"shown\":\"night\""), std::string::npos) << st;
    EXPECT_NE(st.find("\"sun_elevation_deg\":-3"), std::string::npos) << st;  // about -39 degrees

    auto control = navmap::ipc::ControlClient::connect((dir / "control.sock").string());
    ASSERT_TRUE(control) << control.error().message;
    ASSERT_TRUE(control.value().request(R"({"cmd":"set_style","style":"day"})"));
    (void)receive(c, 2500ms, night.last_seq, d);  // the 2 s fade
    const Window day = receive(c, 1500ms, night.last_seq, d);
    ASSERT_GT(day.frames, 3) << d.output();
    EXPECT_GT(day.brightness, night.brightness * 1.3) << "night " << night.brightness << ", day " << day.brightness;
    st = status();
    EXPECT_NE(st.find("\"mode\":\"day\""), std::string::npos) << st;
    EXPECT_NE(st.find("\"reason\":\"fixed\""), std::string::npos) << st;

    ASSERT_TRUE(control.value().request(R"({"cmd":"set_style","style":"auto"})"));
    (void)receive(c, 2500ms, day.last_seq, d);
    const Window again = receive(c, 1500ms, day.last_seq, d);
    ASSERT_GT(again.frames, 3) << d.output();
    EXPECT_NEAR(again.brightness, night.brightness, 0.05 * night.brightness);
    EXPECT_NE(status().find("\"shown\":\"night\""), std::string::npos) << status();
    EXPECT_EQ(d.stop(), 0) << d.output().substr(0, 2000);
    fs::remove_all(dir);
}

}  // namespace
