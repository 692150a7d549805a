// SPDX-License-Identifier: Apache-2.0
#pragma once
// Clients that run as another user, for tests of peer checks and per-uid limits: a forked child
// drops to the given uid/gid/groups (setgroups, setresgid, setresuid; no way back), does its
// work and reports, and stays alive with whatever it opened until the test releases it.
// Switching users needs root (the tests run as root here and in CI); cannotSwitchUser() says
// why not otherwise, for GTEST_SKIP().

#include <sys/types.h>

#include <chrono>
#include <functional>
#include <string>
#include <vector>

namespace navmap::test {

struct ForeignUser {
    uid_t uid = 65534;          ///< nobody
    gid_t gid = 65534;          ///< nogroup
    std::vector<gid_t> groups;  ///< supplementary groups; empty: none
};

/// Empty when this process may switch users; otherwise the reason, e.g. "runs as uid 1000, not
/// root: cannot run a client as another uid".
std::string cannotSwitchUser();

class ForeignProcess {
public:
    /// Forks; the child closes every inherited descriptor but stderr and its two pipes, becomes
    /// `user`, runs `work` and sends back its result. A failed switch reports "setresuid: ...".
    ForeignProcess(const ForeignUser& user, const std::function<std::string()>& work);
    /// Releases the child and waits for it (SIGKILL after 5 s).
    ~ForeignProcess();
    ForeignProcess(const ForeignProcess&) = delete;
    ForeignProcess& operator=(const ForeignProcess&) = delete;

    /// What `work` returned; empty when nothing came within `timeout`.
    std::string result(std::chrono::milliseconds timeout = std::chrono::seconds(30));
    /// Lets the child exit (closing what it opened).
    void release();

private:
    pid_t m_pid = -1;
    int m_report_fd = -1;
    int m_release_fd = -1;
    std::string m_result;
    bool m_have_result = false;
};

}  // namespace navmap::test
