// SPDX-License-Identifier: Apache-2.0
// End to end: navmapd with a replayed drive, a cluster client and a HUD client on the shared-memory
// stream, the control socket, and a graceful stop (issue: frame streaming and the daemon).
#include <gtest/gtest.h>

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "dmabuf_import.h"
#include "golden.h"
#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/control/control_client.h"
#include "navmapd_process.h"
#include "wait_for.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

std::int64_t nowNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
        .count();
}

using navmap::test::writeStandingLog;

struct Daemon {
    pid_t pid = -1;
    fs::path dir, log;
    // `env`: NAME=value assignments for navmapd's environment (empty: none).
    explicit Daemon(const std::string& env = "") {
        dir = fs::temp_directory_path() / ("navmapd-e2e-" + std::to_string(::getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir);
        log = dir / "navmapd.log";
        writeStandingLog(dir / "standing.candump");
        const std::string cmd = (env.empty() ? "" : "env " + env + " ") + std::string(NAVMAPD_PATH) + " --replay " +
                                (dir / "standing.candump").string() + " --control-socket " +
                                (dir / "control.sock").string() + " --frame-socket " + (dir / "frames.sock").string() +
                                " --http-port 0 --profiles cluster,hud --log-level info" +
                                // Labels fade in with wall-clock time: off, so the golden frame is deterministic
                                // (their rendering has its own tests in tests/render).
                                " --no-labels" + " > " + log.string() + " 2>&1";
        const char* argv[] = {"/bin/sh", "-c", cmd.c_str(), nullptr};
        // exec so that the pid is navmapd's own (SIGTERM goes to it, not to the shell).
        const std::string exec_cmd = "exec " + cmd;
        argv[2] = exec_cmd.c_str();
        posix_spawn(&pid, "/bin/sh", nullptr, nullptr, const_cast<char**>(argv), environ);
        for (int i = 0; i < 200 && !fs::exists(dir / "frames.sock"); ++i) std::this_thread::sleep_for(50ms);
    }
    int stop() {
        if (pid <= 0) return -1;
        ::kill(pid, SIGTERM);
        int status = 0;
        for (int i = 0; i < 100; ++i) {
            if (::waitpid(pid, &status, WNOHANG) == pid) {
                pid = -1;
                return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
            }
            std::this_thread::sleep_for(50ms);
        }
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &status, 0);
        pid = -1;
        return -2;
    }
    std::string output() const {
        std::ifstream in(log);
        return {std::istreambuf_iterator<char>(in), {}};
    }
    ~Daemon() {
        stop();
        fs::remove_all(dir);
    }
};

navmap::ipc::StreamRequest request(const char* name) {
    navmap::ipc::StreamRequest r;
    r.profile = *navmap::ipc::defaultStreamProfile(name);
    return r;
}

TEST(NavmapdEndToEnd, ClusterAndHudClientsGetFramesControlWorksAndStopIsGraceful) {
    Daemon d;
    ASSERT_TRUE(fs::exists(d.dir / "frames.sock")) << d.output();
    const std::int64_t t0 = nowNs();
    auto cluster = navmap::ipc::StreamClient::connectUnix((d.dir / "frames.sock").string(), request("cluster"));
    ASSERT_TRUE(cluster) << cluster.error().message;
    auto hud = navmap::ipc::StreamClient::connectUnix((d.dir / "frames.sock").string(), request("hud"));
    ASSERT_TRUE(hud) << hud.error().message;

    // Frames arrive for both, in order, with their sizes and sane timestamps.
    navmap::ipc::ReceivedFrame f;
    std::uint64_t last_seq[2] = {0, 0};
    int counts[2] = {0, 0};
    const auto until = std::chrono::steady_clock::now() + 5s;
    while (std::chrono::steady_clock::now() < until) {
        for (int i = 0; i < 2; ++i) {
            auto& client = i == 0 ? cluster.value() : hud.value();
            auto got = client->next(f, 20ms);
            ASSERT_TRUE(got) << got.error().message << "\n" << d.output();
            if (!got.value()) continue;
            ++counts[i];
            EXPECT_GT(f.header.sequence, last_seq[i]);
            last_seq[i] = f.header.sequence;
            EXPECT_EQ(f.header.width, i == 0 ? 1280u : 800u);
            EXPECT_EQ(f.header.height, i == 0 ? 480u : 240u);
            EXPECT_GE(f.header.render_time_ns, t0);
            EXPECT_LE(f.header.render_time_ns, f.receive_time_ns);
            if (f.header.source_time_ns != 0) {
                EXPECT_LE(f.header.source_time_ns, f.header.render_time_ns);
                EXPECT_GT(f.header.source_time_ns, f.header.render_time_ns - 2'000'000'000)
                    << "pose data older than 2 s";
            }
        }
    }
    EXPECT_GT(counts[0], 5) << d.output();
    EXPECT_GT(counts[1], 5) << d.output();
    // Before its first frame each client was told that the map was loading (a status header as
    // soon as its profile had the client, docs/navmapd.md "Start-up").
    for (int i = 0; i < 2; ++i) {
        const auto& client = i == 0 ? cluster.value() : hud.value();
        EXPECT_GE(client->stats().statuses, 1u) << d.output();
        const auto st = nlohmann::json::parse(client->lastStatus(), nullptr, false);
        ASSERT_TRUE(st.is_object()) << "status '" << client->lastStatus() << "'";
        EXPECT_EQ(st["state"], "loading") << st.dump();
        EXPECT_EQ(st["profile"], i == 0 ? "cluster" : "hud") << st.dump();
        EXPECT_EQ(st["view"], i == 0 ? "snail" : "hud") << st.dump();
        EXPECT_TRUE(st["tiles_wanted"].is_number_unsigned() && st["held_back"].is_number_unsigned()) << st.dump();
        EXPECT_GE(st["waited_ms"].get<std::int64_t>(), 0) << st.dump();
        EXPECT_EQ(st["max_wait_ms"], 15000) << st.dump();
    }

    // A settled cluster frame of the standing vehicle matches its golden.
    navmap::ipc::ReceivedFrame settled;
    for (int i = 0; i < 50; ++i) {
        auto got = cluster.value()->next(settled, 200ms);
        ASSERT_TRUE(got);
        if (got.value()) break;
    }
    navmap::render::Image image(static_cast<int>(settled.header.width), static_cast<int>(settled.header.height));
    for (std::uint32_t y = 0; y < settled.header.height; ++y) {
        std::memcpy(&image.rgba[static_cast<std::size_t>(y) * settled.header.width * 4],
                    &settled.pixels[static_cast<std::size_t>(y) * settled.header.stride], settled.header.width * 4);
    }
    EXPECT_GOLDEN(image, "daemon/golden/navmapd_cluster_standing.png", (navmap::test::GoldenTolerance{12, 0.02}));

    // The control socket: status, a malformed line (error, nothing changes), a view change.
    auto control = navmap::ipc::ControlClient::connect((d.dir / "control.sock").string());
    ASSERT_TRUE(control) << control.error().message;
    auto status = control.value().request(R"({"cmd":"get_status"})");
    ASSERT_TRUE(status) << status.error().message;
    EXPECT_NE(status.value().find("\"ok\":true"), std::string::npos) << status.value();
    EXPECT_NE(status.value().find("\"valid\":true"), std::string::npos)
        << "the replayed fix is in use: " << status.value();
    // GPU tile uploads are counted per profile: the cluster (listed first) uploaded the tiles it draws.
    const std::size_t uploads_at = status.value().find("\"tiles_uploaded\":");
    ASSERT_NE(uploads_at, std::string::npos) << status.value();
    EXPECT_GT(std::strtoull(status.value().c_str() + uploads_at + std::strlen("\"tiles_uploaded\":"), nullptr, 10), 0u)
        << status.value();
    // Where the cluster's frame time goes: the renderer's passes of one frame in 30, timed.
    nlohmann::json passes;
    for (int i = 0; i < 40; ++i) {
        auto st = control.value().request(R"({"cmd":"get_status"})");
        ASSERT_TRUE(st) << st.error().message;
        const auto j = nlohmann::json::parse(st.value(), nullptr, false);
        ASSERT_TRUE(j.is_object()) << st.value();
        const auto& first = j["status"]["profiles"][0];
        ASSERT_EQ(first["name"], "cluster");
        passes = first["passes"];
        if (first["passes_sampled"].get<int>() >= 1) break;
        std::this_thread::sleep_for(250ms);
    }
    ASSERT_TRUE(passes.contains("terrain")) << "no cluster frame had its passes timed: " << passes.dump();
    EXPECT_GT(passes["terrain"]["p50_ms"].get<double>(), 0.0) << passes.dump();
    EXPECT_GT(passes["roads"]["p50_ms"].get<double>(), 0.0) << passes.dump();
    EXPECT_GT(passes["render"]["p50_ms"].get<double>(), 0.0) << passes.dump();
    std::printf("cluster passes: %s\n", passes.dump().c_str());
    auto bad = control.value().request(R"({"cmd":"set_view","display":"cluster","mode":"sideways"})");
    ASSERT_TRUE(bad);
    EXPECT_NE(bad.value().find("\"ok\":false"), std::string::npos) << bad.value();
    auto garbage = control.value().request("{{{ not json");
    ASSERT_TRUE(garbage);
    EXPECT_NE(garbage.value().find("\"ok\":false"), std::string::npos) << garbage.value();
    auto view = control.value().request(R"({"cmd":"set_view","display":"cluster","mode":"bird"})");
    ASSERT_TRUE(view);
    EXPECT_NE(view.value().find("\"ok\":true"), std::string::npos) << view.value();
    // The bird's-eye view looks down: the frame changes a lot.
    std::this_thread::sleep_for(1500ms);
    navmap::ipc::ReceivedFrame bird;
    for (int i = 0; i < 50; ++i) {
        auto got = cluster.value()->next(bird, 200ms);
        ASSERT_TRUE(got);
        if (got.value()) break;
    }
    std::size_t differing = 0;
    for (std::size_t i = 0; i < std::min(bird.pixels.size(), settled.pixels.size()); i += 4)
        differing += bird.pixels[i] != settled.pixels[i];
    EXPECT_GT(differing, settled.pixels.size() / 4 / 4) << "set_view bird did not change the cluster view";

    // SIGTERM: exit status 0, clients see the stream end.
    EXPECT_EQ(d.stop(), 0) << d.output();
    navmap::ipc::ReceivedFrame after;
    bool ended = false;
    for (int i = 0; i < 20 && !ended; ++i) {
        auto got = cluster.value()->next(after, 100ms);
        ended = !got;
    }
    EXPECT_TRUE(ended) << "the client did not notice the daemon stopping";
    const std::string out = d.output();
    EXPECT_NE(out.find("<5>navmapd: ready in"), std::string::npos) << out;
    EXPECT_NE(out.find("<5>navmapd: stopping"), std::string::npos) << out;
}

// `env`: assignments put before the command ("NAME=value ...").
// A lost GL context is not the end (docs/gles-profile.md "Lost contexts"): the renderer's test hook
// drops navmapd's context after 40 frames, as a GPU reset would. A control subscriber gets a
// gpu_reset event, the log says so, and the cluster's frames come back with the standing golden's
// pixels.
TEST(NavmapdEndToEnd, ALostGlContextIsMadeAnewAndFramesResume) {
    Daemon d("NAVMAP_TEST_LOSE_CONTEXT_AFTER_FRAMES=40");
    ASSERT_TRUE(fs::exists(d.dir / "frames.sock")) << d.output();
    auto control = navmap::ipc::ControlClient::connect((d.dir / "control.sock").string());
    ASSERT_TRUE(control) << control.error().message;
    auto subscribed = control.value().request(R"({"cmd":"subscribe","events":["gpu_reset"]})");
    ASSERT_TRUE(subscribed) << subscribed.error().message;
    EXPECT_EQ(subscribed.value(), R"({"ok":true,"cmd":"subscribe","events":["gpu_reset"]})");
    auto cluster = navmap::ipc::StreamClient::connectUnix((d.dir / "frames.sock").string(), request("cluster"));
    ASSERT_TRUE(cluster) << cluster.error().message;
    // Frames until the reset, then five more (the first ones wait for the tiles again).
    navmap::ipc::ReceivedFrame f;
    int before = 0, after = 0;
    const auto until = std::chrono::steady_clock::now() + 30s;
    while (after < 5 && std::chrono::steady_clock::now() < until) {
        auto got = cluster.value()->next(f, 100ms);
        ASSERT_TRUE(got) << got.error().message << "\n" << d.output();
        const bool reset = d.output().find("navmapd: GL context lost or reset (1 so far)") != std::string::npos;
        if (got.value()) ++(reset ? after : before);
    }
    EXPECT_GT(before, 0) << "frames before the reset";
    ASSERT_EQ(after, 5) << "frames after the reset\n" << d.output();
    auto event = control.value().nextEvent(2s);
    ASSERT_TRUE(event) << event.error().message;
    EXPECT_EQ(event.value(), R"({"event":"gpu_reset","resets":1})");
    navmap::render::Image image(static_cast<int>(f.header.width), static_cast<int>(f.header.height));
    for (std::uint32_t y = 0; y < f.header.height; ++y) {
        std::memcpy(&image.rgba[static_cast<std::size_t>(y) * f.header.width * 4],
                    &f.pixels[static_cast<std::size_t>(y) * f.header.stride], f.header.width * 4);
    }
    EXPECT_GOLDEN(image, "daemon/golden/navmapd_cluster_standing.png", (navmap::test::GoldenTolerance{12, 0.02}));
    EXPECT_EQ(d.stop(), 0) << d.output();
    const std::string out = d.output();
    EXPECT_NE(out.find("<4>navmap: GL context lost (reset status 0x8255); making a new one"), std::string::npos) << out;
    EXPECT_NE(out.find("<4>navmapd: GL context lost or reset (1 so far): made anew"), std::string::npos) << out;
    EXPECT_EQ(out.find("(2 so far)"), std::string::npos) << "the hook fires once\n" << out;
}

// Clients of payload dmabuf (docs/frame-protocol.md "dma-buf frames") get the cluster's frame in
// a buffer the renderer exported: the same picture as the standing golden, attribution included
// (blended on the GPU), through a mapping and through an EGL import alike, and no pixel copied by
// navmapd (get_status "cpu_copies" stays 0 while
// they are its only clients). Where the renderer cannot export, the request is refused naming why
// and the test stops there, saying so: render_dmabuf_guest runs it in a kernel with vgem, where
// NAVMAP_EXPECT_DMABUF=1 makes a refusal a failure.
TEST(NavmapdEndToEnd, DmabufClientsGetTheFrameWithoutACopy) {
    Daemon d;
    ASSERT_TRUE(fs::exists(d.dir / "frames.sock")) << d.output();
    navmap::ipc::StreamRequest r = request("cluster");
    r.payload = navmap::ipc::StreamPayload::Dmabuf;
    r.hold = true;
    // The refusal comes once the renderer is up; until then it says the renderer is starting.
    navmap::ipc::Result<std::unique_ptr<navmap::ipc::StreamClient>> c = navmap::ipc::Error{"not tried"};
    for (int i = 0; i < 100; ++i) {
        c = navmap::ipc::StreamClient::connectUnix((d.dir / "frames.sock").string(), r, 5s);
        if (c || c.error().message.find("the renderer is still starting") == std::string::npos) break;
        std::this_thread::sleep_for(200ms);
    }
    const char* expect = std::getenv("NAVMAP_EXPECT_DMABUF");
    if (!c && !(expect && std::string(expect) == "1")) {
        EXPECT_NE(c.error().message.find("handshake: dmabuf frames are not available here ("), std::string::npos)
            << c.error().message;
        GTEST_SKIP() << "navmapd cannot export dma-bufs here (" << c.error().message
                     << "); render_dmabuf_guest runs this test where it can";
    }
    ASSERT_TRUE(c) << c.error().message << "\n" << d.output();
    EXPECT_NE(d.output().find("dma-buf export: on, buffers from /dev/dri/"), std::string::npos) << d.output();
    EXPECT_EQ(c.value()->payload(), navmap::ipc::StreamPayload::Dmabuf);
    // Frames of the standing vehicle once the map is drawn; the last one is compared. Under qemu
    // without KVM a start-up frame can take longer than the first-frame timeout: then connect again.
    navmap::ipc::HeldFrame f;
    int frames = 0;
    const auto until = std::chrono::steady_clock::now() + 150s;
    while (frames < 10 && std::chrono::steady_clock::now() < until) {
        auto got = c.value()->nextHeld(f, 500ms);
        if (!got && frames == 0 && got.error().message.find("no frame within") != std::string::npos) {
            c = navmap::ipc::StreamClient::connectUnix((d.dir / "frames.sock").string(), r, 5s);
            ASSERT_TRUE(c) << c.error().message;
            continue;
        }
        ASSERT_TRUE(got) << got.error().message << "\n" << d.output();
        if (!got.value()) continue;
        ++frames;
        EXPECT_EQ(f.header.encoding, navmap::ipc::FrameEncoding::Dmabuf);
        EXPECT_GE(f.dmabuf_fd, 0);
        EXPECT_EQ(f.dmabuf.fourcc, 0x34324241U) << "DRM_FORMAT_ABGR8888";
        if (frames < 10) {
            ASSERT_TRUE(c.value()->release());
        }
    }
    ASSERT_EQ(frames, 10) << d.output();
    navmap::render::Image image(static_cast<int>(f.header.width), static_cast<int>(f.header.height));
    for (std::uint32_t y = 0; y < f.header.height; ++y) {
        std::memcpy(&image.rgba[static_cast<std::size_t>(y) * f.header.width * 4],
                    f.pixels + static_cast<std::size_t>(y) * f.header.stride, f.header.width * 4);
    }
    // A GPU client imports the buffer into its own EGL display (this process is not navmapd's)
    // and sees the same frame.
    navmap::render::Image imported;
    std::string why;
    ASSERT_TRUE(
        navmap::test::readThroughEgl({f.dmabuf_fd, f.dmabuf.fourcc, f.dmabuf.modifier, f.dmabuf.stride, f.dmabuf.offset,
                                      static_cast<int>(f.header.width), static_cast<int>(f.header.height)},
                                     &imported, &why))
        << why;
    EXPECT_EQ(imported.rgba, image.rgba) << "the EGL import differs from the mapped buffer";
    ASSERT_TRUE(c.value()->release());
    EXPECT_GOLDEN(image, "daemon/golden/navmapd_cluster_standing.png", (navmap::test::GoldenTolerance{12, 0.02}));
    EXPECT_EQ(c.value()->stats().cpu_copies, 0U);
    auto control = navmap::ipc::ControlClient::connect((d.dir / "control.sock").string());
    ASSERT_TRUE(control) << control.error().message;
    auto status = control.value().request(R"({"cmd":"get_status"})");
    ASSERT_TRUE(status) << status.error().message;
    const auto j = nlohmann::json::parse(status.value());
    for (const auto& p : j["status"]["profiles"]) {
        if (p["name"] != "cluster") continue;
        EXPECT_EQ(p["cpu_copies"], 0) << "no readback, no ring copy: " << p.dump();
        EXPECT_GE(p["dmabuf"]["exported"].get<int>(), 10) << p.dump();
    }
    EXPECT_TRUE(j["status"]["dmabuf"]["available"].get<bool>()) << j.dump();
    EXPECT_EQ(d.stop(), 0) << d.output();
}

std::pair<int, std::string> runNavmapd(const std::string& args, const std::string& env = "") {
    const std::string cmd = env + " " + std::string(NAVMAPD_PATH) + " " + args + " 2>&1";
    FILE* p = ::popen(cmd.c_str(), "r");
    std::string out;
    char buf[512];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    const int st = ::pclose(p);
    return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, out};
}

TEST(NavmapdEndToEnd, BadInputIsOneClearErrorLine) {
    auto [status, out] = runNavmapd("--store /nonexistent/x.navmap --run-for 1");
    EXPECT_EQ(status, 1);
    EXPECT_NE(out.find("<3>navmapd: open(/nonexistent/x.navmap): No such file or directory"), std::string::npos) << out;
    std::tie(status, out) = runNavmapd("--profiles dashboard --run-for 1");
    EXPECT_EQ(status, 1);
    EXPECT_NE(out.find("<3>navmapd: --profiles: unknown profile 'dashboard'"), std::string::npos) << out;
    std::tie(status, out) = runNavmapd(
        "--replay /nonexistent/drive.candump --run-for 1 --control-socket /tmp/navmapd-bad-c.sock "
        "--frame-socket /tmp/navmapd-bad-f.sock --http-port 0");
    EXPECT_EQ(status, 1);
    EXPECT_NE(out.find("/nonexistent/drive.candump"), std::string::npos) << out;
    std::tie(status, out) = runNavmapd("--speed 0");
    EXPECT_NE(status, 0);
    EXPECT_NE(out.find("--speed"), std::string::npos) << out;
}

// The line of `out` that holds `what`, or "".
std::string lineWith(const std::string& out, const std::string& what) {
    const std::size_t at = out.find(what);
    if (at == std::string::npos) return "";
    const std::size_t begin = out.rfind('\n', at);
    const std::size_t end = out.find('\n', at);
    return out.substr(
        begin == std::string::npos ? 0 : begin + 1,
        end == std::string::npos ? std::string::npos : end - (begin == std::string::npos ? 0 : begin + 1));
}

// At start-up navmapd logs the GL context's version and the features it turned off on it
// (docs/gles-profile.md): as this machine's driver makes it, and with Mesa held to an embedded
// ES 3.0 profile without GL_EXT_color_buffer_float.
TEST(NavmapdEndToEnd, LogsTheGlContextAndTheFeaturesItTurnedOff) {
    const fs::path dir = fs::temp_directory_path() / ("navmapd-gl-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    writeStandingLog(dir / "standing.candump");
    const std::string args = "--replay " + (dir / "standing.candump").string() + " --control-socket " +
                             (dir / "control.sock").string() + " --frame-socket " + (dir / "frames.sock").string() +
                             " --http-port 0 --profiles hud --no-labels --log-level info --run-for 1";
    auto [status, out] = runNavmapd(args);
    EXPECT_EQ(status, 0) << out;
    std::string line = lineWith(out, "navmapd: GL context: OpenGL ES 3.");
    ASSERT_FALSE(line.empty()) << out;
    EXPECT_NE(line.find("; features off: "), std::string::npos) << line;
    std::printf("[ info     ] %s\n", line.c_str());
    // The dma-buf export probe (docs/gles-profile.md "dma-buf export"): on llvmpipe, off and why.
    const std::string dmabuf = lineWith(out, "navmapd: dma-buf export: ");
    ASSERT_FALSE(dmabuf.empty()) << out;
    std::printf("[ info     ] %s\n", dmabuf.c_str());
    if (line.find("llvmpipe") != std::string::npos) {
        EXPECT_NE(dmabuf.find("<6>navmapd: dma-buf export: off (llvmpipe on the surfaceless platform: "),
                  std::string::npos)
            << dmabuf;
        EXPECT_NE(dmabuf.find("): frames go through shared memory"), std::string::npos) << dmabuf;
    }
    if (line.find("Mesa") == std::string::npos) {
        GTEST_SKIP() << "not a Mesa driver, so it cannot be held to ES 3.0 by MESA_GLES_VERSION_OVERRIDE: " << line;
    }
    if (line.find("OpenGL ES 3.2") != std::string::npos) {
        EXPECT_EQ(line.find("shadow-volume roads"), std::string::npos)
            << "float colour buffers are ES 3.2 core: " << line;
    }

    std::tie(status, out) =
        runNavmapd(args, "MESA_GLES_VERSION_OVERRIDE=3.0 MESA_EXTENSION_OVERRIDE=-GL_EXT_color_buffer_float");
    EXPECT_EQ(status, 0) << out;
    line = lineWith(out, "navmapd: GL context: ");
    std::printf("[ info     ] %s\n", line.c_str());
    EXPECT_NE(line.find("<6>navmapd: GL context: OpenGL ES 3.0 (OpenGL ES 3.0 Mesa "), std::string::npos) << out;
    EXPECT_NE(line.find("; features off: shadow-volume roads (no GL_EXT_color_buffer_float before ES 3.2): "
                        "geometric roads"),
              std::string::npos)
        << line;
    EXPECT_NE(out.find("<5>navmapd: ready in"), std::string::npos) << out;
    fs::remove_all(dir);
}

TEST(NavmapdEndToEnd, CheckConfigPrintsTheEffectiveConfiguration) {
    const fs::path cfg = fs::temp_directory_path() / "navmapd-check.toml";
    std::ofstream(cfg) << "[render]\nstyle = \"night\"\n[[profile]]\nname = \"cluster\"\nwidth = 1280\nheight = 480\n";
    const std::string cmd = std::string(NAVMAPD_PATH) + " --check-config --config " + cfg.string() + " 2>&1";
    FILE* p = ::popen(cmd.c_str(), "r");
    std::string out;
    char buf[512];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    EXPECT_EQ(::pclose(p), 0) << out;
    EXPECT_NE(out.find("configuration OK"), std::string::npos) << out;
    EXPECT_NE(out.find("style night"), std::string::npos) << out;
    EXPECT_NE(out.find("profile cluster: 1280x480"), std::string::npos) << out;
    std::ofstream(cfg) << "[render]\nstyle = \"dusk\"\n";
    p = ::popen(cmd.c_str(), "r");
    out.clear();
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    EXPECT_NE(::pclose(p), 0);
    EXPECT_NE(out.find("render.style = \"dusk\": expected day or night"), std::string::npos) << out;
    fs::remove(cfg);
}

// input.dbc: a file without a single message (a wrong file) beside the good navmap.dbc stops the
// start with one line naming it, exit 1 (bad input, docs/tools.md); a usable file's broken entries
// are skipped, logged once and counted in get_status, and the good file beside it decodes.
TEST(NavmapdEndToEnd, DbcFilesWithoutMessagesStopTheStartAndBrokenEntriesAreCounted) {
    const fs::path dir = fs::temp_directory_path() / ("navmapd-dbc-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    writeStandingLog(dir / "standing.candump");
    std::ofstream(dir / "garbage.dbc") << "not a DBC file\n\x89PNG\r\n";
    std::ofstream(dir / "extra.dbc") << "VERSION \"\"\n\nBO_ 1536 EXTRA: 8 X\n SG_ A : 0|8@1+ (1,0) [0|0] \"\" X\n"
                                     << "BO_ x: 8 X\n";
    const auto write_config = [&](const fs::path& second) {
        std::ofstream(dir / "navmapd.toml", std::ios::trunc)
            << "[input]\nsource = \"replay\"\nreplay_log = \"" << (dir / "standing.candump").string() << "\"\ndbc = [\""
            << NAVMAP_IPC_DEFAULT_DBC << "\", \"" << second.string() << "\"]\n"
            << "[render]\nlabels = false\n[[profile]]\nname = \"small\"\nwidth = 320\nheight = 240\nfps = 5\n"
            << "[control]\nsocket = \"" << (dir / "control.sock").string() << "\"\n[stream]\nsocket = \""
            << (dir / "frames.sock").string() << "\"\nhttp_port = 0\n";
    };
    const std::string config = "--config " + (dir / "navmapd.toml").string();
    write_config(dir / "garbage.dbc");
    const std::string garbage = (dir / "garbage.dbc").string();
    const std::string refused = "<3>navmapd: " + garbage +
                                ": no message (BO_) in it, not a DBC file (first: " + garbage +
                                ":2: unexpected text '?PNG')\n";
    auto [status, out] = runNavmapd(config + " --noop --run-for 20");
    EXPECT_EQ(status, 1) << out;
    EXPECT_NE(out.find(refused), std::string::npos) << out;
    // --check-config opens them as the start does: the same line, exit 1 (it said "configuration OK").
    std::tie(status, out) = runNavmapd(config + " --check-config");
    EXPECT_EQ(status, 1) << out;
    EXPECT_EQ(out, refused);
    // So is a signal mapped to a message that none of the DBC files has.
    write_config(dir / "extra.dbc");
    std::ofstream(dir / "navmapd.toml", std::ios::app)
        << "[[can.signal]]\nvss = \"Vehicle.Speed\"\nmessage = \"ABS\"\nsignal = \"SPEED\"\n";
    std::tie(status, out) = runNavmapd(config + " --check-config");
    EXPECT_EQ(status, 1) << out;
    EXPECT_NE(out.find("<3>navmapd: signal map Vehicle.Speed <- ABS.SPEED: message 'ABS' is in none of the DBC files"),
              std::string::npos)
        << out;

    write_config(dir / "extra.dbc");
    const std::string extra = (dir / "extra.dbc").string();
    const std::string skipped = "<4>navmapd: " + extra + ": 1 broken DBC entries skipped (first: " + extra +
                                ":5: BO_: expected a numeric message id)\n";
    std::tie(status, out) = runNavmapd(config + " --check-config");
    EXPECT_EQ(status, 0) << out;
    EXPECT_EQ(out.rfind(skipped + "configuration OK\n", 0), 0u) << out;
    navmap::test::NavmapdProcess d(NAVMAPD_PATH, "--config " + (dir / "navmapd.toml").string() + " --noop",
                                   dir / "navmapd.log", dir / "frames.sock");
    ASSERT_TRUE(fs::exists(dir / "frames.sock")) << d.output();
    // The DBC files are read on the input's start-up thread, which may log after the frame
    // socket exists: wait for the line instead of reading the log once.
    EXPECT_TRUE(navmap::test::waitFor([&] { return d.output().find(skipped) != std::string::npos; }, 10s))
        << d.output();
    std::string st;
    const auto decoded = [&] {
        auto control = navmap::ipc::ControlClient::connect((dir / "control.sock").string());
        if (!control) return false;
        auto reply = control.value().request(R"({"cmd":"get_status"})");
        st = reply ? reply.value() : reply.error().message;
        return st.find("\"valid\":true") != std::string::npos;
    };
    EXPECT_TRUE(navmap::test::waitFor(decoded, 10s)) << "navmap.dbc's fixes decode: " << st;
    EXPECT_NE(st.find("\"dbc_skipped_entries\":1"), std::string::npos) << st;
    EXPECT_EQ(d.stop(), 0) << d.output();
    fs::remove_all(dir);
}

// Files that took toml++ down (a 200,000-level header or dotted key: SIGSEGV, exit 139) or that
// it parsed at any size (a million profiles, 1.2 GB): one error line naming the place, exit 1.
TEST(NavmapdEndToEnd, CheckConfigRefusesDeepAndHugeFilesWithOneLine) {
    const fs::path cfg = fs::temp_directory_path() / ("navmapd-deep-" + std::to_string(::getpid()) + ".toml");
    const auto repeat = [](const std::string& s, std::size_t n) {
        std::string out;
        for (std::size_t i = 0; i < n; ++i) out += s;
        return out;
    };
    const std::string deep = repeat("a.", 199999) + "a";
    const std::string nested =
        "nested more than 32 levels deep (tables, dotted keys, arrays and inline tables together)";
    std::string profiles;
    for (std::size_t i = 0; i < 65; ++i) profiles += "[[profile]]\nname = \"p" + std::to_string(i) + "\"\n";
    const std::pair<std::string, std::string> cases[] = {
        {"[" + deep + "]\n", ":1:2: table header " + nested},
        {"[render]\n" + deep + " = 1\n", ":2:1: key " + nested},
        {"[render]\nx = " + repeat("{a = ", 100000) + "1" + repeat("}", 100000) + "\n",
         ":2:80: inline table " + nested},
        {"[render]\nx = " + repeat("[", 200000) + repeat("]", 200000) + "\n", ":2:35: array " + nested},
        {repeat("[[profile]]\n", 30000), ":20001:3: more than 20000 keys, tables and array elements"},
        {profiles, ":129:1: 65 profiles, more than 64"},
    };
    for (const auto& [text, error] : cases) {
        std::ofstream(cfg, std::ios::trunc) << text;
        const auto [status, out] = runNavmapd("--check-config --config " + cfg.string());
        EXPECT_EQ(status, 1) << error << "\n" << out.substr(0, 500);
        EXPECT_EQ(out, "<3>navmapd: " + cfg.string() + error + "\n");
    }
    fs::remove(cfg);
}

}  // namespace
