// SPDX-License-Identifier: Apache-2.0
// ControlServer over a real Unix socket: round trips into ControlState snapshots, garbage and
// over-long lines, subscriptions and events, SO_PEERCRED (with clients running as other uids),
// socket mode and group, stale/live socket files, client limits, slow subscribers, the
// own-thread mode, and no leaked fds.

#include <gtest/gtest.h>

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <fstream>
#include <future>
#include <thread>

#include <nlohmann/json.hpp>

#include "control_test_util.h"
#include "foreign_user.h"
#include "navmap/ipc/control/control_client.h"
#include "navmap/ipc/control/control_protocol.h"
#include "navmap/ipc/control/control_server.h"
#include "navmap/ipc/control/control_state.h"
#include "wait_for.h"

using namespace navmap::ipc;
using namespace std::chrono_literals;
using navmap::test::countOpenFds;

namespace {

using Fixture = navmap::test::ControlServerFixture;

std::string req(ControlClient& c, const std::string& line) {
    auto r = c.request(line, 3s);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? r.value() : std::string();
}

}  // namespace

TEST(ControlServer, CommandsReachTheSnapshotsAndRepliesAreExact) {
    const int fds = countOpenFds();
    {
        Fixture f;
        ASSERT_TRUE(f.server);
        auto c = f.connect();
        EXPECT_EQ(f.state.route(), nullptr);
        EXPECT_EQ(
            req(c,
                R"({"cmd":"set_route","id":"r1","points":[[42.5075,1.5218],[42.51,1.53]],"maneuvers":[{"index":1,"type":"turn_left","text":"CG-2"}]})"),
            R"({"ok":true,"cmd":"set_route","id":"r1","maneuvers":1,"points":2})");
        const auto route = f.state.route();
        ASSERT_NE(route, nullptr);
        EXPECT_EQ(route->id, "r1");
        ASSERT_EQ(route->points.size(), 2U);
        EXPECT_DOUBLE_EQ(route->points[1].lat_deg, 42.51);
        EXPECT_EQ(route->maneuvers.at(0).text, "CG-2");

        EXPECT_EQ(req(c, R"({"cmd":"set_view","display":"hud","mode":"snail","orientation":"north-up"})"),
                  R"({"ok":true,"cmd":"set_view"})");
        EXPECT_EQ(req(c, R"({"cmd":"set_style","style":"night","id":"q2"})"),
                  R"({"ok":true,"cmd":"set_style","id":"q2"})");
        EXPECT_EQ(f.state.view()->ground, Ground::LandCover);
        EXPECT_EQ(req(c, R"({"cmd":"set_style","ground":"orthoimage"})"), R"({"ok":true,"cmd":"set_style"})");
        const auto view = f.state.view();
        EXPECT_EQ(view->style, MapStyle::Night);  // kept: only the ground was given
        EXPECT_EQ(view->ground, Ground::Orthoimage);
        EXPECT_EQ(view->displays.at("hud").mode, ViewMode::Snail);
        EXPECT_EQ(view->displays.at("hud").orientation, ViewOrientation::NorthUp);
        EXPECT_EQ(view->displays.at("cluster").mode, ViewMode::Auto);

        // Unknown display: rejected by the handler, nothing changes.
        EXPECT_EQ(
            req(c, R"({"cmd":"set_view","display":"rear","mode":"bird"})"),
            R"j({"ok":false,"cmd":"set_view","error":"unknown display \"rear\" (expected center | cluster | hud)"})j");
        EXPECT_EQ(f.state.view(), view);

        const auto status = nlohmann::json::parse(req(c, R"({"cmd":"get_status"})"));
        EXPECT_EQ(status["ok"], true);
        EXPECT_EQ(status["status"]["route"]["id"], "r1");
        EXPECT_EQ(status["status"]["style"], "night");
        EXPECT_EQ(status["status"]["ground"], "orthoimage");
        EXPECT_EQ(status["status"]["displays"]["hud"]["mode"], "snail");
        EXPECT_TRUE(status["status"]["displays"]["hud"]["camera"].is_null());
        EXPECT_EQ(status["status"]["control"]["clients"], 1);

        EXPECT_EQ(req(c, R"({"cmd":"clear_route"})"), R"({"ok":true,"cmd":"clear_route"})");
        EXPECT_EQ(f.state.route(), nullptr);
        const auto st = f.server->stats();
        EXPECT_EQ(st.commands, 6U);
        EXPECT_EQ(st.errors, 1U);
    }
    EXPECT_EQ(countOpenFds(), fds);
}

TEST(ControlServer, GarbageGetsAnErrorPerLineAndChangesNothing) {
    const int fds = countOpenFds();
    {
        Fixture f;
        ASSERT_TRUE(f.server);
        auto c = f.connect();
        ASSERT_EQ(req(c, R"({"cmd":"set_route","id":"good","points":[[1,2],[3,4]]})").substr(0, 11), R"({"ok":true,)");
        const auto route = f.state.route();
        const auto view = f.state.view();
        // Several lines in one write, CRLF, blank lines, binary junk.
        ASSERT_TRUE(c.send("hello\r\n\n{\"cmd\":\"set_route\",\"id\":\"bad\",\"points\":[[1,2],[3,4],[5,6],[95,1]]}\n"
                           "\x01\x02\xff\n{\"cmd\":\"set_style\",\"style\":\"dusk\"}")
                        .ok());
        auto l1 = c.readLine(3s);
        auto l2 = c.readLine(3s);
        auto l3 = c.readLine(3s);
        auto l4 = c.readLine(3s);
        ASSERT_TRUE(l1.ok() && l2.ok() && l3.ok() && l4.ok());
        EXPECT_EQ(
            l1.value().rfind(
                R"({"ok":false,"error":"invalid JSON: parse error at line 1, column 1: syntax error while parsing value)",
                0),
            0U)
            << l1.value();
        EXPECT_EQ(
            l2.value(),
            R"({"ok":false,"cmd":"set_route","id":"bad","error":"points[3]: latitude 95 out of range [-90, 90]"})");
        EXPECT_EQ(l3.value().rfind(R"({"ok":false,"error":"invalid JSON)", 0), 0U) << l3.value();
        EXPECT_EQ(l4.value(),
                  R"({"ok":false,"cmd":"set_style","error":"\"style\": \"dusk\" is not one of day | night | auto"})");
        // Still connected, state untouched.
        EXPECT_EQ(req(c, R"({"cmd":"get_status","id":"after"})").substr(0, 42),
                  R"({"ok":true,"cmd":"get_status","id":"after")");
        EXPECT_EQ(f.state.route(), route);
        EXPECT_EQ(f.state.view(), view);
        EXPECT_EQ(f.server->stats().errors, 4U);
    }
    EXPECT_EQ(countOpenFds(), fds);
}

TEST(ControlServer, OverlongLineDisconnectsWithAReason) {
    const int fds = countOpenFds();
    {
        ControlServerConfig cfg;
        cfg.limits.max_line_bytes = 4096;
        Fixture f(cfg);
        ASSERT_TRUE(f.server);
        auto c = f.connect();
        auto other = f.connect();
        // Raw writes without a newline: the first 3000 bytes are fine, 6000 are not.
        const std::string chunk(3000, 'x');
        ASSERT_EQ(::send(c.fd(), chunk.data(), chunk.size(), MSG_NOSIGNAL), 3000);
        std::this_thread::sleep_for(20ms);
        EXPECT_EQ(f.server->stats().overlong_disconnects, 0U);
        ASSERT_EQ(::send(c.fd(), chunk.data(), chunk.size(), MSG_NOSIGNAL), 3000);
        auto l = c.readLine(3s);
        ASSERT_TRUE(l.ok()) << l.error().message;
        EXPECT_EQ(l.value(), R"({"ok":false,"error":"line longer than 4096 bytes; disconnecting"})");
        auto eof = c.readLine(3s);
        ASSERT_FALSE(eof.ok());
        EXPECT_NE(eof.error().message.find("connection closed by the server"), std::string::npos);
        EXPECT_EQ(f.server->stats().overlong_disconnects, 1U);
        // Other clients are unaffected; a line just under the limit is fine.
        std::string padded = R"({"cmd":"get_status","id":")" + std::string(200, 'p') + "\"}";
        padded += std::string(4096 - padded.size(), ' ');
        EXPECT_EQ(req(other, padded).substr(0, 30), R"({"ok":true,"cmd":"get_status",)");
    }
    EXPECT_EQ(countOpenFds(), fds);
}

TEST(ControlServer, SubscribersReceiveTheirEvents) {
    const int fds = countOpenFds();
    {
        Fixture f;
        ASSERT_TRUE(f.server);
        auto all = f.connect();
        auto lost_only = f.connect();
        auto none = f.connect();
        EXPECT_EQ(
            req(all, R"({"cmd":"subscribe"})"),
            R"({"ok":true,"cmd":"subscribe","events":["route_progress","position_lost","position_regained","off_route","back_on_route","gpu_reset"]})");
        EXPECT_EQ(req(lost_only, R"({"cmd":"subscribe","events":["position_lost"]})"),
                  R"({"ok":true,"cmd":"subscribe","events":["position_lost"]})");
        std::thread publisher([&] {
            ControlEvent e;
            e.kind = ControlEventKind::RouteProgress;
            e.route_id = "r1";
            e.driven_m = 120.5;
            e.remaining_m = 3400.0;
            f.server->publish(e);
            e.kind = ControlEventKind::PositionLost;
            e.since_s = 2.0;
            f.server->publish(e);
            e.kind = ControlEventKind::PositionRegained;
            f.server->publish(e);
        });
        publisher.join();
        auto e1 = all.nextEvent(3s);
        auto e2 = all.nextEvent(3s);
        auto e3 = all.nextEvent(3s);
        ASSERT_TRUE(e1.ok() && e2.ok() && e3.ok());
        EXPECT_EQ(e1.value(), R"({"event":"route_progress","id":"r1","driven_m":120.5,"remaining_m":3400.0})");
        EXPECT_EQ(e2.value(), R"({"event":"position_lost","since_s":2.0})");
        EXPECT_EQ(e3.value(), R"({"event":"position_regained"})");
        auto l1 = lost_only.nextEvent(3s);
        ASSERT_TRUE(l1.ok());
        EXPECT_EQ(l1.value(), R"({"event":"position_lost","since_s":2.0})");
        EXPECT_FALSE(lost_only.nextEvent(100ms).ok());
        EXPECT_FALSE(none.nextEvent(100ms).ok());
        // A request while events are flowing: the reply is returned, events are kept.
        f.server->publish({ControlEventKind::PositionRegained, {}, 0, 0, 0});
        std::this_thread::sleep_for(50ms);
        EXPECT_EQ(req(all, R"({"cmd":"clear_route"})"), R"({"ok":true,"cmd":"clear_route"})");
        auto kept = all.nextEvent(1s);
        ASSERT_TRUE(kept.ok());
        EXPECT_EQ(kept.value(), R"({"event":"position_regained"})");
        EXPECT_EQ(f.server->stats().events, 5U);
    }
    EXPECT_EQ(countOpenFds(), fds);
}

TEST(ControlServer, DuplicateKeysAreRefusedAndChangeNothing) {
    const int fds = countOpenFds();
    {
        Fixture f;
        ASSERT_TRUE(f.server);
        auto c = f.connect();
        ASSERT_EQ(req(c, R"({"cmd":"set_route","id":"kept","points":[[1,2],[3,4]]})").substr(0, 11), R"({"ok":true,)");
        const auto route = f.state.route();
        const auto view = f.state.view();
        // With the last key winning this was a clear_route.
        EXPECT_EQ(req(c, R"({"cmd":"get_status","cmd":"clear_route"})"),
                  R"({"ok":false,"error":"duplicate key \"cmd\""})");
        EXPECT_EQ(req(c, R"({"cmd":"set_route","id":"other","points":[[1,2],{"lat":5,"lat":6}]})"),
                  R"({"ok":false,"cmd":"set_route","id":"other","error":"points[1]: duplicate key \"lat\""})");
        EXPECT_EQ(req(c, R"({"cmd":"set_view","display":"cluster","mode":"bird","mode":"snail"})"),
                  R"({"ok":false,"cmd":"set_view","error":"duplicate key \"mode\""})");
        EXPECT_EQ(f.state.route(), route);
        EXPECT_EQ(f.state.route()->id, "kept");
        EXPECT_EQ(f.state.view(), view);
        EXPECT_EQ(f.server->stats().errors, 3U);
    }
    EXPECT_EQ(countOpenFds(), fds);
}

TEST(ControlServer, IdleConnectionsAreClosedSoSilentClientsCannotHoldEverySlot) {
    const int fds = countOpenFds();
    {
        ControlServerConfig cfg;  // 16 slots, as the daemon has
        cfg.idle_timeout = 400ms;
        Fixture f(cfg);
        ASSERT_TRUE(f.server);
        // A subscriber with nothing to receive waits for events: not idle. A client that sends
        // keep-alive blank lines is not idle either.
        auto subscriber = f.connect();
        EXPECT_EQ(req(subscriber, R"({"cmd":"subscribe","events":["position_lost"]})").substr(0, 11), R"({"ok":true,)");
        auto keepalive = f.connect();
        // Every other slot taken by a client that never says anything.
        std::vector<ControlClient> silent;
        for (std::size_t i = 0; i + 2 < cfg.max_clients; ++i) {
            silent.push_back(f.connect());
        }
        std::this_thread::sleep_for(100ms);
        EXPECT_EQ(f.server->stats().clients, cfg.max_clients);
        {
            auto refused = f.connect();
            auto l = refused.readLine(1s);
            ASSERT_TRUE(l.ok()) << l.error().message;
            EXPECT_EQ(l.value(), R"j({"ok":false,"error":"too many clients (limit 16)"})j");
        }
        // Past the timeout the silent clients get the reason and the end of the connection.
        for (int i = 0; i < 8; ++i) {
            ASSERT_TRUE(keepalive.send("").ok());
            std::this_thread::sleep_for(100ms);
        }
        for (auto& s : silent) {
            auto l = s.readLine(2s);
            ASSERT_TRUE(l.ok()) << l.error().message;
            EXPECT_EQ(l.value(), R"({"ok":false,"error":"idle for 0.4 s without a request; disconnecting"})");
            auto eof = s.readLine(2s);
            ASSERT_FALSE(eof.ok());
            EXPECT_NE(eof.error().message.find("connection closed by the server"), std::string::npos)
                << eof.error().message;
        }
        EXPECT_EQ(f.server->stats().idle_disconnects, silent.size());
        // A new client gets a slot and a reply; the subscriber and the keep-alive client stayed.
        auto fresh = f.connect();
        EXPECT_EQ(req(fresh, R"({"cmd":"get_status","id":"after"})").substr(0, 42),
                  R"({"ok":true,"cmd":"get_status","id":"after")");
        EXPECT_EQ(req(keepalive, R"({"cmd":"clear_route"})"), R"({"ok":true,"cmd":"clear_route"})");
        f.server->publish({ControlEventKind::PositionLost, {}, 0, 0, 3.0});
        auto ev = subscriber.nextEvent(2s);
        ASSERT_TRUE(ev.ok()) << ev.error().message;
        EXPECT_EQ(ev.value(), R"({"event":"position_lost","since_s":3.0})");
        EXPECT_EQ(f.server->stats().clients, 3U);
        EXPECT_EQ(f.server->stats().idle_disconnects, silent.size());
    }
    EXPECT_EQ(countOpenFds(), fds);
}

TEST(ControlServer, IdleTimeoutWakesAPollOnceCaller) {
    const int fds = countOpenFds();
    {
        ControlServerConfig cfg;
        cfg.idle_timeout = 200ms;
        Fixture f(cfg, false);  // stepped from this thread with pollOnce()
        ASSERT_TRUE(f.server);
        auto c = f.connect();
        ASSERT_TRUE(f.server->pollOnce(0ms).ok());
        EXPECT_EQ(f.server->stats().clients, 1U);
        // One long poll returns when the client turns idle, not after the caller's 10 s.
        const auto t0 = std::chrono::steady_clock::now();
        while (f.server->stats().idle_disconnects == 0 && std::chrono::steady_clock::now() - t0 < 5s) {
            ASSERT_TRUE(f.server->pollOnce(10s).ok());
        }
        EXPECT_LT(std::chrono::steady_clock::now() - t0, 2s);
        EXPECT_EQ(f.server->stats().idle_disconnects, 1U);
        EXPECT_EQ(f.server->stats().clients, 0U);
        auto l = c.readLine(1s);
        ASSERT_TRUE(l.ok()) << l.error().message;
        EXPECT_EQ(l.value(), R"({"ok":false,"error":"idle for 0.2 s without a request; disconnecting"})");
    }
    EXPECT_EQ(countOpenFds(), fds);
}

TEST(ControlServer, PeerCredentialsDecideWhoMayConnect) {
    const int fds = countOpenFds();
    {
        ControlServerConfig cfg;
        cfg.allow_root = false;
        cfg.allowed_uids = {::geteuid() + 1000};
        Fixture f(cfg);
        ASSERT_TRUE(f.server);
        auto c = f.connect();
        auto l = c.readLine(3s);
        ASSERT_TRUE(l.ok());
        EXPECT_EQ(l.value(), R"({"ok":false,"error":"peer uid )" + std::to_string(::geteuid()) + " (pid " +
                                 std::to_string(::getpid()) + ") is not allowed on " + f.server->path() + "\"}");
        EXPECT_FALSE(c.readLine(3s).ok());  // closed
        EXPECT_EQ(f.server->stats().refused_peer, 1U);
        EXPECT_EQ(f.server->stats().connections, 0U);
    }
    {
        // The own uid is allowed by default, and a listed gid admits too.
        ControlServerConfig cfg;
        cfg.allow_root = false;
        cfg.allowed_uids = {::geteuid() + 1000};
        cfg.allowed_gids = {::getegid()};
        Fixture f(cfg);
        auto c = f.connect();
        EXPECT_EQ(req(c, R"({"cmd":"clear_route"})"), R"({"ok":true,"cmd":"clear_route"})");
    }
    EXPECT_EQ(countOpenFds(), fds);
}

TEST(ControlServer, SocketFileModeStaleFilesAndLiveServers) {
    const int fds = countOpenFds();
    {
        ControlServerConfig cfg;
        cfg.socket_mode = 0640;
        Fixture f(cfg, false);
        ASSERT_TRUE(f.server);
        struct stat st {};
        ASSERT_EQ(::stat(f.server->path().c_str(), &st), 0);
        EXPECT_TRUE(S_ISSOCK(st.st_mode));
        EXPECT_EQ(st.st_mode & 0777, 0640U);

        // A second server on a live path is refused.
        ControlState other;
        ControlServerConfig cfg2;
        cfg2.socket_path = f.server->path();
        auto second = ControlServer::create(cfg2, other);
        ASSERT_FALSE(second.ok());
        EXPECT_EQ(second.error().message,
                  "bind(" + f.server->path() + "): Address in use (another server is listening)");

        // A stale socket file (bound, never listening) is replaced.
        const std::string stale = f.dir.file("stale.sock");
        const int s = ::socket(AF_UNIX, SOCK_STREAM, 0);
        sockaddr_un a{};
        a.sun_family = AF_UNIX;
        std::strcpy(a.sun_path, stale.c_str());
        ASSERT_EQ(::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
        ::close(s);
        cfg2.socket_path = stale;
        auto replaced = ControlServer::create(cfg2, other);
        ASSERT_TRUE(replaced.ok()) << replaced.error().message;
        replaced.value().reset();
        EXPECT_FALSE(std::filesystem::exists(stale));  // removed on destruction

        // Not a socket / too long / missing directory.
        const std::string plain = f.dir.file("plain");
        { std::ofstream(plain) << "x"; }
        cfg2.socket_path = plain;
        auto r = ControlServer::create(cfg2, other);
        ASSERT_FALSE(r.ok());
        EXPECT_EQ(r.error().message, "control socket path " + plain + ": exists and is not a socket");
        cfg2.socket_path = "/tmp/" + std::string(200, 'a');
        r = ControlServer::create(cfg2, other);
        ASSERT_FALSE(r.ok());
        EXPECT_EQ(r.error().message, "control socket path \"" + cfg2.socket_path + "\": length must be 1..107 bytes");
        cfg2.socket_path = f.dir.file("no/such/dir.sock");
        r = ControlServer::create(cfg2, other);
        ASSERT_FALSE(r.ok());
        EXPECT_EQ(r.error().message, "bind(" + cfg2.socket_path + "): No such file or directory");
        auto missing = ControlClient::connect(f.dir.file("absent.sock"));
        ASSERT_FALSE(missing.ok());
        EXPECT_EQ(missing.error().message, "connect(" + f.dir.file("absent.sock") + "): No such file or directory");
    }
    EXPECT_EQ(countOpenFds(), fds);
}

TEST(ControlServer, ClientLimitAndSlowSubscribers) {
    const int fds = countOpenFds();
    {
        ControlServerConfig cfg;
        cfg.max_clients = 2;
        cfg.max_output_bytes = 64 * 1024;
        Fixture f(cfg, false);  // stepped from this thread with pollOnce()
        ASSERT_TRUE(f.server);
        auto a = f.connect();
        auto b = f.connect();
        ASSERT_TRUE(f.server->pollOnce(50ms).ok());
        auto c = f.connect();
        ASSERT_TRUE(f.server->pollOnce(50ms).ok());
        auto l = c.readLine(1s);
        ASSERT_TRUE(l.ok());
        EXPECT_EQ(l.value(), R"j({"ok":false,"error":"too many clients (limit 2)"})j");
        EXPECT_EQ(f.server->stats().refused_full, 1U);

        // `a` subscribes and never reads: once the kernel buffers and 64 KiB are full it is dropped.
        ASSERT_TRUE(a.send(R"({"cmd":"subscribe"})").ok());
        ASSERT_TRUE(f.server->pollOnce(50ms).ok());
        ControlEvent e;
        e.kind = ControlEventKind::RouteProgress;
        e.route_id = std::string(200, 'r');
        for (int round = 0; round < 200 && f.server->stats().slow_disconnects == 0; ++round) {
            for (int k = 0; k < 500; ++k) {
                f.server->publish(e);
            }
            ASSERT_TRUE(f.server->pollOnce(0ms).ok());
        }
        EXPECT_EQ(f.server->stats().slow_disconnects, 1U);
        EXPECT_EQ(f.server->stats().clients, 1U);
        ASSERT_TRUE(b.send(R"({"cmd":"clear_route"})").ok());
        ASSERT_TRUE(f.server->pollOnce(100ms).ok());
        auto rb = b.readLine(1s);
        ASSERT_TRUE(rb.ok());
        EXPECT_EQ(rb.value(), R"({"ok":true,"cmd":"clear_route"})");
    }
    EXPECT_EQ(countOpenFds(), fds);
}

TEST(ControlServer, ManyClientsConcurrently) {
    const int fds = countOpenFds();
    {
        ControlServerConfig cfg;
        cfg.max_clients = 8;
        Fixture f(cfg);
        ASSERT_TRUE(f.server);
        std::atomic<int> ok{0};
        std::vector<std::thread> threads;
        threads.reserve(6);
        for (int t = 0; t < 6; ++t) {
            threads.emplace_back([&, t] {
                auto c = ControlClient::connect(f.server->path());
                if (!c.ok()) {
                    return;
                }
                for (int i = 0; i < 50; ++i) {
                    const std::string id = "t" + std::to_string(t) + "-" + std::to_string(i);
                    auto r = c.value().request(R"({"cmd":"set_route","id":")" + id + R"(","points":[[1,2],[3,4]]})");
                    if (r.ok() &&
                        r.value() == R"({"ok":true,"cmd":"set_route","id":")" + id + R"(","maneuvers":0,"points":2})") {
                        ++ok;
                    }
                }
            });
        }
        for (auto& t : threads) {
            t.join();
        }
        EXPECT_EQ(ok.load(), 300);
        EXPECT_EQ(f.state.route()->version, 300U);
    }
    EXPECT_EQ(countOpenFds(), fds);
}

TEST(ControlServer, SocketFileIs0660WithItsGroupWhateverTheUmask) {
    const int fds = countOpenFds();
    {
        ControlServerConfig cfg;
        const gid_t group = ::geteuid() == 0 ? 65534 : ::getegid();  // root may give it any group
        cfg.socket_group = group;
        const mode_t old = ::umask(0);
        Fixture f(cfg, false);
        ::umask(old);
        ASSERT_TRUE(f.server);
        struct stat st {};
        ASSERT_EQ(::stat(f.server->path().c_str(), &st), 0);
        EXPECT_EQ(st.st_mode & 07777, 0660U) << std::oct << (st.st_mode & 07777);
        EXPECT_EQ(st.st_gid, group);
    }
    EXPECT_EQ(countOpenFds(), fds);
}

TEST(ControlServer, MembersOfTheSocketGroupMayConnectOthersNot) {
    if (const auto why = navmap::test::cannotSwitchUser(); !why.empty()) {
        GTEST_SKIP() << why;
    }
    constexpr gid_t kHmi = 64000;
    ControlServerConfig cfg;
    cfg.socket_group = kHmi;
    Fixture f(cfg);
    ASSERT_TRUE(f.server);
    ASSERT_EQ(::chmod(std::filesystem::path(f.server->path()).parent_path().c_str(), 0755), 0);
    const std::string path = f.server->path();
    const auto clear_route = [path] {
        auto c = ControlClient::connect(path);
        if (!c.ok()) {
            return c.error().message;
        }
        auto r = c.value().request(R"({"cmd":"clear_route"})", 3s);
        return r.ok() ? r.value() : r.error().message;
    };
    // A member through a supplementary group (SO_PEERGROUPS), not through its primary gid.
    navmap::test::ForeignProcess member({64001, 64001, {kHmi}}, clear_route);
    EXPECT_EQ(member.result(), R"({"ok":true,"cmd":"clear_route"})");
    // Anyone else: the file mode keeps them out; were it wider, SO_PEERCRED would.
    navmap::test::ForeignProcess stranger({64002, 64002, {}}, clear_route);
    EXPECT_EQ(stranger.result(), "connect(" + path + "): Permission denied");
    ASSERT_EQ(::chmod(path.c_str(), 0666), 0);
    navmap::test::ForeignProcess stranger2({64002, 64002, {}}, clear_route);
    const std::string refused = stranger2.result();
    EXPECT_EQ(refused.rfind(R"({"ok":false,"error":"peer uid 64002 (pid )", 0), 0U) << refused;
    EXPECT_NE(refused.find(") is not allowed on " + path), std::string::npos) << refused;
    EXPECT_EQ(f.server->stats().refused_peer, 1U);
}

TEST(ControlState, SetViewCameraWinsOverTheModeUntilAModeOrNullClearsIt) {
    ControlState state{{"cluster", "hud"}};
    auto apply = [&](const char* line) {
        const auto r = parseControlLine(line);
        EXPECT_TRUE(r.command) << r.error;
        EXPECT_TRUE(state.setView(std::get<SetViewCommand>(r.command->body)).ok()) << line;
    };
    apply(R"({"cmd":"set_view","display":"cluster","camera":{"zoom":16.5,"pitch":60}})");
    EXPECT_EQ(state.view()->displays.at("cluster").camera, (ViewCamera{16.5, 60.0, std::nullopt}));
    EXPECT_EQ(state.view()->displays.at("cluster").mode, ViewMode::Auto);
    EXPECT_FALSE(state.view()->displays.at("hud").camera);
    EXPECT_FALSE(state.view()->displays.at("cluster").orientation_set) << "the display's own orientation applies";
    // The orientation leaves the camera as it is (it turns a camera without a fixed bearing).
    apply(R"({"cmd":"set_view","display":"cluster","orientation":"north-up"})");
    EXPECT_TRUE(state.view()->displays.at("cluster").camera);
    EXPECT_TRUE(state.view()->displays.at("cluster").orientation_set);
    auto status = state.status();
    EXPECT_EQ(status["displays"]["cluster"]["camera"], nlohmann::json({{"zoom", 16.5}, {"pitch", 60.0}}));
    // A mode given without a camera: the display follows the mode again.
    apply(R"({"cmd":"set_view","display":"cluster","mode":"snail"})");
    EXPECT_FALSE(state.view()->displays.at("cluster").camera);
    // Camera and mode together: the camera wins (the mode is kept for later).
    apply(R"({"cmd":"set_view","display":"cluster","mode":"bird","camera":{"zoom":14.5,"pitch":30,"bearing":90}})");
    EXPECT_EQ(state.view()->displays.at("cluster").camera, (ViewCamera{14.5, 30.0, 90.0}));
    EXPECT_EQ(state.view()->displays.at("cluster").mode, ViewMode::Bird);
    status = state.status();
    EXPECT_EQ(status["displays"]["cluster"]["camera"]["bearing"], 90.0);
    apply(R"({"cmd":"set_view","display":"cluster","camera":null})");
    EXPECT_FALSE(state.view()->displays.at("cluster").camera);
    EXPECT_EQ(state.view()->displays.at("cluster").mode, ViewMode::Bird);
}

namespace {

constexpr uid_t kNobody = 65534;

// Opens `count` connections to `path`, sends `line` on each and reads its first line; returns
// those lines (or the error), one per line. The connections stay open until the process ends:
// for a ForeignProcess standing in for another user's clients. With `wait_first`, then waits
// that long for a second line on the first connection and appends it after "first then: ".
std::string holdControlConnections(const std::string& path, const std::string& line, int count,
                                   std::chrono::milliseconds wait_first = 0ms) {
    static std::vector<ControlClient> held;  // the child's: kept until it exits
    std::string report;
    for (int i = 0; i < count; ++i) {
        auto c = ControlClient::connect(path);
        if (!c.ok()) {
            report += c.error().message + "\n";
            continue;
        }
        auto r = c.value().request(line, 3s);
        report += (r.ok() ? r.value() : r.error().message) + "\n";
        held.push_back(std::move(c.value()));
    }
    if (wait_first.count() > 0 && !held.empty()) {
        auto l = held.front().readLine(wait_first);
        report += "first then: " + (l.ok() ? l.value() : l.error().message) + "\n";
    }
    return report;
}

int countLines(const std::string& report, const std::string& line) {
    int n = 0;
    std::size_t at = 0;
    while ((at = report.find(line + "\n", at)) != std::string::npos) {
        n += at == 0 || report[at - 1] == '\n' ? 1 : 0;
        at += line.size() + 1;
    }
    return n;
}

}  // namespace

TEST(ControlServer, SubscribersThatLeaveTheirRepliesUnreadDoNotHoldTheSlots) {
    const int fds = countOpenFds();
    {
        ControlServerConfig cfg;  // 16 slots, as the daemon has
        cfg.idle_timeout = 400ms;
        Fixture f(cfg);
        ASSERT_TRUE(f.server);
        // A subscriber that reads its reply and its events, and sends nothing else.
        auto reader = f.connect();
        EXPECT_EQ(req(reader, R"({"cmd":"subscribe","events":["position_lost"]})"),
                  R"({"ok":true,"cmd":"subscribe","events":["position_lost"]})");
        // Fifteen that send one subscribe line and then neither send nor read anything.
        std::vector<ControlClient> stalled;
        for (int i = 0; i < 15; ++i) {
            stalled.push_back(f.connect());
            ASSERT_TRUE(stalled.back().send(R"({"cmd":"subscribe","events":["position_lost"]})").ok());
        }
        ASSERT_TRUE(navmap::test::waitFor([&] { return f.server->stats().commands == 16; }));
        {
            auto refused = f.connect();
            EXPECT_EQ(req(refused, R"({"cmd":"get_status"})"),
                      R"j({"ok":false,"error":"too many clients (limit 16)"})j");
        }
        // Events keep coming for 1.2 s (three timeouts); the reader reads each one.
        for (int i = 0; i < 12; ++i) {
            f.server->publish({ControlEventKind::PositionLost, {}, 0, 0, static_cast<double>(i)});
            auto ev = reader.nextEvent(2s);
            ASSERT_TRUE(ev.ok()) << ev.error().message;
            std::this_thread::sleep_for(100ms);
        }
        // Each stalled one finds its reply, the events it never read, the reason, and the end.
        for (auto& s : stalled) {
            std::vector<std::string> lines;
            for (;;) {
                auto l = s.readLine(2s);
                if (!l.ok()) {
                    EXPECT_NE(l.error().message.find("connection closed by the server"), std::string::npos)
                        << l.error().message;
                    break;
                }
                lines.push_back(l.value());
            }
            ASSERT_GE(lines.size(), 2U);
            EXPECT_EQ(lines.front(), R"({"ok":true,"cmd":"subscribe","events":["position_lost"]})");
            EXPECT_EQ(lines.back(),
                      R"({"ok":false,"error":"left its replies and events unread for 0.4 s; disconnecting"})");
        }
        EXPECT_EQ(f.server->stats().idle_disconnects, 15U);
        // The HMI's get_status is answered; the reading subscriber stayed and gets the next event.
        auto hmi = f.connect();
        EXPECT_EQ(req(hmi, R"({"cmd":"get_status","id":"hmi"})").substr(0, 40),
                  R"({"ok":true,"cmd":"get_status","id":"hmi")");
        f.server->publish({ControlEventKind::PositionLost, {}, 0, 0, 99.0});
        auto ev = reader.nextEvent(2s);
        ASSERT_TRUE(ev.ok()) << ev.error().message;
        EXPECT_EQ(ev.value(), R"({"event":"position_lost","since_s":99.0})");
    }
    EXPECT_EQ(countOpenFds(), fds);
}

TEST(ControlServer, AnotherUidIsCappedInConnectionsAndSubscribersAndNeverLocksOutTheHmi) {
    if (const auto why = navmap::test::cannotSwitchUser(); !why.empty()) {
        GTEST_SKIP() << why;
    }
    ControlServerConfig cfg;  // the daemon's limits: 16 slots, 8 per uid, 4 subscribers per uid
    cfg.socket_mode = 0666;
    cfg.allowed_uids = {kNobody};
    Fixture f(cfg);
    ASSERT_TRUE(f.server);
    ASSERT_EQ(::chmod(std::filesystem::path(f.server->path()).parent_path().c_str(), 0755), 0);
    const std::string path = f.server->path();
    // nobody opens 16 connections that each subscribe and read their reply, then hold them.
    navmap::test::ForeignProcess nobody({kNobody, kNobody, {}}, [path] {
        return holdControlConnections(path, R"({"cmd":"subscribe","events":["position_lost"]})", 16);
    });
    const std::string report = nobody.result();
    EXPECT_EQ(countLines(report, R"({"ok":true,"cmd":"subscribe","events":["position_lost"]})"), 4) << report;
    EXPECT_EQ(countLines(report,
                         R"j({"ok":false,"cmd":"subscribe","error":"too many subscribers from uid 65534 (limit 4)"})j"),
              4)
        << report;
    EXPECT_EQ(countLines(report, R"j({"ok":false,"error":"too many connections from uid 65534 (limit 8)"})j"), 8)
        << report;
    // The HMI (root here: privileged) is answered, with connections to spare.
    std::vector<ControlClient> hmi;
    for (int i = 0; i < 8; ++i) {
        hmi.push_back(f.connect());
        EXPECT_EQ(req(hmi.back(), R"({"cmd":"get_status","id":"hmi"})").substr(0, 40),
                  R"({"ok":true,"cmd":"get_status","id":"hmi")");
    }
    const auto s = f.server->stats();
    EXPECT_EQ(s.refused_uid_full, 8U);
    EXPECT_EQ(s.refused_subscribers, 4U);
    EXPECT_EQ(s.refused_full, 0U);
    EXPECT_EQ(s.evictions, 0U);
    EXPECT_EQ(s.clients, 16U);
    nobody.release();
}

TEST(ControlServer, APrivilegedPeerTakesTheSlotOfTheLongestSilentUnprivilegedOne) {
    if (const auto why = navmap::test::cannotSwitchUser(); !why.empty()) {
        GTEST_SKIP() << why;
    }
    ControlServerConfig cfg;
    cfg.socket_mode = 0666;
    cfg.allowed_uids = {64001, 64002, 64003};
    cfg.max_subscribers_per_uid = 8;
    Fixture f(cfg);
    ASSERT_TRUE(f.server);
    ASSERT_EQ(::chmod(std::filesystem::path(f.server->path()).parent_path().c_str(), 0755), 0);
    const std::string path = f.server->path();
    const std::string subscribe = R"({"cmd":"subscribe","events":["position_lost"]})";
    const std::string ok = R"({"ok":true,"cmd":"subscribe","events":["position_lost"]})";
    // Two other users take all 16 slots with subscribers that read what they get (not idle).
    // The first of 64001's connections is the one silent longest; it waits for what comes next.
    navmap::test::ForeignProcess first({64001, 64001, {}},
                                       [&] { return holdControlConnections(path, subscribe, 8, 10s); });
    ASSERT_TRUE(navmap::test::waitFor([&] { return f.server->stats().commands == 8; }, 10s));
    navmap::test::ForeignProcess second({64002, 64002, {}}, [&] { return holdControlConnections(path, subscribe, 8); });
    EXPECT_EQ(countLines(second.result(), ok), 8) << second.result();
    // A third unprivileged user finds no slot.
    navmap::test::ForeignProcess third({64003, 64003, {}}, [&] { return holdControlConnections(path, subscribe, 1); });
    EXPECT_EQ(third.result(), "{\"ok\":false,\"error\":\"too many clients (limit 16)\"}\n");
    // The HMI (root) gets a slot: 64001's first connection is told why and closed.
    auto hmi = f.connect();
    EXPECT_EQ(req(hmi, R"({"cmd":"get_status","id":"hmi"})").substr(0, 40),
              R"({"ok":true,"cmd":"get_status","id":"hmi")");
    const std::string report = first.result();
    EXPECT_EQ(countLines(report, ok), 8) << report;
    EXPECT_EQ(
        countLines(
            report,
            R"(first then: {"ok":false,"error":"slot taken by privileged uid 0 (all 16 in use); disconnecting"})"),
        1)
        << report;
    const auto s = f.server->stats();
    EXPECT_EQ(s.evictions, 1U);
    EXPECT_EQ(s.refused_full, 1U);
    EXPECT_EQ(s.clients, 16U);
    first.release();
    second.release();
    third.release();
}
