// SPDX-License-Identifier: Apache-2.0
// navmapsrc end to end: the test process runs a FrameServer and publishes known frames, one at a
// time (the next only once the previous one is handed out, so none is dropped); gst-launch-1.0
// runs the element from the build tree (GST_PLUGIN_PATH) with a registry in a temporary folder.
// Checked: the PNGs of multifilesink byte for byte against the published pixels, a VP8/WebM file
// by gst-discoverer-1.0, gst-inspect-1.0 without a warning, EOS when the server stops, the error
// messages, and reconnect=true across a server restart.

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "navmap/ipc/stream/frame_server.h"
#include "stream_test_util.h"
#include "wait_for.h"

using namespace navmap::ipc;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

constexpr unsigned long kGstBufferFlagDiscontBit = 0x40;  // GST_BUFFER_FLAG_DISCONT as fakesink prints flags
constexpr int kWidth = 96;
constexpr int kHeight = 48;
constexpr int kFps = 30;
constexpr std::int64_t kFramePeriodNs = 1'000'000'000 / kFps;

struct CommandResult {
    int exit_code = -1;
    std::string out;  ///< stdout and stderr together
};

/// Runs `command` through sh with a 60 s limit.
CommandResult runCommand(const std::string& command) {
    CommandResult r;
    FILE* p = popen(("timeout 60 " + command + " 2>&1").c_str(), "r");
    if (p == nullptr) {
        return r;
    }
    char buf[4096];
    std::size_t n = 0;
    while ((n = fread(buf, 1, sizeof(buf), p)) > 0) {
        r.out.append(buf, n);
    }
    const int status = pclose(p);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

bool haveProgram(const std::string& name) {
    return std::system(("command -v " + name + " >/dev/null 2>&1").c_str()) == 0;
}

/// Frame `seq`: every byte depends on x, y, the channel and seq (alpha too), so a wrong row, a
/// swapped channel, a premultiplied alpha or another frame shows.
std::vector<std::uint8_t> testFrame(std::uint64_t seq) {
    std::vector<std::uint8_t> px(static_cast<std::size_t>(kWidth) * kHeight * 4);
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            auto* p = &px[(static_cast<std::size_t>(y) * kWidth + x) * 4];
            p[0] = static_cast<std::uint8_t>(x * 2 + seq * 17);
            p[1] = static_cast<std::uint8_t>(y * 5 + seq * 29);
            p[2] = static_cast<std::uint8_t>((x ^ y) + seq * 7);
            p[3] = static_cast<std::uint8_t>(64 + ((x + y + seq) % 192));
        }
    }
    return px;
}

/// A PNG's RGBA bytes as stored (alpha not premultiplied); empty when it cannot be read.
std::vector<std::uint8_t> readPngRgba(const fs::path& path, int* width, int* height) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path.string(), &config);
    if (!in) {
        return {};
    }
    const auto& spec = in->spec();
    *width = spec.width;
    *height = spec.height;
    if (spec.nchannels != 4) {
        return {};
    }
    std::vector<std::uint8_t> px(static_cast<std::size_t>(spec.width) * spec.height * 4);
    if (!in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, px.data())) {
        return {};
    }
    return px;
}

std::size_t countFiles(const fs::path& dir) {
    std::error_code ec;
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        n += e.is_regular_file() ? 1 : 0;
    }
    return n;
}

class NavmapSrcTest : public ::testing::Test {
protected:
    void SetUp() override {
        for (const char* tool : {"gst-launch-1.0", "gst-inspect-1.0", "gst-discoverer-1.0"}) {
            if (!haveProgram(tool)) {
                GTEST_SKIP() << tool << " is not installed (gstreamer1.0-tools, gstreamer1.0-plugins-base-apps)";
            }
        }
        m_dir = fs::temp_directory_path() / ("navmapsrc-test-" + std::to_string(getpid()) + "-" +
                                             ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(m_dir);
        fs::create_directories(m_dir / "frames");
        // The plugin from the build tree; a registry of our own, never the one under $HOME.
        setenv("GST_PLUGIN_PATH", NAVMAP_GST_PLUGIN_DIR, 1);
        setenv("GST_REGISTRY", (m_dir / "registry.bin").c_str(), 1);
        m_socket = navmap::stream_test::uniqueSocketPath("gst");
    }
    void TearDown() override {
        if (!m_dir.empty()) fs::remove_all(m_dir);
    }

    std::unique_ptr<FrameServer> startServer(std::vector<RenderedProfile> rendered = {}) {
        FrameServerOptions o;
        o.unix_path = m_socket;
        o.tcp_port = 0;  // any free port: tcpPort()
        o.rendered_profiles = std::move(rendered);
        auto server = std::make_unique<FrameServer>(o);
        EXPECT_TRUE(server->start().ok());
        return server;
    }

    /// navmapsrc for the test profile (bird 96x48 at 30 fps) plus `extra` properties.
    std::string source(const std::string& extra = "") const {
        return "navmapsrc socket=" + m_socket + " profile=test width=" + std::to_string(kWidth) +
               " height=" + std::to_string(kHeight) + " view=bird fps=" + std::to_string(kFps) + " " + extra;
    }

    /// Waits for a client, then publishes frames first..last (render time seq periods after
    /// `t0_ns`, or render_time(seq)), each once the previous one has been handed out. False when a
    /// client or a hand-out does not come within 10 s.
    static bool publishFrames(FrameServer& server, std::uint64_t first, std::uint64_t last, std::int64_t t0_ns,
                              const std::function<std::int64_t(std::uint64_t)>& render_time = {}) {
        if (!navmap::test::waitFor([&] { return !server.activeProfiles().empty(); }, 10s)) {
            return false;
        }
        for (std::uint64_t seq = first; seq <= last; ++seq) {
            const auto sent = server.stats().frames_sent;
            const auto px = testFrame(seq);
            FrameView v;
            v.pixels = px.data();
            v.width = kWidth;
            v.height = kHeight;
            v.render_time_ns = render_time ? render_time(seq) : t0_ns + static_cast<std::int64_t>(seq) * kFramePeriodNs;
            if (server.publish("bird", v) == 0 ||
                !navmap::test::waitFor([&] { return server.stats().frames_sent > sent; }, 10s)) {
                return false;
            }
        }
        return true;
    }

    /// The saved PNGs must be frames first..last, in order, byte for byte.
    void expectSavedFrames(std::uint64_t first, std::uint64_t last) const {
        ASSERT_EQ(countFiles(m_dir / "frames"), last - first + 1);
        for (std::uint64_t seq = first; seq <= last; ++seq) {
            char name[32];
            std::snprintf(name, sizeof(name), "frame-%05d.png", static_cast<int>(seq - first));
            int w = 0;
            int h = 0;
            const auto png = readPngRgba(m_dir / "frames" / name, &w, &h);
            ASSERT_EQ(w, kWidth) << name;
            ASSERT_EQ(h, kHeight) << name;
            EXPECT_TRUE(png == testFrame(seq)) << name << " is not the published frame " << seq;
        }
    }

    std::string pngSink() const {
        return " ! videoconvert ! pngenc ! multifilesink location=" + (m_dir / "frames").string() + "/frame-%05d.png";
    }

    fs::path m_dir;
    std::string m_socket;
};

TEST_F(NavmapSrcTest, InspectIsClean) {
    // Its own registry, so the plugin is scanned here and stderr holds what that printed; no
    // system plugin beside it (what they print is not ours); a GLib warning or critical aborts.
    fs::create_directories(m_dir / "no-system-plugins");
    const auto r =
        runCommand("env G_DEBUG=fatal-warnings GST_PLUGIN_SYSTEM_PATH_1_0=" + (m_dir / "no-system-plugins").string() +
                   " gst-inspect-1.0 navmapsrc 2>" + (m_dir / "stderr.txt").string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    std::ifstream err(m_dir / "stderr.txt");
    const std::string stderr_text((std::istreambuf_iterator<char>(err)), std::istreambuf_iterator<char>());
    EXPECT_EQ(stderr_text, "");
    for (const char* expected : {"navmap frame source", "format: RGBA", "socket", "profile", "transport", "(0): shm",
                                 "(1): raw", "(2): zlib", "reconnect", "num-buffers"}) {
        EXPECT_NE(r.out.find(expected), std::string::npos) << expected << " missing in\n" << r.out;
    }
}

TEST_F(NavmapSrcTest, PngsArePublishedFramesByteForByteThenEosWhenTheServerStops) {
    // The Unix socket with each transport, and TCP (host and port) with zlib.
    for (const std::string transport : {"shm", "raw", "zlib", "tcp zlib"}) {
        SCOPED_TRACE(transport);
        fs::remove_all(m_dir / "frames");
        fs::create_directories(m_dir / "frames");
        auto server = startServer();
        const std::string where =
            transport.starts_with("tcp ")
                ? "host=127.0.0.1 port=" + std::to_string(server->tcpPort()) + " transport=" + transport.substr(4)
                : "transport=" + transport;
        auto launched = std::async(std::launch::async, runCommand, "gst-launch-1.0 " + source(where) + pngSink());
        ASSERT_TRUE(publishFrames(*server, 1, 5, 1'000'000'000));
        EXPECT_TRUE(navmap::test::waitFor([&] { return countFiles(m_dir / "frames") == 5; }, 10s));
        server.reset();  // navmapd stops: the stream ends, the pipeline gets EOS
        const auto r = launched.get();
        ASSERT_EQ(r.exit_code, 0) << r.out;
        EXPECT_NE(r.out.find("Got EOS from element"), std::string::npos) << r.out;
        expectSavedFrames(1, 5);
    }
}

TEST_F(NavmapSrcTest, Vp8WebmFileIsPlayable) {
    constexpr int kFrames = 30;
    auto server = startServer();
    const auto webm = m_dir / "out.webm";
    auto launched =
        std::async(std::launch::async, runCommand,
                   "gst-launch-1.0 " + source("num-buffers=" + std::to_string(kFrames)) +
                       " ! videoconvert ! vp8enc deadline=1 ! webmmux ! filesink location=" + webm.string());
    ASSERT_TRUE(publishFrames(*server, 1, kFrames, 0));
    const auto r = launched.get();
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto d = runCommand("gst-discoverer-1.0 " + webm.string());
    ASSERT_EQ(d.exit_code, 0) << d.out;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(d.out, m, std::regex(R"(Duration: (\d+):(\d+):(\d+\.\d+))"))) << d.out;
    const double seconds = std::stoi(m[1]) * 3600.0 + std::stoi(m[2]) * 60.0 + std::stod(m[3]);
    // 30 frames at 30 fps from their render times: 1 s, after the running time the first arrived at.
    EXPECT_GE(seconds, 0.99) << d.out;
    EXPECT_LE(seconds, 2.0) << d.out;
    const std::regex video_stream(R"(video #\d)");
    const auto videos =
        std::distance(std::sregex_iterator(d.out.begin(), d.out.end(), video_stream), std::sregex_iterator());
    EXPECT_EQ(videos, 1) << d.out;
    EXPECT_NE(d.out.find("Width: 96"), std::string::npos) << d.out;
    EXPECT_NE(d.out.find("Height: 48"), std::string::npos) << d.out;
    EXPECT_NE(d.out.find("VP8"), std::string::npos) << d.out;
}

TEST_F(NavmapSrcTest, TimestampsAreRenderTimesInRunningTime) {
    // Irregular render times (a second's gap after frame 3): the PTS follow them to the
    // nanosecond, not the arrival; the first PTS is the running time the first frame came at.
    const std::vector<std::int64_t> render_ns = {5'000'000'000, 5'040'000'000, 5'050'000'001, 6'050'000'001,
                                                 6'083'333'334};
    auto server = startServer();
    auto launched = std::async(std::launch::async, runCommand,
                               "gst-launch-1.0 -v " + source("num-buffers=5") + " ! fakesink silent=false");
    ASSERT_TRUE(publishFrames(*server, 1, 5, 0, [&](std::uint64_t seq) { return render_ns[seq - 1]; }));
    const auto r = launched.get();
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const std::regex chain(
        R"(chain .*pts: (\d+):(\d+):(\d+)\.(\d{9}), duration: 0:00:00\.033333333, offset: (\d+), offset_end: (\d+), flags: ([0-9a-f]+))");
    std::vector<std::int64_t> pts;
    for (auto it = std::sregex_iterator(r.out.begin(), r.out.end(), chain); it != std::sregex_iterator(); ++it) {
        const auto& m = *it;
        pts.push_back(((std::stoll(m[1]) * 60 + std::stoll(m[2])) * 60 + std::stoll(m[3])) * 1'000'000'000 +
                      std::stoll(m[4]));
        EXPECT_EQ(std::stoull(m[5]), pts.size() - 1) << m[0];
        EXPECT_EQ(std::stoull(m[6]), pts.size()) << m[0];
        const bool discont = (std::stoul(m[7], nullptr, 16) & kGstBufferFlagDiscontBit) != 0;
        EXPECT_EQ(discont, pts.size() == 1) << "DISCONT on the first buffer only: " << m[0];
    }
    ASSERT_EQ(pts.size(), 5U) << r.out;
    EXPECT_LT(pts[0], 5'000'000'000) << "the first frame's running time";
    for (std::size_t i = 1; i < pts.size(); ++i) {
        EXPECT_EQ(pts[i] - pts[0], render_ns[i] - render_ns[0]) << "frame " << i + 1;
    }
}

TEST_F(NavmapSrcTest, ErrorsSayWhatIsWrong) {
    const auto missing = runCommand("gst-launch-1.0 " + source() + " ! fakesink");
    EXPECT_NE(missing.exit_code, 0);
    EXPECT_NE(
        missing.out.find("Could not receive navmapd's frames: connect(" + m_socket + "): No such file or directory"),
        std::string::npos)
        << missing.out;

    const auto no_size = runCommand("gst-launch-1.0 navmapsrc socket=" + m_socket + " profile=test ! fakesink");
    EXPECT_NE(no_size.exit_code, 0);
    EXPECT_NE(no_size.out.find("profile test is not cluster, hud or center: it needs the properties width, height "
                               "and view"),
              std::string::npos)
        << no_size.out;

    auto server = startServer({{"center", "bird", 1280, 720}});
    const auto shm_over_tcp = runCommand(
        "gst-launch-1.0 " + source("host=127.0.0.1 port=" + std::to_string(server->tcpPort())) + " ! fakesink");
    EXPECT_NE(shm_over_tcp.exit_code, 0);
    EXPECT_NE(shm_over_tcp.out.find("payload shm needs the Unix socket"), std::string::npos) << shm_over_tcp.out;

    const auto refused = runCommand("gst-launch-1.0 " + source() + " ! fakesink");
    EXPECT_NE(refused.exit_code, 0);
    EXPECT_NE(refused.out.find("handshake refused by " + m_socket + ": handshake: bird 96x48 is not rendered here"),
              std::string::npos)
        << refused.out;
}

TEST_F(NavmapSrcTest, ReconnectCarriesOnAcrossAServerRestart) {
    auto launched = std::async(std::launch::async, runCommand,
                               "gst-launch-1.0 " + source("reconnect=true num-buffers=6") + pngSink());
    {
        auto first = startServer();
        ASSERT_TRUE(publishFrames(*first, 1, 3, 0));
        ASSERT_TRUE(navmap::test::waitFor([&] { return countFiles(m_dir / "frames") == 3; }, 10s));
    }  // stopped: the element reconnects with backoff instead of ending
    std::this_thread::sleep_for(300ms);
    auto second = startServer();
    ASSERT_TRUE(publishFrames(*second, 4, 6, 10'000'000'000));
    const auto r = launched.get();
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("No frames from navmapd, reconnecting"), std::string::npos) << r.out;
    expectSavedFrames(1, 6);
}

}  // namespace
