// SPDX-License-Identifier: Apache-2.0
// sysError: "<call>(<object>): <strerror>", alone and as the socket users in ipc/ report real
// failures with it (the control socket, its client, the frame server).

#include "navmap/ipc/net/sys_error.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "navmap/ipc/control/control_client.h"
#include "navmap/ipc/control/control_server.h"
#include "navmap/ipc/control/control_state.h"
#include "navmap/ipc/stream/frame_server.h"
#include "open_fds.h"

namespace {

using navmap::ipc::net::sysError;

// A path under a directory that does not exist: bind() and connect() fail with ENOENT.
std::string missingPath(const char* name) {
    return "/tmp/navmap-net-missing-" + std::to_string(::getpid()) + "/" + name;
}

TEST(SysErrorTest, NamesTheCallTheObjectAndTheErrnoText) {
    EXPECT_EQ(sysError("bind", "/run/navmap/frames.sock", EACCES),
              std::string("bind(/run/navmap/frames.sock): ") + std::strerror(EACCES));
    EXPECT_EQ(sysError("setsockopt(CAN_RAW_FILTER)", "can0", ENODEV),
              std::string("setsockopt(CAN_RAW_FILTER)(can0): ") + std::strerror(ENODEV));
}

TEST(SysErrorTest, ReadsErrnoWhenNotGivenAndLeavesItAsItWas) {
    errno = ECONNREFUSED;
    const std::string text = sysError("connect", "127.0.0.1:7000");
    EXPECT_EQ(text, std::string("connect(127.0.0.1:7000): ") + std::strerror(ECONNREFUSED));
    EXPECT_EQ(errno, ECONNREFUSED);
}

TEST(SysErrorTest, ControlServerBindFailureNamesCallPathAndReason) {
    const std::string path = missingPath("control.sock");
    navmap::ipc::ControlState state;
    navmap::ipc::ControlServerConfig config;
    config.socket_path = path;
    const int before = navmap::test::countOpenFds();
    auto server = navmap::ipc::ControlServer::create(config, state);
    ASSERT_FALSE(server);
    EXPECT_EQ(server.error().message, "bind(" + path + "): " + std::strerror(ENOENT));
    EXPECT_EQ(navmap::test::countOpenFds(), before) << "the socket of the failed create is closed";
}

TEST(SysErrorTest, ControlClientConnectFailureNamesCallPathAndReason) {
    const std::string path = missingPath("control.sock");
    const int before = navmap::test::countOpenFds();
    auto client = navmap::ipc::ControlClient::connect(path);
    ASSERT_FALSE(client);
    EXPECT_EQ(client.error().message, "connect(" + path + "): " + std::strerror(ENOENT));
    EXPECT_EQ(navmap::test::countOpenFds(), before);
}

TEST(SysErrorTest, FrameServerBindFailureNamesCallPathAndReason) {
    navmap::ipc::FrameServerOptions options;
    options.unix_path = missingPath("frames.sock");
    const int before = navmap::test::countOpenFds();
    {
        navmap::ipc::FrameServer server(options);
        const auto st = server.start();
        ASSERT_FALSE(st);
        EXPECT_EQ(st.message(), "bind(" + options.unix_path + "): " + std::strerror(ENOENT));
    }
    EXPECT_EQ(navmap::test::countOpenFds(), before);
}

}  // namespace
