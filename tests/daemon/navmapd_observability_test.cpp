// SPDX-License-Identifier: Apache-2.0
// navmapd as an HMI integrator sees it from outside (no-op renderer: the daemon's own behaviour):
// /metrics is valid Prometheus text (parsed by the Prometheus client library's parser: each
// family once, base units), the version is in get_status and /status, frames are routed by
// profile (two profiles of one view and size are two streams), and a profile with `attribution`
// carries "© OpenStreetMap contributors" in its bottom right corner.
#include <gtest/gtest.h>

#include <poll.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/control/control_client.h"
#include "navmap/version.h"
#include "navmapd_process.h"
#include "stream_test_util.h"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using navmap::stream_test::freeTcpPort;
using navmap::stream_test::httpGet;

// The first `want` bytes of GET `path` (a stream that never ends), or what came within 5 s.
std::string httpHead(int port, const std::string& path, std::size_t want) {
    const int fd = navmap::stream_test::connectTcpRaw(port);
    std::string out;
    if (fd >= 0 && navmap::stream_test::sendAllRaw(
                       fd, "GET " + path + " HTTP/1.0\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\n\r\n")) {
        char buf[65536];
        pollfd p{fd, POLLIN, 0};
        const auto deadline = std::chrono::steady_clock::now() + 5s;
        while (out.size() < want && std::chrono::steady_clock::now() < deadline && ::poll(&p, 1, 1000) > 0) {
            const ssize_t r = ::recv(fd, buf, sizeof buf, 0);
            if (r <= 0) break;
            out.append(buf, static_cast<std::size_t>(r));
        }
    }
    if (fd >= 0) ::close(fd);
    return out;
}

std::string body(const std::string& response) {
    const auto at = response.find("\r\n\r\n");
    return at == std::string::npos ? std::string() : response.substr(at + 4);
}

struct ProgramRun {
    int status = -1;
    std::string out;
};

ProgramRun run(const std::string& cmd) {
    ProgramRun r;
    FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
    if (p == nullptr) return r;
    char buf[4096];
    std::size_t n = 0;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
    const int st = ::pclose(p);
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    return r;
}

// Two bird's-eye profiles of the same size, one with the attribution and one without: the same
// stream before frames were routed by profile.
class NavmapdObservability : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / ("navmapd-observability-" + std::to_string(::getpid()));
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
        navmap::test::writeStandingLog(m_dir / "standing.candump");
        m_port = freeTcpPort();
        std::ofstream(m_dir / "navmapd.toml")
            << "[input]\nsource = \"replay\"\nreplay_log = \"" << (m_dir / "standing.candump").string()
            << "\"\n[[profile]]\nname = \"plain\"\nwidth = 320\nheight = 180\nview = \"bird\"\n"
               "attribution = false\n"
               "[[profile]]\nname = \"credited\"\nwidth = 320\nheight = 180\nview = \"bird\"\n"
               "attribution = true\n"
               "[control]\nsocket = \""
            << (m_dir / "control.sock").string() << "\"\n[stream]\nsocket = \"" << (m_dir / "frames.sock").string()
            << "\"\nhttp_port = " << m_port << "\n";
        m_daemon = std::make_unique<navmap::test::NavmapdProcess>(
            NAVMAPD_PATH, "--noop --config " + (m_dir / "navmapd.toml").string(), m_dir / "navmapd.log",
            m_dir / "frames.sock");
        ASSERT_TRUE(fs::exists(m_dir / "frames.sock")) << m_daemon->output();
    }
    void TearDown() override {
        m_daemon.reset();
        fs::remove_all(m_dir);
    }
    navmap::ipc::StreamRequest request(const std::string& name) const {
        navmap::ipc::StreamRequest r;
        r.profile.name = name;
        r.profile.width = 320;
        r.profile.height = 180;
        r.profile.view = "bird";
        return r;
    }
    // get_status over the control socket, parsed; a discarded value (and a failed test) when the
    // request or the reply is broken.
    nlohmann::json getStatus() {
        auto control = navmap::ipc::ControlClient::connect((m_dir / "control.sock").string());
        if (!control.ok()) {
            ADD_FAILURE() << control.error().message;
            return nlohmann::json::value_t::discarded;
        }
        auto reply = control.value().request(R"({"cmd":"get_status"})", 5s);
        if (!reply.ok()) {
            ADD_FAILURE() << reply.error().message;
            return nlohmann::json::value_t::discarded;
        }
        auto j = nlohmann::json::parse(reply.value(), nullptr, false);
        if (!j.is_object()) ADD_FAILURE() << "get_status: " << reply.value();
        return j;
    }

    fs::path m_dir;
    int m_port = 0;
    std::unique_ptr<navmap::test::NavmapdProcess> m_daemon;
};

// Pixels of the bottom right 200x24 corner that differ from the frame's top left pixel (the
// no-op renderer's sky), and of those the light ones (text).
struct Corner {
    int changed = 0;
    int light = 0;
};
Corner corner(const navmap::ipc::ReceivedFrame& f) {
    Corner c;
    const std::uint8_t* sky = f.pixels.data();
    for (std::uint32_t y = f.header.height - 24; y < f.header.height; ++y) {
        for (std::uint32_t x = f.header.width - 200; x < f.header.width; ++x) {
            const std::uint8_t* p = f.pixels.data() + y * f.header.stride + x * 4;
            if (p[0] != sky[0] || p[1] != sky[1] || p[2] != sky[2]) ++c.changed;
            if (p[0] > 170 && p[1] > 170 && p[2] > 170) ++c.light;
        }
    }
    return c;
}

}  // namespace

TEST_F(NavmapdObservability, ProfilesOfOneViewAndSizeAreTwoStreamsAndTheAttributionIsDrawn) {
    auto plain = navmap::ipc::StreamClient::connectUnix((m_dir / "frames.sock").string(), request("plain"));
    auto credited = navmap::ipc::StreamClient::connectUnix((m_dir / "frames.sock").string(), request("credited"));
    ASSERT_TRUE(plain.ok()) << plain.error().message;
    ASSERT_TRUE(credited.ok()) << credited.error().message;
    navmap::ipc::ReceivedFrame f;
    int plain_frames = 0;
    int credited_frames = 0;
    Corner credit;
    const auto until = std::chrono::steady_clock::now() + 20s;
    while ((plain_frames < 15 || credited_frames < 15) && std::chrono::steady_clock::now() < until) {
        for (auto* c : {plain.value().get(), credited.value().get()}) {
            auto r = c->next(f, 200ms);
            ASSERT_TRUE(r.ok()) << r.error().message << "\n" << m_daemon->output();
            if (!r.value()) continue;
            const Corner k = corner(f);
            if (c == plain.value().get()) {
                // Never a frame of the other profile: its corner is the sky, untouched.
                ASSERT_EQ(k.changed, 0) << "the plain profile got a frame with the attribution (sequence "
                                        << f.header.sequence << ")";
                ++plain_frames;
            } else {
                ASSERT_GT(k.changed, 1000) << "the credited profile's frame " << f.header.sequence << " has no box";
                ASSERT_GT(k.light, 40) << "no text in the box";
                credit = k;
                ++credited_frames;
            }
        }
    }
    EXPECT_GE(plain_frames, 15) << m_daemon->output();
    EXPECT_GE(credited_frames, 15) << m_daemon->output();
    std::printf("attribution corner: %d pixels changed, %d light (text)\n", credit.changed, credit.light);
    // The rest of the credited frame is the sky.
    EXPECT_EQ(f.pixels[(10 * f.header.width + 10) * 4], f.pixels[0]);
}

TEST_F(NavmapdObservability, MetricsParseAsPrometheusTextEachFamilyOnceInBaseUnits) {
    // A client on each profile, so that the stream families have clients and frames.
    auto plain = navmap::ipc::StreamClient::connectUnix((m_dir / "frames.sock").string(), request("plain"));
    ASSERT_TRUE(plain.ok()) << plain.error().message;
    navmap::ipc::ReceivedFrame f;
    for (int i = 0; i < 50 && plain.value()->stats().frames < 10; ++i) ASSERT_TRUE(plain.value()->next(f, 200ms).ok());
    std::this_thread::sleep_for(1200ms);  // the daemon's families are refreshed every second
    const std::string response = httpGet(m_port, "/metrics");
    ASSERT_EQ(response.rfind("HTTP/1.0 200 OK\r\n", 0), 0U) << response;
    const std::string text = body(response);
    const fs::path file = m_dir / "metrics.txt";
    std::ofstream(file) << text;
    const ProgramRun check = run("/usr/bin/python3 " NAVMAP_CHECK_METRICS " " + file.string());
    if (check.status == 77) GTEST_SKIP() << check.out;
    EXPECT_EQ(check.status, 0) << check.out << "\n" << text;
    std::printf("%s", check.out.substr(0, check.out.find('\n') + 1).c_str());
    // The daemon's and the server's families are both there, in seconds and bytes.
    for (const char* family :
         {"navmap_frame_seconds summary", "navmap_latency_seconds summary", "navmap_stream_frames_sent counter",
          "navmap_stream_clients gauge", "navmap_process_resident_bytes gauge", "navmap_build_info gauge"}) {
        EXPECT_NE(check.out.find(std::string("\n") + family + " "), std::string::npos) << family << "\n" << check.out;
    }
    EXPECT_NE(text.find("navmap_build_info{version=\"" NAVMAP_VERSION "\"} 1\n"), std::string::npos) << text;
    EXPECT_NE(text.find("navmap_frames_published_total{profile=\"plain\"} "), std::string::npos) << text;
}

// A presence and format check, not a timing assertion: the time from the exec to a profile's
// first published frame is in /metrics and get_status once it has one, and absent (null) for a
// profile nobody watched, which has published none.
TEST_F(NavmapdObservability, TheFirstFrameTimeOfEachProfileIsInMetricsAndGetStatus) {
    auto plain = navmap::ipc::StreamClient::connectUnix((m_dir / "frames.sock").string(), request("plain"));
    ASSERT_TRUE(plain.ok()) << plain.error().message;
    navmap::ipc::ReceivedFrame f;
    bool got = false;
    for (int i = 0; i < 50 && !got; ++i) {
        auto r = plain.value()->next(f, 200ms);
        ASSERT_TRUE(r.ok()) << r.error().message;
        got = r.value();
    }
    ASSERT_TRUE(got) << m_daemon->output();
    std::this_thread::sleep_for(1200ms);  // the daemon's families are refreshed every second
    const std::string text = body(httpGet(m_port, "/metrics"));
    EXPECT_NE(text.find("# TYPE navmap_first_frame_seconds gauge\n"), std::string::npos) << text;
    const std::string key = "navmap_first_frame_seconds{profile=\"plain\"} ";
    const auto at = text.find(key);
    ASSERT_NE(at, std::string::npos) << text;
    const double seconds = std::stod(text.substr(at + key.size()));
    EXPECT_GT(seconds, 0.0);
    EXPECT_LT(seconds, 60.0);  // generous: a plausibility bound, not a speed target
    EXPECT_EQ(text.find("navmap_first_frame_seconds{profile=\"credited\"}"), std::string::npos) << text;

    const nlohmann::json j = getStatus();
    ASSERT_TRUE(j.is_object());
    const auto& profiles = j["status"]["profiles"];
    ASSERT_EQ(profiles.size(), 2U) << j.dump();
    EXPECT_EQ(profiles[0]["name"], "plain");
    ASSERT_TRUE(profiles[0]["first_frame_s"].is_number()) << j.dump();
    EXPECT_NEAR(profiles[0]["first_frame_s"].get<double>(), seconds, 1e-3);
    EXPECT_TRUE(profiles[1]["first_frame_s"].is_null()) << j.dump();
}

// Where a profile's frame time goes: every frame's select/render/publish, and the renderer's
// passes of the sampled frames (one in 30), in get_status and as navmap_pass_seconds.
TEST_F(NavmapdObservability, PerPassTimesOfEachProfileAreInGetStatusAndMetrics) {
    auto plain = navmap::ipc::StreamClient::connectUnix((m_dir / "frames.sock").string(), request("plain"));
    ASSERT_TRUE(plain.ok()) << plain.error().message;
    navmap::ipc::ReceivedFrame f;
    // Enough frames that at least two had their passes timed.
    for (int i = 0; i < 300 && plain.value()->stats().frames < 70; ++i) {
        ASSERT_TRUE(plain.value()->next(f, 200ms).ok());
    }
    ASSERT_GE(plain.value()->stats().frames, 70U) << m_daemon->output();
    std::this_thread::sleep_for(1200ms);  // the daemon's families are refreshed every second
    const nlohmann::json j = getStatus();
    ASSERT_TRUE(j.is_object());
    const auto& p = j["status"]["profiles"][0];
    ASSERT_EQ(p["name"], "plain");
    EXPECT_GE(p["passes_sampled"].get<int>(), 2) << j.dump();
    const auto& passes = p["passes"];
    for (const char* name :
         {"select", "render", "publish", "uploads", "terrain", "roads", "route", "labels", "marker", "other"}) {
        ASSERT_TRUE(passes.contains(name)) << name << ": " << passes.dump();
        EXPECT_GE(passes[name]["p50_ms"].get<double>(), 0.0) << name;
        EXPECT_LE(passes[name]["p50_ms"].get<double>(), passes[name]["p99_ms"].get<double>()) << name;
    }
    // This daemon's renderer is the no-op one: its passes take no time, the daemon's own steps
    // do (navmapd_e2e_test checks the GL renderer's passes).
    EXPECT_GE(passes["render"]["samples"].get<int>(), 70) << passes.dump();
    EXPECT_GT(passes["select"]["p99_ms"].get<double>(), 0.0) << passes.dump();
    EXPECT_GT(passes["publish"]["p99_ms"].get<double>(), 0.0) << passes.dump();
    EXPECT_EQ(passes["terrain"]["samples"].get<int>(), p["passes_sampled"].get<int>()) << passes.dump();

    const std::string text = body(httpGet(m_port, "/metrics"));
    EXPECT_NE(text.find("# TYPE navmap_pass_seconds gauge\n"), std::string::npos) << text;
    const std::string key = "navmap_pass_seconds{pass=\"select\",profile=\"plain\",quantile=\"0.99\"} ";
    const auto at = text.find(key);
    ASSERT_NE(at, std::string::npos) << text;
    EXPECT_GT(std::stod(text.substr(at + key.size())), 0.0);
    EXPECT_NE(text.find("navmap_pass_seconds{pass=\"terrain\",profile=\"plain\",quantile=\"0.5\"} "),
              std::string::npos);
}

TEST_F(NavmapdObservability, TheVersionIsInGetStatusAndStatus) {
    std::this_thread::sleep_for(1200ms);
    const nlohmann::json j = getStatus();
    ASSERT_TRUE(j.is_object());
    EXPECT_EQ(j["status"]["version"], NAVMAP_VERSION) << j.dump();
    const auto status = nlohmann::json::parse(body(httpGet(m_port, "/status")), nullptr, false);
    ASSERT_TRUE(status.is_object());
    EXPECT_EQ(status["daemon"]["version"], NAVMAP_VERSION);
    EXPECT_EQ(status["daemon"]["profiles"][1]["attribution"], true);
    EXPECT_EQ(status["daemon"]["profiles"][0]["attribution"], false);
}

// The live page's stream without ?profile= is the first configured profile: it streams JPEG
// frames instead of answering 400 for a profile navmapd does not render, and the page asks for it.
TEST_F(NavmapdObservability, TheDefaultMjpegStreamIsTheFirstProfile) {
    const std::string stream = httpHead(m_port, "/stream.mjpg", 4096);
    ASSERT_EQ(stream.rfind("HTTP/1.0 200 OK\r\n", 0), 0U) << stream.substr(0, 400) << "\n" << m_daemon->output();
    EXPECT_NE(stream.find("multipart/x-mixed-replace"), std::string::npos) << stream.substr(0, 400);
    const auto part = stream.find("Content-Type: image/jpeg\r\n");
    ASSERT_NE(part, std::string::npos) << stream.substr(0, 400);
    const auto jpeg = stream.find("\r\n\r\n", part);
    ASSERT_NE(jpeg, std::string::npos);
    ASSERT_GE(stream.size(), jpeg + 6);
    EXPECT_EQ(static_cast<unsigned char>(stream[jpeg + 4]), 0xFF);  // SOI marker
    EXPECT_EQ(static_cast<unsigned char>(stream[jpeg + 5]), 0xD8);
    // The page names the same stream and a button per configured profile.
    const std::string page = body(httpGet(m_port, "/"));
    EXPECT_NE(page.find("show('plain')"), std::string::npos) << page.substr(0, 2000);
    EXPECT_NE(page.find("show('credited')"), std::string::npos);
    EXPECT_EQ(page.find("show('center')"), std::string::npos) << "a button for a profile navmapd does not render";
    EXPECT_NE(page.find("OpenStreetMap contributors"), std::string::npos);
    // A profile navmapd does not render is still refused, naming it.
    const std::string refused = httpGet(m_port, "/stream.mjpg?profile=bird");
    EXPECT_EQ(refused.rfind("HTTP/1.0 4", 0), 0U) << refused.substr(0, 400);
}

// docs/frame-protocol.md "dma-buf frames": navmapd reports its renderer's dma-buf probe in
// get_status, refuses a request for dma-buf frames naming it, and a client that allows the
// fallback gets the profile's frames through shared memory.
TEST_F(NavmapdObservability, DmabufFramesAreRefusedWithTheProbesReasonAndShmServesThem) {
    std::this_thread::sleep_for(1200ms);
    const nlohmann::json j = getStatus();
    ASSERT_TRUE(j.is_object());
    const nlohmann::json want = {
        {"available", false}, {"native_fence_sync", false}, {"reason", "the no-op renderer draws into no GPU buffers"}};
    EXPECT_EQ(j["status"]["dmabuf"], want) << j.dump();
    const std::string sock = (m_dir / "frames.sock").string();
    navmap::ipc::StreamRequest r = request("plain");
    r.payload = navmap::ipc::StreamPayload::Dmabuf;
    auto refused = navmap::ipc::StreamClient::connectUnix(sock, r, 5s);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().message, "handshake refused by " + sock +
                                           ": handshake: dmabuf frames are not available here (the no-op renderer "
                                           "draws into no GPU buffers); ask for shm");
    r.dmabuf_fallback_shm = true;
    auto c = navmap::ipc::StreamClient::connectUnix(sock, r, 5s);
    ASSERT_TRUE(c.ok()) << c.error().message;
    EXPECT_EQ(c.value()->payload(), navmap::ipc::StreamPayload::Shm);
    EXPECT_EQ(c.value()->fallbackReason(), refused.error().message);
    navmap::ipc::ReceivedFrame f;
    auto got = c.value()->next(f, 10s);
    ASSERT_TRUE(got.ok()) << got.error().message;
    ASSERT_TRUE(got.value()) << "no frame within 10 s";
    EXPECT_EQ(f.header.width, 320U);
    EXPECT_EQ(f.pixels.size(), 320U * 180U * 4U);
}
