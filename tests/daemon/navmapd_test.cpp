// navmapd as a whole program: the main job writes frames; bad input gives one clear error.
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

TEST(Navmapd, WritesTheFlyoverFramesAsPng) {
    const auto dir = std::filesystem::temp_directory_path() / "navmapd_frames_test";
    std::filesystem::remove_all(dir);
    const RunResult r = runNavmapd("--frames 4 --width 320 --height 120 --out " + dir.string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("4 frames (320x120) written to"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("<6>navmapd: renderer: gles"), std::string::npos) << r.output;
    navmap::render::Image first, last;
    std::string err;
    ASSERT_TRUE(navmap::render::readImage(dir / "frame_0000.png", &first, &err)) << err;
    ASSERT_TRUE(navmap::render::readImage(dir / "frame_0003.png", &last, &err)) << err;
    EXPECT_EQ(first.width, 320);
    EXPECT_EQ(first.height, 120);
    EXPECT_NE(first.rgba, last.rgba);
    // The lower half looks at terrain: not sky-blue.
    const auto* px = first.pixel(160, 100);
    EXPECT_FALSE(px[0] == 158 && px[1] == 191 && px[2] == 230);
    std::filesystem::remove_all(dir);
}

TEST(Navmapd, MissingDemIsOneClearError) {
    const RunResult r = runNavmapd("--frames 1 --dem /nonexistent/N42E001.hgt --out /tmp/navmapd_unused");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.output.find("<3>navmapd: /nonexistent/N42E001.hgt: cannot open"), std::string::npos) << r.output;
}

TEST(Navmapd, BadOptionIsRejected) {
    const RunResult r = runNavmapd("--frames 0");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("--frames"), std::string::npos) << r.output;
}

}  // namespace
