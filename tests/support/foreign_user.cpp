// SPDX-License-Identifier: Apache-2.0
#include "foreign_user.h"

#include <fcntl.h>
#include <grp.h>
#include <linux/close_range.h>
#include <poll.h>
#include <signal.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <thread>

namespace navmap::test {

namespace {

void writeAll(int fd, const std::string& s) {
    std::size_t off = 0;
    while (off < s.size()) {
        const ssize_t n = ::write(fd, s.data() + off, s.size() - off);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            return;
        }
        off += static_cast<std::size_t>(n);
    }
}

}  // namespace

std::string cannotSwitchUser() {
    if (::geteuid() != 0) {
        return "runs as uid " + std::to_string(::geteuid()) + ", not root: cannot run a client as another uid";
    }
    return {};
}

ForeignProcess::ForeignProcess(const ForeignUser& user, const std::function<std::string()>& work) {
    int report[2];
    int hold[2];
    if (::pipe2(report, O_CLOEXEC) != 0) {
        return;
    }
    if (::pipe2(hold, O_CLOEXEC) != 0) {
        ::close(report[0]);
        ::close(report[1]);
        return;
    }
    m_pid = ::fork();
    if (m_pid == 0) {
        // Child: the pipes to 3 and 4, every other inherited descriptor closed (the parent's
        // listening sockets and connections must not live on in here).
        const int out = ::fcntl(report[1], F_DUPFD, 100);
        const int in = ::fcntl(hold[0], F_DUPFD, 100);
        ::dup2(out, 3);
        ::dup2(in, 4);
        ::syscall(SYS_close_range, 5U, ~0U, 0U);
        std::string result;
        if (::setgroups(user.groups.size(), user.groups.data()) != 0) {
            result = std::string("setgroups: ") + std::strerror(errno);
        } else if (::setresgid(user.gid, user.gid, user.gid) != 0) {
            result = std::string("setresgid: ") + std::strerror(errno);
        } else if (::setresuid(user.uid, user.uid, user.uid) != 0) {
            result = std::string("setresuid: ") + std::strerror(errno);
        } else {
            result = work();
        }
        writeAll(3, result);
        ::close(3);
        char c = 0;
        while (::read(4, &c, 1) < 0 && errno == EINTR) {}
        ::_exit(0);
    }
    ::close(report[1]);
    ::close(hold[0]);
    if (m_pid < 0) {
        ::close(report[0]);
        ::close(hold[1]);
        return;
    }
    m_report_fd = report[0];
    m_release_fd = hold[1];
}

std::string ForeignProcess::result(std::chrono::milliseconds timeout) {
    if (m_have_result || m_report_fd < 0) {
        return m_result;
    }
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
        if (left <= 0) {
            return m_result;
        }
        pollfd p{m_report_fd, POLLIN, 0};
        if (::poll(&p, 1, static_cast<int>(left)) <= 0) {
            continue;
        }
        char buf[4096];
        const ssize_t n = ::read(m_report_fd, buf, sizeof(buf));
        if (n > 0) {
            m_result.append(buf, static_cast<std::size_t>(n));
            continue;
        }
        if (n < 0 && errno == EINTR) {
            continue;
        }
        m_have_result = true;  // EOF: the child wrote everything
        ::close(m_report_fd);
        m_report_fd = -1;
        return m_result;
    }
}

void ForeignProcess::release() {
    if (m_release_fd >= 0) {
        ::close(m_release_fd);
        m_release_fd = -1;
    }
}

ForeignProcess::~ForeignProcess() {
    release();
    if (m_report_fd >= 0) {
        ::close(m_report_fd);
    }
    if (m_pid <= 0) {
        return;
    }
    int status = 0;
    for (int i = 0; i < 500; ++i) {
        if (::waitpid(m_pid, &status, WNOHANG) == m_pid) {
            return;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ::kill(m_pid, SIGKILL);
    ::waitpid(m_pid, &status, 0);
}

}  // namespace navmap::test
