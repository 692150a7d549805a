// SPDX-License-Identifier: Apache-2.0
// The HTML viewer in a real browser: headless Chromium loads GET /?token=..., shows the MJPEG
// stream and the /status JSON, the page handing its token on to both. Label `browser`; skipped with a reason when
// chromium is not installed (Debian: apt-get install chromium).

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "navmap/ipc/stream/frame_server.h"
#include "navmap/render/image.h"

using namespace navmap::ipc;
using namespace std::chrono_literals;

namespace {

std::string findChromium() {
    for (const char* p : {"/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome"}) {
        if (access(p, X_OK) == 0) {
            return p;
        }
    }
    return {};
}

std::string run(const std::string& cmd) {
    std::string out;
    if (FILE* p = popen(cmd.c_str(), "r")) {
        char buf[4096];
        std::size_t n = 0;
        while ((n = fread(buf, 1, sizeof(buf), p)) > 0) {
            out.append(buf, n);
        }
        pclose(p);
    }
    return out;
}

}  // namespace

TEST(StreamBrowser, HeadlessChromiumShowsTheLiveStreamAndStatus) {
    const std::string chromium = findChromium();
    if (chromium.empty()) {
        GTEST_SKIP() << "chromium is not installed (apt-get install chromium); the browser view is untested here";
    }
    FrameServerOptions o;
    o.http_port = 0;  // HTTP is off unless asked for
    o.http_token = "browser-test-token-0123";
    o.mjpeg_profile = "center";
    o.status_json = [] { return std::string(R"({"marker":"navmap-browser-test"})"); };
    FrameServer server(o);
    ASSERT_TRUE(server.start().ok());
    // A 1280x720 bird's-eye frame in one unmistakable colour, published at 30 fps.
    std::atomic<bool> go{true};
    std::thread render([&] {
        std::vector<std::uint8_t> px(1280 * 720 * 4);
        for (std::size_t i = 0; i < px.size(); i += 4) {
            px[i] = 30;
            px[i + 1] = 200;
            px[i + 2] = 70;
            px[i + 3] = 255;
        }
        while (go) {
            server.publish("bird", FrameView{px.data(), 1280, 720, 0, PixelFormat::Rgba8, 0, 0, {}, {}});
            std::this_thread::sleep_for(33ms);
        }
    });
    const auto dir = std::filesystem::temp_directory_path() / ("navmap-browser-" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    const std::string flags =
        " --headless --no-sandbox --disable-gpu --disable-background-networking --disable-component-update"
        " --disable-sync --no-first-run --user-data-dir=" +
        (dir / "profile").string();
    const std::string url = "http://127.0.0.1:" + std::to_string(server.httpPort()) + "/?token=" + o.http_token;
    const auto shot = dir / "page.png";
    run("timeout 60 " + chromium + flags + " --window-size=1400,900 --timeout=4000 --screenshot=" + shot.string() +
        " " + url + " 2>/dev/null");
    const std::string dom =
        run("timeout 60 " + chromium + flags + " --virtual-time-budget=3000 --dump-dom " + url + " 2>/dev/null");
    go = false;
    render.join();

    navmap::render::Image img;
    std::string err;
    ASSERT_TRUE(navmap::render::readImage(shot, &img, &err)) << err;
    long green = 0;
    for (int y = 0; y < img.height; ++y) {
        for (int x = 0; x < img.width; ++x) {
            const std::uint8_t* p = img.pixel(x, y);
            green += std::abs(p[0] - 30) < 16 && std::abs(p[1] - 200) < 16 && std::abs(p[2] - 70) < 16 ? 1 : 0;
        }
    }
    std::printf("screenshot %dx%d: %ld pixels of the stream colour\n", img.width, img.height, green);
    // Both need the token (the browser's own /favicon.ico request, without it, gets 401).
    EXPECT_GT(green, 100000) << "the MJPEG image is not on the page";
    // The page fetched /status and shows the daemon's JSON.
    EXPECT_NE(dom.find("navmap-browser-test"), std::string::npos) << dom.substr(0, 2000);
    EXPECT_NE(dom.find("live: "), std::string::npos);
    EXPECT_GE(server.stats().mjpeg_clients + server.stats().frames_sent, 1U);
    std::filesystem::remove_all(dir);
}
