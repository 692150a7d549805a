// SPDX-License-Identifier: Apache-2.0
// navmap-wayland on Weston 10 (Debian's), headless backend with the pixman renderer, once under
// the desktop shell (xdg-shell) and twice under ivi-shell with Weston's hmi-controller
// (weston-ivi.ini): the screen is captured with weston-screenshooter (weston --debug; under
// ivi-shell through weston_screenshooter_module.c) and compared with the frames the test's
// frame server published, at the surface's position. The run is bounded everywhere: every
// program runs under timeout(1), every wait has a deadline. Without weston the program prints
// why and exits 77 (CTest: skipped).

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <thread>

#include "wayland_test_util.h"

using namespace navmap::wayland_test;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

constexpr int kScreenWidth = 640;
constexpr int kScreenHeight = 480;

struct Screen {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgb;
    const std::uint8_t* at(int x, int y) const { return &rgb[(static_cast<std::size_t>(y) * width + x) * 3]; }
};

using Expected = std::function<void(int x, int y, std::uint8_t rgb[3])>;

// The largest channel difference between the screen at (x0, y0) and `expected` over w x h.
int maxDifference(const Screen& s, int x0, int y0, int w, int h, const Expected& expected) {
    int worst = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            std::uint8_t e[3];
            expected(x, y, e);
            const std::uint8_t* p = s.at(x0 + x, y0 + y);
            for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(p[c]) - int(e[c])));
        }
    }
    return worst;
}

bool near(const std::uint8_t* p, const std::uint8_t e[3]) {
    return std::abs(p[0] - e[0]) <= 1 && std::abs(p[1] - e[1]) <= 1 && std::abs(p[2] - e[2]) <= 1;
}

// Where a w x h image `expected` is on the screen: its four corners match there (within 1).
bool locate(const Screen& s, int w, int h, const Expected& expected, int* x0, int* y0) {
    std::uint8_t tl[3], tr[3], bl[3], br[3];
    expected(0, 0, tl), expected(w - 1, 0, tr), expected(0, h - 1, bl), expected(w - 1, h - 1, br);
    for (int y = 0; y + h <= s.height; ++y) {
        for (int x = 0; x + w <= s.width; ++x) {
            if (near(s.at(x, y), tl) && near(s.at(x + w - 1, y), tr) && near(s.at(x, y + h - 1), bl) &&
                near(s.at(x + w - 1, y + h - 1), br)) {
                *x0 = x;
                *y0 = y;
                return true;
            }
        }
    }
    return false;
}

Expected pattern(int tag) {
    return [tag](int x, int y, std::uint8_t rgb[3]) { patternPixel(x, y, tag, rgb); };
}

int countOf(const std::string& text, const std::string& what) {
    int n = 0;
    for (auto p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
    return n;
}

bool waitUntil(std::chrono::milliseconds timeout, const std::function<bool()>& done) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
        if (done()) return true;
        std::this_thread::sleep_for(100ms);
    }
    return done();
}

// One headless Weston in a temporary XDG_RUNTIME_DIR of its own, with a unique socket name.
class Weston {
public:
    Weston(const std::string& ini, bool ivi) {
        static int count = 0;
        m_dir = fs::temp_directory_path() /
                ("navmap-wayland-test-" + std::to_string(getpid()) + "-" + std::to_string(++count));
        fs::remove_all(m_dir);
        fs::create_directories(m_dir / "runtime");
        fs::create_directories(m_dir / "shots");
        fs::permissions(m_dir / "runtime", fs::perms::owner_all);
        m_socket = "navmap-test-" + std::to_string(getpid()) + "-" + std::to_string(count);
        std::vector<std::string> argv = {"timeout",
                                         "-k",
                                         "5",
                                         "240",
                                         "weston",
                                         "--backend=headless-backend.so",
                                         "--use-pixman",
                                         "--debug",
                                         "--socket=" + m_socket,
                                         "--width=" + std::to_string(kScreenWidth),
                                         "--height=" + std::to_string(kScreenHeight),
                                         "--config=" + std::string(NAVMAP_WAYLAND_TEST_DIR) + "/" + ini};
        if (ivi) argv.push_back("--modules=" + std::string(NAVMAP_WESTON_SCREENSHOOTER_MODULE));
        m_weston = std::make_unique<Child>(argv, env(), log());
        m_up = waitUntil(15s, [&] { return fs::exists(m_dir / "runtime" / m_socket); });
    }
    ~Weston() {
        m_weston.reset();
        if (!::testing::Test::HasFailure()) fs::remove_all(m_dir);
    }
    bool up() const { return m_up; }
    std::map<std::string, std::string> env() const {
        return {{"XDG_RUNTIME_DIR", (m_dir / "runtime").string()}, {"WAYLAND_DISPLAY", m_socket}};
    }
    std::string path(const std::string& name) const { return (m_dir / name).string(); }
    std::string log() const { return path("weston.log"); }
    void kill() { m_weston->kill(); }  // as if it crashed

    // The screen through weston-screenshooter (a PNG), or false with the reason in `why`.
    bool screenshot(Screen* out, std::string* why) {
        for (const auto& e : fs::directory_iterator(m_dir / "shots")) fs::remove(e.path());
        auto env_vars = env();
        env_vars["XDG_PICTURES_DIR"] = (m_dir / "shots").string();
        Child shooter({"timeout", "-k", "2", "10", "weston-screenshooter"}, env_vars, path("screenshooter.log"),
                      (m_dir / "shots").string());
        const int st = shooter.wait(15s);
        if (st == -1 || !WIFEXITED(st) || WEXITSTATUS(st) != 0) {
            *why = "weston-screenshooter failed: " + readFile(path("screenshooter.log"));
            return false;
        }
        for (const auto& e : fs::directory_iterator(m_dir / "shots")) {
            auto in = OIIO::ImageInput::open(e.path().string());
            if (!in) continue;
            const OIIO::ImageSpec& spec = in->spec();
            std::vector<std::uint8_t> px(static_cast<std::size_t>(spec.width) * spec.height * spec.nchannels);
            const bool ok = in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, px.data());
            in->close();
            if (!ok || spec.nchannels < 3) continue;
            out->width = spec.width;
            out->height = spec.height;
            out->rgb.resize(static_cast<std::size_t>(spec.width) * spec.height * 3);
            for (std::size_t i = 0, n = static_cast<std::size_t>(spec.width) * spec.height; i < n; ++i) {
                std::copy_n(&px[i * spec.nchannels], 3, &out->rgb[i * 3]);
            }
            return true;
        }
        *why = "weston-screenshooter wrote no PNG into " + (m_dir / "shots").string();
        return false;
    }

    // Screenshots until `found` says yes (true) or `timeout` passes (false; the last one in `last`).
    bool screenUntil(std::chrono::milliseconds timeout, const std::function<bool(const Screen&)>& found, Screen* last) {
        std::string why;
        return waitUntil(timeout, [&] { return screenshot(last, &why) && found(*last); });
    }

private:
    fs::path m_dir;
    std::string m_socket;
    std::unique_ptr<Child> m_weston;
    bool m_up = false;
};

std::vector<std::string> clientArgs(const std::string& socket, const std::vector<std::string>& more) {
    std::vector<std::string> a = {"timeout", "-k",       "5",         "240",    NAVMAP_WAYLAND_EXE,
                                  "--unix",  socket,     "--profile", "wl",     "--width",
                                  "320",     "--height", "200",       "--view", "bird"};
    a.insert(a.end(), more.begin(), more.end());
    return a;
}

std::string socketPath(const std::string& tag) {
    return "/tmp/navmap-wayland-" + tag + "-" + std::to_string(getpid()) + ".sock";
}

// hmi-controller lays out applications once its UI client is ready: its background is drawn.
bool hmiControllerReady(Weston& weston, Screen* s) {
    return weston.screenUntil(
        20s,
        [](const Screen& sc) {
            const auto* p = sc.at(320, 240);
            return p[0] + p[1] + p[2] > 0;
        },
        s);
}

}  // namespace

// xdg-shell: the window shows the published frame exactly, keeps it while navmapd is gone,
// shows the next server's frames after reconnecting, and exits 1 saying so when Weston dies.
TEST(NavmapWaylandWeston, DesktopShellShowsTheFramesAndKeepsTheLastWhileNavmapdIsGone) {
    Weston weston("weston-desktop.ini", false);
    ASSERT_TRUE(weston.up()) << readFile(weston.log());
    const std::string sock = socketPath("desktop");
    auto server = std::make_unique<PatternServer>(sock, 1);
    ASSERT_TRUE(server->started()) << server->error();
    Child client(clientArgs(sock, {}), weston.env(), weston.path("client.log"));

    Screen s;
    int x0 = -1, y0 = -1;
    ASSERT_TRUE(weston.screenUntil(
        20s, [&](const Screen& sc) { return locate(sc, 320, 200, pattern(1), &x0, &y0); }, &s))
        << "the frame is not on the screen\n"
        << readFile(weston.path("client.log"));
    const int first = maxDifference(s, x0, y0, 320, 200, pattern(1));
    std::printf("desktop-shell: frame at (%d, %d), max channel difference %d\n", x0, y0, first);
    EXPECT_LE(first, 1);
    EXPECT_NE(readFile(weston.path("client.log")).find("xdg-shell"), std::string::npos);

    server.reset();  // navmapd gone: the window keeps its last frame
    ASSERT_TRUE(waitUntil(10s, [&] {
        return readFile(weston.path("client.log")).find("showing the last frame") != std::string::npos;
    })) << readFile(weston.path("client.log"));
    std::string why;
    ASSERT_TRUE(weston.screenshot(&s, &why)) << why;
    const int kept = maxDifference(s, x0, y0, 320, 200, pattern(1));
    std::printf("desktop-shell: navmapd gone, the last frame kept: max channel difference %d\n", kept);
    EXPECT_LE(kept, 1);

    server = std::make_unique<PatternServer>(sock, 2);  // back: the new server's frames
    ASSERT_TRUE(server->started()) << server->error();
    ASSERT_TRUE(weston.screenUntil(
        20s, [&](const Screen& sc) { return maxDifference(sc, x0, y0, 320, 200, pattern(2)) <= 1; }, &s))
        << "no frame of the second server\n"
        << readFile(weston.path("client.log"));
    std::printf("desktop-shell: after the reconnect, max channel difference %d\n",
                maxDifference(s, x0, y0, 320, 200, pattern(2)));

    weston.kill();  // the compositor gone: a clear message and exit status 1
    const int st = client.wait(10s);
    ASSERT_NE(st, -1) << "navmap-wayland did not exit when Weston died";
    ASSERT_TRUE(WIFEXITED(st));
    EXPECT_EQ(WEXITSTATUS(st), 1);
    const std::string log = readFile(weston.path("client.log"));
    EXPECT_NE(log.find("closed the connection"), std::string::npos) << log;
}

// --dmabuf: navmapd (a server that exports nothing, as on llvmpipe) refuses dma-buf frames; the
// window shows the same frames through wl_shm and the log names the refusal once.
TEST(NavmapWaylandWeston, DmabufFallsBackToWlShmAndSaysWhyOnce) {
    Weston weston("weston-desktop.ini", false);
    ASSERT_TRUE(weston.up()) << readFile(weston.log());
    const std::string sock = socketPath("dmabuf");
    PatternServer server(sock, 3);
    ASSERT_TRUE(server.started()) << server.error();
    Child client(clientArgs(sock, {"--dmabuf"}), weston.env(), weston.path("client.log"));
    Screen s;
    int x0 = -1, y0 = -1;
    ASSERT_TRUE(weston.screenUntil(
        20s, [&](const Screen& sc) { return locate(sc, 320, 200, pattern(3), &x0, &y0); }, &s))
        << "the frame is not on the screen\n"
        << readFile(weston.path("client.log"));
    EXPECT_LE(maxDifference(s, x0, y0, 320, 200, pattern(3)), 1);
    const std::string log = readFile(weston.path("client.log"));
    const std::string line = "navmap-wayland: no dma-buf frames (handshake refused by " + sock +
                             ": handshake: dmabuf frames are not available here (this server exports no dma-buf "
                             "frames); ask for shm); using wl_shm buffers\n";
    EXPECT_NE(log.find(line), std::string::npos) << log;
    EXPECT_EQ(log.find("navmap-wayland: no dma-buf"), log.rfind("navmap-wayland: no dma-buf")) << log;
    EXPECT_NE(log.find("(payload shm)"), std::string::npos) << log;
}

// RGB565 frames (converted by the server on publish) land in an RGB565 wl_shm buffer row for row;
// the screen shows the pattern at 5-6-5 bits, widened as the compositor does (bit replication).
TEST(NavmapWaylandWeston, DesktopShellShowsRgb565FramesAsTheyCome) {
    Weston weston("weston-desktop.ini", false);
    ASSERT_TRUE(weston.up()) << readFile(weston.log());
    const std::string sock = socketPath("desktop565");
    PatternServer server(sock, 2);
    ASSERT_TRUE(server.started()) << server.error();
    Child client(clientArgs(sock, {"--format", "rgb565"}), weston.env(), weston.path("client.log"));
    const Expected quantised = [](int x, int y, std::uint8_t rgb[3]) {
        patternPixel(x, y, 2, rgb);
        const unsigned r = rgb[0] >> 3, g = rgb[1] >> 2, b = rgb[2] >> 3;
        rgb[0] = static_cast<std::uint8_t>((r << 3) | (r >> 2));
        rgb[1] = static_cast<std::uint8_t>((g << 2) | (g >> 4));
        rgb[2] = static_cast<std::uint8_t>((b << 3) | (b >> 2));
    };
    Screen s;
    int x0 = -1, y0 = -1;
    ASSERT_TRUE(weston.screenUntil(
        20s, [&](const Screen& sc) { return locate(sc, 320, 200, quantised, &x0, &y0); }, &s))
        << "the RGB565 frame is not on the screen\n"
        << readFile(weston.path("client.log"));
    const int diff = maxDifference(s, x0, y0, 320, 200, quantised);
    std::printf("desktop-shell, rgb565: frame at (%d, %d), max channel difference %d\n", x0, y0, diff);
    EXPECT_LE(diff, 1);
    EXPECT_NE(readFile(weston.path("client.log")).find("rgb565 frames as RGB565"), std::string::npos)
        << readFile(weston.path("client.log"));
    EXPECT_EQ(client.stop(), 0);
}

// xdg-shell, full screen: desktop-shell configures the output's 640x480; navmap-wayland asks the
// server for it and the frames cover the screen 1:1.
TEST(NavmapWaylandWeston, DesktopShellFullscreenTakesTheOutputsSizeFromNavmapd) {
    Weston weston("weston-desktop.ini", false);
    ASSERT_TRUE(weston.up()) << readFile(weston.log());
    const std::string sock = socketPath("desktop-full");
    PatternServer server(sock, 3);
    ASSERT_TRUE(server.started()) << server.error();
    Child client(clientArgs(sock, {"--fullscreen"}), weston.env(), weston.path("client.log"));
    Screen s;
    ASSERT_TRUE(weston.screenUntil(
        20s, [&](const Screen& sc) { return maxDifference(sc, 0, 0, kScreenWidth, kScreenHeight, pattern(3)) <= 1; },
        &s))
        << "the 640x480 frame does not cover the screen: max channel difference "
        << maxDifference(s, 0, 0, kScreenWidth, kScreenHeight, pattern(3)) << "\n"
        << readFile(weston.path("client.log"));
    std::printf("desktop-shell, full screen: 640x480 frame at (0, 0), max channel difference %d\n",
                maxDifference(s, 0, 0, kScreenWidth, kScreenHeight, pattern(3)));
    const std::string log = readFile(weston.path("client.log"));
    EXPECT_NE(log.find("sized the surface 640x480"), std::string::npos) << log;
    EXPECT_NE(log.find("streaming wl 640x480 bird"), std::string::npos) << log;
    EXPECT_EQ(client.stop(), 0);
}

// ivi-shell: hmi-controller gives the surface 160x205; navmap-wayland asks navmapd for that size
// and shows the frames 1:1 at the controller's position (0, 0).
TEST(NavmapWaylandWeston, IviShellTakesTheControllersSizeFromNavmapd) {
    Weston weston("weston-ivi.ini", true);
    ASSERT_TRUE(weston.up()) << readFile(weston.log());
    Screen s;
    ASSERT_TRUE(hmiControllerReady(weston, &s)) << readFile(weston.log());
    const std::string sock = socketPath("ivi");
    PatternServer server(sock, 3);
    ASSERT_TRUE(server.started()) << server.error();
    Child client(clientArgs(sock, {"--ivi-id", "9000"}), weston.env(), weston.path("client.log"));
    ASSERT_TRUE(weston.screenUntil(
        20s, [&](const Screen& sc) { return maxDifference(sc, 0, 0, 160, 205, pattern(3)) <= 1; }, &s))
        << "the 160x205 frame is not at (0, 0): max channel difference " << maxDifference(s, 0, 0, 160, 205, pattern(3))
        << "\n"
        << readFile(weston.path("client.log"));
    std::printf("ivi-shell: 160x205 frame at (0, 0), max channel difference %d\n",
                maxDifference(s, 0, 0, 160, 205, pattern(3)));
    const std::string log = readFile(weston.path("client.log"));
    EXPECT_NE(log.find("ivi-shell, ivi_id 9000"), std::string::npos) << log;
    EXPECT_NE(log.find("sized the surface 160x205"), std::string::npos) << log;
    EXPECT_NE(log.find("streaming wl 160x205 bird"), std::string::npos) << log;
    EXPECT_EQ(client.stop(), 0);
}

// ivi-shell, navmapd renders the profile at 320x200 only: the refused 160x205 is said once in
// the log and the 320x200 frames are scaled into the surface (160x100, centred at y = 52).
TEST(NavmapWaylandWeston, IviShellScalesTheFramesWhenNavmapdRefusesTheSize) {
    Weston weston("weston-ivi.ini", true);
    ASSERT_TRUE(weston.up()) << readFile(weston.log());
    Screen s;
    ASSERT_TRUE(hmiControllerReady(weston, &s)) << readFile(weston.log());
    const std::string sock = socketPath("ivi-fixed");
    PatternServer server(sock, 1, {{"wl", "bird", 320, 200}});
    ASSERT_TRUE(server.started()) << server.error();
    Child client(clientArgs(sock, {"--ivi-id", "9001"}), weston.env(), weston.path("client.log"));
    // Target pixel (x, y) of the 160x100 placement shows source pixel (2x + 1, 2y + 1); black around.
    const Expected scaled = [](int x, int y, std::uint8_t rgb[3]) {
        if (y < 52 || y >= 152) {
            rgb[0] = rgb[1] = rgb[2] = 0;
            return;
        }
        patternPixel(2 * x + 1, 2 * (y - 52) + 1, 1, rgb);
    };
    ASSERT_TRUE(weston.screenUntil(
        20s, [&](const Screen& sc) { return maxDifference(sc, 0, 0, 160, 205, scaled) <= 1; }, &s))
        << "max channel difference " << maxDifference(s, 0, 0, 160, 205, scaled) << "\n"
        << readFile(weston.path("client.log"));
    std::printf("ivi-shell, size refused: 320x200 scaled into 160x205, max channel difference %d\n",
                maxDifference(s, 0, 0, 160, 205, scaled));
    std::this_thread::sleep_for(1s);
    const std::string log = readFile(weston.path("client.log"));
    EXPECT_EQ(countOf(log, "does not render wl at 160x205"), 1) << log;
    EXPECT_EQ(client.stop(), 0);
}

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    for (const char* program : {"weston", "weston-screenshooter", "timeout"}) {
        if (findOnPath(program).empty()) {
            std::printf("SKIPPED: %s is not installed (apt-get install weston; scripts/install-deps.sh)\n", program);
            return 77;
        }
    }
    return RUN_ALL_TESTS();
}
