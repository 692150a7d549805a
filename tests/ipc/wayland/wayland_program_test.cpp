// SPDX-License-Identifier: Apache-2.0
// The navmap-wayland program without a compositor: the messages and exit statuses when there is
// no Wayland compositor to talk to, and a usage error.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "wayland_test_util.h"

using namespace navmap::wayland_test;

namespace {

std::string runWithout(const std::map<std::string, std::string>& env, int* status) {
    const std::string log =
        std::filesystem::temp_directory_path() / ("navmap-wayland-nodisplay-" + std::to_string(getpid()) + ".log");
    std::filesystem::remove(log);
    Child c({NAVMAP_WAYLAND_EXE, "--unix", "/nonexistent/navmap.sock"}, env, log);
    *status = c.wait(std::chrono::seconds(20));
    std::string out = readFile(log);
    std::filesystem::remove(log);
    return out;
}

}  // namespace

TEST(NavmapWaylandErrors, NoCompositorIsAClearMessageAndExitStatus1) {
    int st = 0;
    std::string out = runWithout({{"WAYLAND_DISPLAY", ""}, {"XDG_RUNTIME_DIR", ""}}, &st);
    ASSERT_TRUE(WIFEXITED(st)) << out;
    EXPECT_EQ(WEXITSTATUS(st), 1);
    EXPECT_NE(out.find("navmap-wayland: no Wayland compositor: WAYLAND_DISPLAY and XDG_RUNTIME_DIR are not set"),
              std::string::npos)
        << out;

    const std::string dir = std::filesystem::temp_directory_path();
    out = runWithout({{"WAYLAND_DISPLAY", "navmap-no-such-display"}, {"XDG_RUNTIME_DIR", dir}}, &st);
    ASSERT_TRUE(WIFEXITED(st)) << out;
    EXPECT_EQ(WEXITSTATUS(st), 1);
    EXPECT_NE(out.find("no Wayland compositor at WAYLAND_DISPLAY=navmap-no-such-display in XDG_RUNTIME_DIR=" + dir +
                       ": No such file or directory"),
              std::string::npos)
        << out;
}

TEST(NavmapWaylandErrors, UsageErrorsExit2) {
    int st = 0;
    const std::string log = std::filesystem::temp_directory_path() / ("navmap-wayland-usage.log");
    std::filesystem::remove(log);
    Child c({NAVMAP_WAYLAND_EXE, "--tcp", "host:1", "--payload", "shm"}, {}, log);
    st = c.wait(std::chrono::seconds(20));
    ASSERT_TRUE(WIFEXITED(st));
    EXPECT_EQ(WEXITSTATUS(st), 2);
    EXPECT_NE(readFile(log).find("--payload shm needs --unix"), std::string::npos) << readFile(log);
    // dma-bufs are local and fall back to shm: --tcp or another payload is a usage error.
    for (const std::vector<std::string>& args :
         {std::vector<std::string>{"--tcp", "host:1", "--dmabuf"},
          std::vector<std::string>{"--unix", "/nonexistent.sock", "--dmabuf", "--payload", "raw"}}) {
        std::vector<std::string> argv = {NAVMAP_WAYLAND_EXE};
        argv.insert(argv.end(), args.begin(), args.end());
        std::filesystem::remove(log);
        Child d(argv, {}, log);
        st = d.wait(std::chrono::seconds(20));
        ASSERT_TRUE(WIFEXITED(st));
        EXPECT_EQ(WEXITSTATUS(st), 2);
        EXPECT_NE(readFile(log).find("--dmabuf needs --unix and payload shm"), std::string::npos) << readFile(log);
    }
}
