// navmapd as a whole program: the main job renders a simulated drive per display profile and
// records the frames; bad input gives one clear error.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

#include "navmap/render/image.h"

namespace {

struct RunResult {
    int status = -1;
    std::string output;
};

RunResult runNavmapd(const std::string& args) {
    RunResult r;
    const std::string cmd = std::string(NAVMAPD_PATH) + " " + args + " 2>&1";
    FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) return r;
    std::array<char, 4096> buf{};
    while (std::fgets(buf.data(), buf.size(), p)) r.output += buf.data();
    const int st = ::pclose(p);
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    return r;
}

TEST(Navmapd, RecordsASimulatedDrivePerProfile) {
    const auto dir = std::filesystem::temp_directory_path() / "navmapd_frames_test";
    std::filesystem::remove_all(dir);
    const RunResult r = runNavmapd("--frames 4 --sim-step 5 --profiles hud,center --out " + dir.string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("hud: 4 frames (800x240) in"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("center: 4 frames (1280x720) in"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("<6>navmapd: simulated drive: andorra-la-vella -> encamp"), std::string::npos) << r.output;
    navmap::render::Image first, last;
    std::string err;
    ASSERT_TRUE(navmap::render::readImage(dir / "center" / "frame_0000.png", &first, &err)) << err;
    ASSERT_TRUE(navmap::render::readImage(dir / "center" / "frame_0003.png", &last, &err)) << err;
    EXPECT_EQ(first.width, 1280);
    EXPECT_EQ(first.height, 720);
    EXPECT_NE(first.rgba, last.rgba) << "the vehicle moved";
    // The bird's-eye view shows the marker's red at the screen centre area.
    int red = 0;
    for (int y = 200; y < 520; ++y)
        for (int x = 540; x < 740; ++x) {
            const auto* px = first.pixel(x, y);
            red += px[0] > 200 && px[1] < 90 && px[2] < 80;
        }
    EXPECT_GT(red, 20) << "vehicle marker not visible";
    std::filesystem::remove_all(dir);
}

TEST(Navmapd, MissingStoreIsOneClearError) {
    const RunResult r = runNavmapd("--frames 1 --store /nonexistent/x.navmap --out /tmp/navmapd_unused");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("<3>navmapd: open(/nonexistent/x.navmap): No such file or directory"), std::string::npos) << r.output;
}

TEST(Navmapd, UnknownProfileAndPlaceAreRejected) {
    RunResult r = runNavmapd("--frames 1 --profiles dashboard --out /tmp/navmapd_unused");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("unknown profile 'dashboard'"), std::string::npos) << r.output;
    r = runNavmapd("--frames 1 --from atlantis --out /tmp/navmapd_unused");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("--from atlantis: expected lat,lon"), std::string::npos) << r.output;
}

TEST(Navmapd, BadOptionIsRejected) {
    const RunResult r = runNavmapd("--frames 0");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("--frames"), std::string::npos) << r.output;
}

}  // namespace
