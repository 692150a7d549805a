// SPDX-License-Identifier: Apache-2.0
// navmapd's frame and control sockets against hostile local clients, whole program (no-op
// renderer): socket modes and groups under umask 000, a user outside the group refused by the
// file mode (navmap-view run with setpriv), a user inside it who opens 64 streams of a size that
// is not rendered and cannot lock the cluster out, refused sizes that cost no memory, and HTTP
// off unless configured.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "foreign_user.h"
#include "navmap/ipc/client/frame_ring.h"
#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/control/control_client.h"
#include "navmapd_process.h"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

constexpr gid_t kDisplays = 64000;  // the sockets' group

std::pair<int, std::string> run(const std::string& cmd) {
    FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
    std::string out;
    char buf[512];
    while (p != nullptr && std::fgets(buf, sizeof buf, p)) out += buf;
    const int st = p != nullptr ? ::pclose(p) : -1;
    return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, out};
}

nlohmann::json daemonStatus(const fs::path& control) {
    auto c = navmap::ipc::ControlClient::connect(control.string());
    if (!c) return nullptr;
    auto r = c.value().request(R"({"cmd":"get_status"})", 5s);
    if (!r) return nullptr;
    auto j = nlohmann::json::parse(r.value(), nullptr, false);
    return j.is_object() && j.contains("status") ? j["status"] : nlohmann::json();
}

int countLines(const std::string& report, const std::string& text) {
    std::istringstream in(report);
    int n = 0;
    for (std::string line; std::getline(in, line);) n += line.find(text) != std::string::npos ? 1 : 0;
    return n;
}

TEST(NavmapdStreamAccess, HostileLocalClientsNeitherLockOutTheClusterNorGrowMemory) {
    if (const auto why = navmap::test::cannotSwitchUser(); !why.empty()) {
        GTEST_SKIP() << why << " (the test runs clients as other users and gives the sockets a group)";
    }
    const fs::path dir = fs::temp_directory_path() / ("navmapd-access-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::permissions(dir, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec | fs::perms::others_read |
                             fs::perms::others_exec);
    const fs::path frames = dir / "frames.sock", control = dir / "control.sock";
    std::ofstream(dir / "navmapd.toml") << "[control]\nsocket = \"" << control.string() << "\"\ngroup = \"" << kDisplays
                                        << "\"\n[stream]\nsocket = \"" << frames.string() << "\"\ngroup = \""
                                        << kDisplays << "\"\nallowed_uids = [65534]\nmax_clients_per_uid = 4\n";
    const mode_t old = ::umask(0);
    navmap::test::NavmapdProcess d(
        NAVMAPD_PATH, "--config " + (dir / "navmapd.toml").string() + " --noop --profiles cluster,hud --log-level info",
        dir / "navmapd.log", frames);
    ::umask(old);
    ASSERT_TRUE(fs::exists(frames)) << d.output();
    for (int i = 0; i < 100 && !fs::exists(control); ++i) std::this_thread::sleep_for(50ms);

    // Both sockets: 0660 and the configured group, though the daemon started under umask 000.
    for (const auto& sock : {frames, control}) {
        struct stat st {};
        ASSERT_EQ(::stat(sock.c_str(), &st), 0) << sock;
        EXPECT_EQ(st.st_mode & 07777, 0660U) << sock << ": " << std::oct << (st.st_mode & 07777);
        EXPECT_EQ(st.st_gid, kDisplays) << sock;
    }
    // HTTP is off unless configured.
    EXPECT_EQ(d.output().find("http://"), std::string::npos) << d.output();

    // A user outside the group: navmap-view cannot even connect.
    const auto [outsider, outsiderText] =
        run("setpriv --reuid=64002 --regid=64002 --clear-groups " NAVMAP_VIEW_PATH " --unix " + frames.string() +
            " --profile cluster --frames 1");
    EXPECT_NE(outsider, 0) << outsiderText;
    EXPECT_NE(outsiderText.find("connect(" + frames.string() + "): Permission denied"), std::string::npos)
        << outsiderText;

    // nobody, allowed and in the group, opens 64 streams at a size the daemon does not render and
    // holds them open.
    const auto before = daemonStatus(control);
    ASSERT_TRUE(before.is_object()) << d.output();
    navmap::test::ForeignProcess nobody({65534, 65534, {kDisplays}}, [&] {
        auto* held = new std::vector<std::unique_ptr<navmap::ipc::StreamClient>>();  // kept until the process exits
        std::string report;
        for (int i = 0; i < 64; ++i) {
            navmap::ipc::StreamRequest r;
            r.profile.name = "x";
            r.profile.width = 4000 + i;
            r.profile.height = 4096;
            r.profile.view = "bird";
            auto c = navmap::ipc::StreamClient::connectUnix(frames.string(), r);
            report += c ? std::string("accepted") : c.error().message;
            report += "\n";
            if (c) held->push_back(std::move(c.value()));
        }
        return report;
    });
    const std::string report = nobody.result();
    const int not_rendered =
        countLines(report, "is not rendered here; rendered: cluster (snail 1280x480), hud (hud 800x240)");
    const int uid_full = countLines(report, "too many connections from uid 65534 (limit 4)");
    EXPECT_EQ(countLines(report, "accepted"), 0) << report;
    EXPECT_GE(not_rendered, 1) << report;
    EXPECT_EQ(not_rendered + uid_full, 64) << report;

    // The cluster still gets frames (as root, and as nobody within its own four).
    const auto [cluster, clusterText] =
        run(std::string(NAVMAP_VIEW_PATH) + " --unix " + frames.string() + " --profile cluster --frames 3");
    EXPECT_EQ(cluster, 0) << clusterText << d.output();
    EXPECT_NE(clusterText.find("(3 frames)"), std::string::npos) << clusterText;

    // Eight more sizes that are not rendered, from root: refused, no ring, no memory.
    std::vector<std::unique_ptr<navmap::ipc::StreamClient>> kept;
    for (int i = 0; i < 8; ++i) {
        navmap::ipc::StreamRequest r;
        r.profile.width = 4096;
        r.profile.height = 4096 - i;
        r.profile.view = "bird";
        auto c = navmap::ipc::StreamClient::connectUnix(frames.string(), r);
        EXPECT_FALSE(c) << "size " << r.profile.height;
        if (c) kept.push_back(std::move(c.value()));
    }
    std::this_thread::sleep_for(1200ms);  // the status snapshot is refreshed every second
    const auto after = daemonStatus(control);
    ASSERT_TRUE(after.is_object()) << d.output();
    const double rss_before = before["memory"]["rss_bytes"].get<double>() / 1e6;
    const double rss_after = after["memory"]["rss_bytes"].get<double>() / 1e6;
    std::printf("navmapd RSS %.0f MB before the 72 refused streams, %.0f MB after; ring bytes %llu\n", rss_before,
                rss_after, static_cast<unsigned long long>(after["stream"]["ring_bytes"].get<std::uint64_t>()));
    EXPECT_LT(rss_after - rss_before, 32.0) << "refused streams cost memory";
    // What rings there are: the cluster's, kept (idle) since navmap-view mapped it; none for the
    // refused streams.
    EXPECT_EQ(after["stream"]["ring_bytes"].get<std::uint64_t>(),
              navmap::ipc::FrameRingLayout::make(2, 1280, 480, navmap::ipc::PixelFormat::Rgba8).total_bytes)
        << after.dump();
    EXPECT_GE(after["stream"]["refusals"]["not_rendered"].get<std::uint64_t>(),
              static_cast<std::uint64_t>(not_rendered + 8));
    EXPECT_EQ(after["stream"]["refusals"]["uid_full"].get<std::uint64_t>(), static_cast<std::uint64_t>(uid_full));
    nobody.release();
    EXPECT_EQ(d.stop(), 0) << d.output();
    fs::remove_all(dir);
}

}  // namespace
