// SPDX-License-Identifier: Apache-2.0
// The live page of navmapd itself in headless Chromium: HTTP on a configured port with a token,
// the page's stream is the first configured profile (not a built-in name), its buttons are the
// configured profiles, the map data attribution is on the page, and the stream's pixels arrive.
// Label `browser`; skipped with a reason when chromium is not installed.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "navmap/ipc/client/stream_client.h"
#include "navmap/render/image.h"
#include "navmapd_process.h"
#include "stream_test_util.h"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using navmap::stream_test::freeTcpPort;

std::string findChromium() {
    for (const char* p : {"/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome"}) {
        if (::access(p, X_OK) == 0) return p;
    }
    return {};
}

std::string run(const std::string& cmd) {
    std::string out;
    if (FILE* p = ::popen(cmd.c_str(), "r")) {
        char buf[4096];
        std::size_t n = 0;
        while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
        ::pclose(p);
    }
    return out;
}

}  // namespace

TEST(NavmapdBrowser, TheLivePageShowsTheFirstProfileItsButtonsAndTheAttribution) {
    const std::string chromium = findChromium();
    if (chromium.empty()) {
        GTEST_SKIP() << "chromium is not installed (apt-get install chromium); the live page is untested here";
    }
    const fs::path dir = fs::temp_directory_path() / ("navmapd-browser-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    navmap::test::writeStandingLog(dir / "standing.candump");
    const int port = freeTcpPort();
    const std::string token = "browser-test-token-navmapd-0123";
    std::ofstream(dir / "navmapd.toml")
        << "[input]\nsource = \"replay\"\nreplay_log = \"" << (dir / "standing.candump").string()
        << "\"\n[[profile]]\nname = \"rear\"\nwidth = 640\nheight = 360\nview = \"bird\"\n"
           "[[profile]]\nname = \"cluster\"\nwidth = 1280\nheight = 480\nview = \"snail\"\n"
           "[control]\nsocket = \""
        << (dir / "control.sock").string() << "\"\n[stream]\nsocket = \"" << (dir / "frames.sock").string()
        << "\"\nhttp_port = " << port << "\nhttp_token = \"" << token << "\"\n";
    navmap::test::NavmapdProcess daemon(NAVMAPD_PATH, "--noop --config " + (dir / "navmapd.toml").string(),
                                        dir / "navmapd.log", dir / "frames.sock");
    ASSERT_TRUE(fs::exists(dir / "frames.sock")) << daemon.output();
    // The colour of a "rear" frame (the no-op renderer's sky) as a display client receives it.
    navmap::ipc::StreamRequest rear;
    rear.profile.name = "rear";
    rear.profile.width = 640;
    rear.profile.height = 360;
    rear.profile.view = "bird";
    auto client = navmap::ipc::StreamClient::connectUnix((dir / "frames.sock").string(), rear);
    ASSERT_TRUE(client.ok()) << client.error().message;
    navmap::ipc::ReceivedFrame frame;
    for (int i = 0; i < 50 && client.value()->stats().frames == 0; ++i)
        ASSERT_TRUE(client.value()->next(frame, 200ms).ok());
    ASSERT_GT(client.value()->stats().frames, 0U) << daemon.output();
    const std::uint8_t sky[3] = {frame.pixels[0], frame.pixels[1], frame.pixels[2]};
    client.value().reset();

    const std::string flags =
        " --headless --no-sandbox --disable-gpu --disable-background-networking --disable-component-update"
        " --disable-sync --no-first-run --user-data-dir=" +
        (dir / "profile").string();
    const std::string url = "http://127.0.0.1:" + std::to_string(port) + "/?token=" + token;
    const auto shot = dir / "page.png";
    run("timeout 60 " + chromium + flags + " --window-size=1000,800 --timeout=5000 --screenshot=" + shot.string() +
        " " + url + " 2>/dev/null");
    const std::string dom =
        run("timeout 60 " + chromium + flags + " --virtual-time-budget=3000 --dump-dom " + url + " 2>/dev/null");

    // The page's stream is the first configured profile, and its buttons are the configured ones.
    EXPECT_NE(dom.find("/stream.mjpg?profile=rear"), std::string::npos) << dom.substr(0, 3000);
    EXPECT_NE(dom.find(">rear</button>"), std::string::npos) << dom.substr(0, 3000);
    EXPECT_NE(dom.find(">cluster</button>"), std::string::npos);
    EXPECT_EQ(dom.find(">center</button>"), std::string::npos) << "a profile navmapd does not render";
    // The attribution of the map data is on the page.
    EXPECT_NE(dom.find("OpenStreetMap contributors"), std::string::npos) << dom.substr(0, 3000);
    EXPECT_NE(dom.find("\u00a9"), std::string::npos);
    // /status came through with the token: the daemon's JSON, its version in it.
    EXPECT_NE(dom.find("\"version\": \""), std::string::npos) << dom.substr(0, 3000);
    EXPECT_NE(dom.find("live: "), std::string::npos);

    navmap::render::Image img;
    std::string err;
    ASSERT_TRUE(navmap::render::readImage(shot, &img, &err)) << err;
    long stream_pixels = 0;
    for (int y = 0; y < img.height; ++y) {
        for (int x = 0; x < img.width; ++x) {
            const std::uint8_t* p = img.pixel(x, y);
            stream_pixels +=
                std::abs(p[0] - sky[0]) < 12 && std::abs(p[1] - sky[1]) < 12 && std::abs(p[2] - sky[2]) < 12 ? 1 : 0;
        }
    }
    std::printf("screenshot %dx%d: %ld pixels of the stream's colour %d,%d,%d\n", img.width, img.height, stream_pixels,
                sky[0], sky[1], sky[2]);
    // The 640x360 image (230400 pixels) is on the page.
    EXPECT_GT(stream_pixels, 150000) << "the stream is not on the page";
    if (stream_pixels <= 150000) {
        const fs::path kept = fs::path(NAVMAP_BINARY_DIR) / "golden-failures" / "navmapd_browser_page.png";
        fs::create_directories(kept.parent_path());
        fs::copy_file(shot, kept, fs::copy_options::overwrite_existing);
        std::printf("the screenshot is kept as %s\n", kept.c_str());
    }
    daemon.stop();
    fs::remove_all(dir);
}
