// SPDX-License-Identifier: Apache-2.0
// navmapsrc end to end: the test process runs a FrameServer and publishes known frames, one at a
// time (the next only once the previous one is handed out, so none is dropped); gst-launch-1.0
// runs the element from the build tree (GST_PLUGIN_PATH) with a registry in a temporary folder.
// Checked: the PNGs of multifilesink byte for byte against the published pixels, a VP8/WebM file
// by gst-discoverer-1.0, gst-inspect-1.0 without a warning, EOS when the server stops, the error
// messages, and reconnect=true across a server restart. Pipelines in the test process (appsink)
// check every field of each buffer's GstNavmapFrameMeta against the validity and metadata block
// published with its frame; gst-launch-1.0 -m the element messages of post-messages=true.

#include <OpenImageIO/imageio.h>
#include <gst/app/gstappsink.h>
#include <gst/gst.h>
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
#include <optional>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "navmap/gst/navmap_frame_meta.h"
#include "navmap/ipc/client/frame_meta.h"
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

/// Frame `seq`'s validity: 1 fresh, 2 stale_pose without any pose yet, 3 degraded (two reasons) and
/// off_route, 4 stale_pose with an age, 5 none (a server from before validity).
FrameValidity testValidity(std::uint64_t seq) {
    FrameValidity v;
    v.version = kFrameValidityVersion;
    v.pose_age_ms = static_cast<std::uint32_t>(20 + seq);
    switch (seq) {
        case 2:
            v.flags = kValidityStalePose;
            v.pose_age_ms = kPoseAgeNone;
            break;
        case 3:
            v.flags = kValidityDegraded | kValidityOffRoute;
            v.degraded = kDegradedTilesMissing | kDegradedRoadGraphOff;
            break;
        case 4:
            v.flags = kValidityStalePose;
            v.pose_age_ms = 1500;
            break;
        case 5: v = {}; break;
        default: break;
    }
    return v;
}

/// Frame `seq`'s metadata block: every field known on 1 and 3 (other values), nothing known on 2,
/// none on 4 and 5.
std::optional<FrameMeta> testBlock(std::uint64_t seq) {
    FrameMeta m;
    if (seq == 2) {
        return m;
    }
    if (seq != 1 && seq != 3) {
        return std::nullopt;
    }
    const double k = static_cast<double>(seq);
    m.has_pose = true;
    m.lat_deg = 42.5 + k * 0.25;  // binary fractions: printed as written
    m.lon_deg = 1.5 - k * 0.125;
    m.heading_deg = 90.25 * k;
    m.pose_time_ns = 1764691200123456789LL + static_cast<std::int64_t>(seq);
    m.has_next = true;
    m.next_type = seq == 1 ? 12 : 3;  // roundabout, turn_left
    m.next_exit = seq == 1 ? 3 : 0;
    m.next_distance_m = 187.5 * k;
    m.next_street = seq == 1 ? "Avinguda de Tarragona" : "Carrer Major";
    m.lanes_known = true;
    m.lanes =
        seq == 1 ? std::vector<std::uint8_t>{kLaneLeft, kLaneStraight | kLaneRecommended, kLaneRight | kLaneSlightRight}
                 : std::vector<std::uint8_t>{kLaneLeft | kLaneRecommended};
    m.has_remaining = true;
    m.remaining_m = 4213.25 * k;
    m.remaining_s = 431.5 * k;
    m.current_street = seq == 1 ? "Carrer Prat de la Creu" : "CG-1";
    m.speed_limit_kmh = static_cast<std::uint16_t>(40 + 10 * seq);
    return m;
}

/// `m` must hold frame `seq`'s validity and, when `with_block`, its metadata block; no meta at all
/// for a frame with neither.
void expectFrameMeta(const GstNavmapFrameMeta* m, std::uint64_t seq, bool with_block) {
    SCOPED_TRACE("frame " + std::to_string(seq));
    const auto v = testValidity(seq);
    const auto block = with_block ? testBlock(seq) : std::nullopt;
    if (!v.known() && !block) {
        EXPECT_EQ(m, nullptr) << "a frame without validity or block carries no meta";
        return;
    }
    ASSERT_NE(m, nullptr);
    EXPECT_EQ(m->sequence, seq);
    EXPECT_EQ(m->validity_known, v.known() ? TRUE : FALSE);
    EXPECT_EQ(m->flags, v.flags);
    EXPECT_EQ(m->degraded, v.degraded);
    EXPECT_EQ(m->pose_age_ms, v.pose_age_ms);
    ASSERT_NE(m->next_type, nullptr);
    ASSERT_NE(m->next_street, nullptr);
    ASSERT_NE(m->current_street, nullptr);
    EXPECT_EQ(m->has_block, block ? TRUE : FALSE);
    const FrameMeta b = block.value_or(FrameMeta{});
    EXPECT_EQ(m->has_pose, b.has_pose ? TRUE : FALSE);
    EXPECT_EQ(m->lat_deg, b.lat_deg);
    EXPECT_EQ(m->lon_deg, b.lon_deg);
    EXPECT_EQ(m->heading_deg, b.heading_deg);
    EXPECT_EQ(m->pose_time_ns, b.pose_time_ns);
    EXPECT_EQ(m->has_next, b.has_next ? TRUE : FALSE);
    EXPECT_STREQ(m->next_type, b.has_next ? metaManeuverName(b.next_type) : "");
    EXPECT_EQ(m->next_exit, b.next_exit);
    EXPECT_EQ(m->next_distance_m, b.next_distance_m);
    EXPECT_STREQ(m->next_street, b.next_street.c_str());
    EXPECT_EQ(m->lane_count, b.lanes_known ? static_cast<int>(b.lanes.size()) : -1);
    for (std::size_t i = 0; i < b.lanes.size(); ++i) {
        EXPECT_EQ(m->lanes[i], b.lanes[i]) << "lane " << i;
    }
    EXPECT_EQ(m->has_remaining, b.has_remaining ? TRUE : FALSE);
    EXPECT_EQ(m->remaining_m, b.remaining_m);
    EXPECT_EQ(m->remaining_s, b.remaining_s);
    EXPECT_STREQ(m->current_street, b.current_street.c_str());
    EXPECT_EQ(m->speed_limit_kmh, b.speed_limit_kmh);
}

/// The buffer's bytes, mapped for reading.
std::vector<std::uint8_t> bufferBytes(GstBuffer* buffer) {
    GstMapInfo map;
    if (!gst_buffer_map(buffer, &map, GST_MAP_READ)) {
        return {};
    }
    std::vector<std::uint8_t> bytes(map.data, map.data + map.size);
    gst_buffer_unmap(buffer, &map);
    return bytes;
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
    /// client or a hand-out does not come within 10 s. `annotate`: each frame with testValidity()
    /// and testBlock() of its sequence.
    static bool publishFrames(FrameServer& server, std::uint64_t first, std::uint64_t last, std::int64_t t0_ns,
                              const std::function<std::int64_t(std::uint64_t)>& render_time = {},
                              bool annotate = false) {
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
            if (annotate) {
                v.validity = testValidity(seq);
                if (auto block = testBlock(seq)) {
                    v.meta = std::make_shared<const std::vector<std::uint8_t>>(encodeFrameMeta(*block));
                }
            }
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

    /// Runs `launch` (an appsink named sink at its end) in this process while frames 1..count are
    /// published with testValidity() and testBlock(); the buffers the appsink got (the caller
    /// unrefs them).
    std::vector<GstBuffer*> pullAnnotatedFrames(const std::string& launch, std::uint64_t count) {
        gst_init(nullptr, nullptr);  // GST_PLUGIN_PATH and GST_REGISTRY are set: the plugin of the build tree
        std::vector<GstBuffer*> buffers;
        GError* error = nullptr;
        GstElement* pipeline = gst_parse_launch(launch.c_str(), &error);
        if (pipeline == nullptr || error != nullptr) {
            ADD_FAILURE() << launch << ": " << (error != nullptr ? error->message : "no pipeline");
            g_clear_error(&error);
            if (pipeline != nullptr) gst_object_unref(pipeline);
            return buffers;
        }
        GstElement* sink = gst_bin_get_by_name(GST_BIN(pipeline), "sink");
        auto server = startServer();
        auto published = std::async(std::launch::async, [&] { return publishFrames(*server, 1, count, 0, {}, true); });
        EXPECT_NE(gst_element_set_state(pipeline, GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
        for (std::uint64_t i = 0; i < count; ++i) {
            GstSample* sample = gst_app_sink_try_pull_sample(GST_APP_SINK(sink), 10 * GST_SECOND);
            if (sample == nullptr) {
                ADD_FAILURE() << "no buffer " << i + 1 << " of " << count;
                break;
            }
            buffers.push_back(gst_buffer_ref(gst_sample_get_buffer(sample)));
            gst_sample_unref(sample);
        }
        EXPECT_TRUE(published.get());
        gst_element_set_state(pipeline, GST_STATE_NULL);
        gst_object_unref(sink);
        gst_object_unref(pipeline);
        return buffers;
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
                                 "(1): raw", "(2): zlib", "reconnect", "meta", "post-messages", "num-buffers"}) {
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

TEST_F(NavmapSrcTest, EachBufferCarriesItsFramesValidityAndMetadataBlock) {
    constexpr std::uint64_t kFrames = 5;
    // Straight into the appsink (pixels checked too), through videoconvert in passthrough, and
    // through a real conversion (the meta is copied onto the new buffer).
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"transport=shm", " ! appsink name=sink sync=false"},
        {"transport=raw", " ! videoconvert ! appsink name=sink sync=false"},
        {"transport=zlib", " ! videoconvert ! video/x-raw,format=BGRx ! appsink name=sink sync=false"},
    };
    for (const auto& [transport, tail] : cases) {
        SCOPED_TRACE(transport + tail);
        auto buffers = pullAnnotatedFrames(source(transport) + tail, kFrames);
        ASSERT_EQ(buffers.size(), kFrames);
        for (std::uint64_t seq = 1; seq <= kFrames; ++seq) {
            GstBuffer* b = buffers[seq - 1];
            expectFrameMeta(gst_buffer_get_navmap_frame_meta(b), seq, true);
            if (tail.find("BGRx") == std::string::npos) {
                EXPECT_TRUE(bufferBytes(b) == testFrame(seq)) << "frame " << seq << ": pixels changed";
            }
        }
        // A copy (what an element that writes into a buffer it does not own makes) has its own
        // meta with the same fields; the original's strings are not shared.
        GstBuffer* copy = gst_buffer_copy(buffers[0]);
        const auto* original = gst_buffer_get_navmap_frame_meta(buffers[0]);
        const auto* copied = gst_buffer_get_navmap_frame_meta(copy);
        expectFrameMeta(copied, 1, true);
        ASSERT_NE(copied, nullptr);
        EXPECT_NE(copied, original);
        EXPECT_NE(copied->next_street, original->next_street);
        for (GstBuffer* b : buffers) gst_buffer_unref(b);
        gst_buffer_unref(copy);  // freeing both: no string freed twice
    }
}

TEST_F(NavmapSrcTest, WithoutTheBlockTheMetaHoldsTheValidityOnly) {
    // meta=false: the server has blocks, the element does not ask for them.
    auto buffers = pullAnnotatedFrames(source("meta=false") + " ! appsink name=sink sync=false", 5);
    ASSERT_EQ(buffers.size(), 5U);
    for (std::uint64_t seq = 1; seq <= 5; ++seq) {
        const auto* m = gst_buffer_get_navmap_frame_meta(buffers[seq - 1]);
        expectFrameMeta(m, seq, false);
        if (seq == 2 || seq == 4) {
            ASSERT_NE(m, nullptr);
            EXPECT_EQ(m->flags, GST_NAVMAP_VALID_STALE_POSE) << "frame " << seq;
        }
    }
    for (GstBuffer* b : buffers) gst_buffer_unref(b);
}

TEST_F(NavmapSrcTest, PostMessagesShowTheFieldsInGstLaunch) {
    auto server = startServer();
    auto launched = std::async(std::launch::async, runCommand,
                               "gst-launch-1.0 -m " + source("post-messages=true num-buffers=5") + " ! fakesink");
    ASSERT_TRUE(publishFrames(*server, 1, 5, 0, {}, true));
    const auto r = launched.get();
    ASSERT_EQ(r.exit_code, 0) << r.out;
    std::vector<std::string> messages;
    const std::regex message(R"(Got message #\d+ from element "navmapsrc0" \(element\): (navmap-frame, [^\n]*))");
    for (auto it = std::sregex_iterator(r.out.begin(), r.out.end(), message); it != std::sregex_iterator(); ++it) {
        messages.push_back((*it)[1]);
    }
    ASSERT_EQ(messages.size(), 5U) << r.out;
    const std::vector<std::vector<std::string>> expected = {
        {"sequence=(guint64)1,", "validity=(string)fresh,", "pose-age-ms=(uint)21,", "meta=(boolean)true,",
         "lat=(double)42.75,", "lon=(double)1.375,", "heading=(double)90.25,",
         "pose-time-ns=(gint64)1764691200123456790,", "next-type=(string)roundabout,", "next-exit=(int)3,",
         "next-distance-m=(double)187.5,", R"x(next-street=(string)"Avinguda\ de\ Tarragona")x",
         "lanes=(string)\"01\\,84\\,18\"", "remaining-m=(double)4213.25,", "remaining-s=(double)431.5,",
         R"x(street=(string)"Carrer\ Prat\ de\ la\ Creu")x", "speed-limit-kmh=(uint)50;"},
        {"sequence=(guint64)2,", "validity=(string)stale_pose,", "pose-age-ms=(uint)4294967295,", "meta=(boolean)true,",
         "lanes=(string)unknown,", "street=(string)\"\"", "speed-limit-kmh=(uint)0;"},
        {"sequence=(guint64)3,", "validity=(string)degraded+off_route,",
         "degraded=(string)tiles_missing+road_graph_off,", "next-type=(string)turn_left,", "lanes=(string)81,",
         "street=(string)CG-1,", "speed-limit-kmh=(uint)70;"},
        {"sequence=(guint64)4,", "validity=(string)stale_pose,", "pose-age-ms=(uint)1500,", "meta=(boolean)false;"},
    };
    for (std::size_t i = 0; i < expected.size(); ++i) {
        for (const auto& field : expected[i]) {
            EXPECT_NE(messages[i].find(field), std::string::npos) << field << " missing in\n" << messages[i];
        }
    }
    EXPECT_EQ(messages[1].find("lat="), std::string::npos) << "no pose: no pose fields\n" << messages[1];
    EXPECT_EQ(messages[1].find("next-type="), std::string::npos) << messages[1];
    EXPECT_EQ(messages[3].find("street="), std::string::npos) << "no block: no block fields\n" << messages[3];
    // Frame 5 has neither validity nor a block: no meta, so the message says it knows nothing.
    EXPECT_NE(messages[4].find("sequence=(guint64)5,"), std::string::npos) << messages[4];
    EXPECT_NE(messages[4].find("validity=(string)unknown,"), std::string::npos) << messages[4];
}

}  // namespace
