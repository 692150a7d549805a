// SPDX-License-Identifier: Apache-2.0
// Every installed tool follows cli/include/navmap/cli/cli.h: --version prints "<tool> <version>"
// and exits 0, --help exits 0, a usage error (unknown option, a number that is not finite or out
// of its range) exits 2 naming the option and the range, bad input (a missing file, no daemon)
// exits 1 (docs/tools.md).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <string>
#include <vector>

#include "navmap/version.h"

namespace {

struct ProgramRun {
    int status = -1;
    std::string out;  // stdout and stderr
};

ProgramRun run(const std::string& args) {
    ProgramRun r;
    FILE* p = ::popen((args + " 2>&1").c_str(), "r");
    if (p == nullptr) return r;
    char buf[4096];
    std::size_t n = 0;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
    const int st = ::pclose(p);
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    return r;
}

struct Tool {
    const char* name;
    const char* path;
    std::string required;   ///< the tool's required options, so that the unknown one is the error
    std::string bad_input;  ///< arguments naming input that does not exist -> exit 1
    std::string bad_input_says;
};

const std::vector<Tool>& tools() {
    static const std::vector<Tool> kT = {
        {"navmapd", NAVMAPD_PATH, "", "--config /nonexistent/navmapd.toml", "/nonexistent/navmapd.toml"},
        {"navmap-view", NAVMAP_VIEW_PATH, "--unix s", "--unix /nonexistent/frames.sock --frames 1",
         "connect(/nonexistent/frames.sock): No such file or directory"},
#ifdef NAVMAP_WAYLAND_PATH
        // No compositor (its environment cleared): the Wayland failure, exit 1 (docs/wayland.md).
        {"navmap-wayland", "env -u WAYLAND_DISPLAY -u XDG_RUNTIME_DIR " NAVMAP_WAYLAND_PATH, "--unix s",
         "--unix /nonexistent/frames.sock", "no Wayland compositor: WAYLAND_DISPLAY and XDG_RUNTIME_DIR are not set"},
#endif
        {"navmap-ctl", NAVMAP_CTL_PATH, "get_status", "--socket /nonexistent/control.sock get_status",
         "connect(/nonexistent/control.sock): No such file or directory"},
        {"navmap-compile", NAVMAP_COMPILE_PATH, "--osm a --out b",
         "--osm /nonexistent/x.osm.pbf --out /tmp/navmap-cli-test.navmap", "/nonexistent/x.osm.pbf"},
        {"navmap-sim", NAVMAP_SIM_PATH, "--from a --to b", "--store /nonexistent/x.navmap --from encamp --to ordino",
         "/nonexistent/x.navmap"},
        {"navmap-soak", NAVMAP_SOAK_PATH, "--navmapd a --drive b",
         "--navmapd /nonexistent/navmapd --drive /nonexistent/drive.candump", "/nonexistent/navmapd"},
        {"navmap-label-quality", NAVMAP_LABEL_QUALITY_PATH, "", "--store /nonexistent/x.navmap --frames 1 --settle 0",
         "/nonexistent/x.navmap"},
        {"navmap-synth-region", NAVMAP_SYNTH_REGION_PATH, "--osm a --out-dir b",
         "--osm /nonexistent/x.osm.pbf --out-dir /nonexistent/region", "/nonexistent/x.osm.pbf: no such file"},
    };
    return kT;
}

}  // namespace

TEST(ToolsCli, VersionHelpUsageAndBadInputExitCodes) {
    for (const auto& t : tools()) {
        SCOPED_TRACE(t.name);
        const std::string exe = t.path;
        ProgramRun r = run(exe + " --version");
        EXPECT_EQ(r.status, 0) << r.out;
        EXPECT_EQ(r.out, std::string(t.name) + " " + NAVMAP_VERSION + "\n");
        r = run(exe + " --help");
        EXPECT_EQ(r.status, 0) << r.out;
        EXPECT_NE(r.out.find("--version"), std::string::npos) << r.out;
        r = run(exe + " " + t.required + " --no-such-option");
        EXPECT_EQ(r.status, 2) << r.out;
        EXPECT_EQ(r.out.rfind(std::string(t.name) + ": ", 0), 0U) << r.out;
        EXPECT_NE(r.out.find("--no-such-option"), std::string::npos) << r.out;
        EXPECT_NE(r.out.find("Run with --help for more information."), std::string::npos) << r.out;
        const std::string name = t.name;
        if (name == "navmap-compile" || name == "navmap-sim" || name == "navmap-soak") {
            // Without its required options the tool says which one is missing, also exit 2.
            r = run(exe);
            EXPECT_EQ(r.status, 2) << r.out;
            EXPECT_NE(r.out.find(" is required"), std::string::npos) << r.out;
        }
        r = run(exe + " " + t.bad_input);
        EXPECT_EQ(r.status, 1) << r.out;
        EXPECT_NE(r.out.find(t.bad_input_says), std::string::npos) << r.out;
    }
}

TEST(ToolsCli, NumbersMustBeFiniteAndInRange) {
    struct Case {
        const char* path;
        std::string args;
        std::string says;
    };
    const std::string compile = std::string(NAVMAP_COMPILE_PATH) + " --osm a.pbf --out b.navmap";
    const std::string sim = std::string(NAVMAP_SIM_PATH) + " --from encamp --to ordino";
    const std::vector<Case> cases = {
        {NAVMAPD_PATH, "--speed nan", "--speed: 'nan' is not a finite number in [0.01, 1000]"},
        {NAVMAPD_PATH, "--run-for inf", "--run-for: 'inf' is not a finite number in [0.1, 1e+07]"},
        {NAVMAPD_PATH, "--http-port 65536", "--http-port: '65536' is not an integer in [0, 65535]"},
        {NAVMAPD_PATH, "--msaa 2.5", "--msaa: '2.5' is not an integer in [-1, 16]"},
        {NAVMAP_VIEW_PATH, "--unix s --duration abc", "--duration: 'abc' is not a finite number in [0, 1e+07]"},
        {NAVMAP_VIEW_PATH, "--unix s --duration NaN", "--duration: 'NaN' is not a finite number in [0, 1e+07]"},
        {NAVMAP_VIEW_PATH, "--unix s --width 8", "--width: '8' is not an integer in [16, 4096]"},
        {NAVMAP_VIEW_PATH, "--unix s --fps 1e3", "--fps: '1e3' is not an integer in [0, 1000]"},
        {NAVMAP_VIEW_PATH, "--tcp host:99999", "--tcp: 'host:99999' is not HOST:PORT with a port in [1, 65535]"},
#ifdef NAVMAP_WAYLAND_PATH
        {NAVMAP_WAYLAND_PATH, "--unix s --width 8", "--width: '8' is not an integer in [16, 4096]"},
        {NAVMAP_WAYLAND_PATH, "--unix s --ivi-id -1", "--ivi-id: '-1' is not an integer in [0, 4294967295]"},
        {NAVMAP_WAYLAND_PATH, "--unix s --duration inf", "--duration: 'inf' is not a finite number in [0, 1e+07]"},
#endif
        {NAVMAP_CTL_PATH, "--timeout inf get_status", "--timeout: 'inf' is not a finite number in [0.1, 3600]"},
        {NAVMAP_CTL_PATH, "subscribe --count 0", "--count: '0' is not an integer in [1, 1000000000]"},
        {"", compile + " --leaf-size nan", "--leaf-size: 'nan' is not a finite number in"},
        {"", compile + " --dem-samples 1", "--dem-samples: '1' is not 0 (no DEM grid) or an integer in [2, "},
        {"", sim + " --position-hz 0", "--position-hz: '0' is not a finite number in [1, 50]"},
        {"", sim + " --noise-m -inf", "--noise-m: '-inf' is not a finite number in [0, 1000]"},
        {"", sim + " --dropouts 1.5", "--dropouts: '1.5' is not an integer in [0, 10000]"},
        {NAVMAP_LABEL_QUALITY_PATH, "--dt nan", "--dt: 'nan' is not a finite number in [0.001, 10]"},
        {NAVMAP_LABEL_QUALITY_PATH, "--frames 0", "--frames: '0' is not an integer in [1, 1000000]"},
        {NAVMAP_LABEL_QUALITY_PATH, "--size 1280x", "--size: '1280x' is not WxH with W and H integers in [16, 8192]"},
        {NAVMAP_SOAK_PATH, "--navmapd x --drive y --duration 1e999",
         "--duration: '1e999' is not a finite number in [1, 1e+07]"},
    };
    for (const auto& c : cases) {
        const std::string cmd = std::string(c.path) + (c.path[0] != '\0' ? " " : "") + c.args;
        SCOPED_TRACE(cmd);
        const ProgramRun r = run(cmd);
        EXPECT_EQ(r.status, 2) << r.out;
        EXPECT_NE(r.out.find(c.says), std::string::npos) << r.out;
    }
}
