// SPDX-License-Identifier: Apache-2.0
#pragma once
// Helpers for control-socket tests: a private temporary directory, an fd count (libosmium
// count_fds style) to check that nothing leaks, and a control server to talk to.

#include <stdlib.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>

#include "navmap/ipc/control/control_client.h"
#include "navmap/ipc/control/control_server.h"
#include "navmap/ipc/control/control_state.h"
#include "open_fds.h"

namespace navmap::test {

/// mkdtemp directory under /tmp (short, so socket paths fit sun_path), removed at scope exit.
class TempDir {
public:
    TempDir() {
        char tmpl[] = "/tmp/navmap-ctl-XXXXXX";
        if (::mkdtemp(tmpl) != nullptr) {
            m_path = tmpl;
        }
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(m_path, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    [[nodiscard]] std::string file(const std::string& name) const { return m_path + "/" + name; }

private:
    std::string m_path;
};

/// A ControlServer on a socket in its own temporary directory, over a ControlState with the
/// three shipped profiles: on its own thread (`threaded`), or stepped by the test with pollOnce().
struct ControlServerFixture {
    TempDir dir;
    ipc::ControlState state{{"cluster", "hud", "center"}};
    std::unique_ptr<ipc::ControlServer> server;

    explicit ControlServerFixture(ipc::ControlServerConfig cfg = {}, bool threaded = true) {
        cfg.socket_path = dir.file("control.sock");
        auto r = ipc::ControlServer::create(cfg, state);
        if (!r.ok()) {
            ADD_FAILURE() << r.error().message;
            return;
        }
        server = std::move(r.value());
        if (threaded) {
            EXPECT_TRUE(server->start().ok());
        }
    }
    ipc::ControlClient connect() {
        auto c = ipc::ControlClient::connect(server->path());
        EXPECT_TRUE(c.ok()) << (c.ok() ? "" : c.error().message);
        return std::move(c.value());
    }
    /// Steps an unthreaded server until `done` or 100 rounds of 20 ms.
    template <class Done>
    void stepUntil(Done done) {
        for (int i = 0; i < 100 && !done(); ++i) {
            ASSERT_TRUE(server->pollOnce(std::chrono::milliseconds(20)).ok());
        }
    }
};

}  // namespace navmap::test
