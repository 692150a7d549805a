// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/can/socketcan_source.h"

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "navmap/ipc/can/socketcan_codec.h"
#include "navmap/ipc/net/sys_error.h"

namespace navmap::ipc {

using net::sysError;

const char* SocketCanStatus::stateName(State s) noexcept {
    switch (s) {
        case State::Closed: return "closed";
        case State::Open: return "open";
        case State::Retrying: return "retrying";
    }
    return "?";
}

SocketCanSource::SocketCanSource(SocketCanOptions options)
    : m_options(std::move(options)), m_backoff(m_options.backoff_initial, m_options.backoff_maximum) {}

SocketCanSource::~SocketCanSource() { closeSocket(); }

void SocketCanSource::closeSocket() {
    m_fd.reset();
    m_drops_before = m_status.kernel_drops;
    m_drops_at_open = 0;
}

void SocketCanSource::failOpen(std::string error) {
    closeSocket();
    ++m_status.open_failures;
    m_status.last_error = std::move(error);
    m_status.state = SocketCanStatus::State::Retrying;
    m_backoff.failed(Backoff::Clock::now());
}

bool SocketCanSource::open() {
    const std::string& name = m_options.interface_name;
    if (name.empty() || name.size() >= IFNAMSIZ) {
        failOpen("interface name '" + name + "' must have 1.." + std::to_string(IFNAMSIZ - 1) + " characters");
        return false;
    }
    m_fd.reset(::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW));
    if (!m_fd.valid()) {
        failOpen(sysError("socket(PF_CAN)", name, errno));
        return false;
    }
    const unsigned index = ::if_nametoindex(name.c_str());
    if (index == 0) {
        failOpen(sysError("if_nametoindex", name, errno));
        return false;
    }
    ifreq ifr{};
    std::memcpy(ifr.ifr_name, name.c_str(), name.size() + 1);
    if (::ioctl(m_fd.get(), SIOCGIFFLAGS, &ifr) < 0) {
        failOpen(sysError("ioctl(SIOCGIFFLAGS)", name, errno));
        return false;
    }
    if ((ifr.ifr_flags & IFF_UP) == 0) {
        failOpen("interface " + name + " is down");
        return false;
    }
    const int one = 1;
    if (m_options.receive_fd) {
        // Older kernels or controllers without FD: keep going with classic frames.
        m_status.fd_enabled = ::setsockopt(m_fd.get(), SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &one, sizeof one) == 0;
    }
    const auto filters = buildRawFilters(m_options.frame_keys);
    if (!filters.empty() && ::setsockopt(m_fd.get(), SOL_CAN_RAW, CAN_RAW_FILTER, filters.data(),
                                         static_cast<socklen_t>(filters.size() * sizeof(can_filter))) < 0) {
        failOpen(sysError("setsockopt(CAN_RAW_FILTER)", name, errno));
        return false;
    }
    if (m_options.receive_error_frames) {
        const can_err_mask_t mask = CAN_ERR_MASK;
        if (::setsockopt(m_fd.get(), SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &mask, sizeof mask) < 0) {
            failOpen(sysError("setsockopt(CAN_RAW_ERR_FILTER)", name, errno));
            return false;
        }
    }
    if (::setsockopt(m_fd.get(), SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof one) < 0) {
        failOpen(sysError("setsockopt(SO_TIMESTAMPNS)", name, errno));
        return false;
    }
    if (::setsockopt(m_fd.get(), SOL_SOCKET, SO_RXQ_OVFL, &one, sizeof one) < 0) {
        failOpen(sysError("setsockopt(SO_RXQ_OVFL)", name, errno));
        return false;
    }
    if (m_options.receive_buffer_bytes > 0) {
        // Failure is not fatal: the default buffer still works, drops are counted.
        (void)::setsockopt(m_fd.get(), SOL_SOCKET, SO_RCVBUF, &m_options.receive_buffer_bytes,
                           sizeof m_options.receive_buffer_bytes);
    }
    sockaddr_can addr{};
    addr.can_family = AF_CAN;
    addr.can_ifindex = static_cast<int>(index);
    if (::bind(m_fd.get(), reinterpret_cast<const sockaddr*>(&addr), sizeof addr) < 0) {
        failOpen(sysError("bind", name, errno));
        return false;
    }
    m_backoff.succeeded();
    m_status.state = SocketCanStatus::State::Open;
    ++m_status.opens;
    return true;
}

std::size_t SocketCanSource::poll(const FrameSink& sink, std::size_t max_frames) {
    if (!m_fd.valid()) {
        if (!m_backoff.due(Backoff::Clock::now()) || !open()) {
            return 0;
        }
    }
    std::size_t delivered = 0;
    for (std::size_t i = 0; i < max_frames; ++i) {
        canfd_frame kframe{};
        iovec iov{&kframe, sizeof kframe};
        alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timespec)) + CMSG_SPACE(sizeof(std::uint32_t))];
        msghdr msg{};
        msg.msg_iov = &iov;
        msg.msg_iovlen = 1;
        msg.msg_control = control;
        msg.msg_controllen = sizeof control;
        const ssize_t n = ::recvmsg(m_fd.get(), &msg, MSG_DONTWAIT);
        if (n < 0) {
            const int err = errno;
            if (err == EAGAIN || err == EWOULDBLOCK) {
                break;
            }
            if (err == EINTR) {
                continue;
            }
            // ENETDOWN (interface set down), ENODEV (interface removed), ...: re-open later.
            failOpen(sysError("recvmsg", m_options.interface_name, err));
            break;
        }
        CanTime stamp{};
        bool have_stamp = false;
        for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
            if (c->cmsg_level != SOL_SOCKET) {
                continue;
            }
            if (c->cmsg_type == SO_TIMESTAMPNS) {
                timespec ts{};
                std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
                stamp = CanTime(std::chrono::seconds(ts.tv_sec) + std::chrono::nanoseconds(ts.tv_nsec));
                have_stamp = true;
            } else if (c->cmsg_type == SO_RXQ_OVFL) {
                std::uint32_t drops = 0;
                std::memcpy(&drops, CMSG_DATA(c), sizeof drops);
                m_drops_at_open = drops;
                m_status.kernel_drops = m_drops_before + drops;
            }
        }
        if (!have_stamp) {
            stamp = CanTime(std::chrono::duration_cast<std::chrono::nanoseconds>(CanClock::now().time_since_epoch()));
        }
        const auto frame = frameFromKernel(&kframe, static_cast<std::size_t>(n), stamp);
        if (!frame) {
            ++m_status.bad_frames;
            continue;
        }
        if (frame->error()) {
            ++m_status.error_frames;
            const ErrorFrameInfo info = classifyErrorFrame(*frame);
            if (info.bus_off) {
                ++m_status.bus_off;
            }
            if (info.controller_problem) {
                ++m_status.controller_problems;
            }
            if (info.protocol_violation || info.transceiver || info.no_ack || info.lost_arbitration || info.bus_error ||
                info.tx_timeout) {
                ++m_status.other_errors;
            }
            m_status.last_error_frame = info.describe();
            m_status.last_error_frame_time = frame->timestamp;
            continue;
        }
        ++m_status.frames;
        if (frame->fd()) {
            ++m_status.fd_frames;
        }
        sink(*frame);
        ++delivered;
    }
    return delivered;
}

void SocketCanSource::waitReadable(std::chrono::milliseconds timeout) {
    if (!m_fd.valid()) {
        const auto now = Backoff::Clock::now();
        // Round up: waking a little early would find the retry not yet due.
        const auto until_retry = std::chrono::ceil<std::chrono::milliseconds>(m_backoff.nextAttempt() - now);
        const auto wait = std::max(std::chrono::milliseconds(0), std::min(timeout, until_retry));
        ::poll(nullptr, 0, static_cast<int>(wait.count()));
        return;
    }
    pollfd p{m_fd.get(), POLLIN, 0};
    ::poll(&p, 1, static_cast<int>(timeout.count()));
}

Status SocketCanSource::send(const CanFrame& frame) {
    if (!m_fd.valid()) {
        return Error{"send(" + m_options.interface_name + "): socket is not open"};
    }
    canfd_frame k{};
    const std::size_t bytes = frameToKernel(frame, k);
    if (bytes == CANFD_MTU && !m_status.fd_enabled) {
        return Error{"send(" + m_options.interface_name + "): CAN FD frames are not enabled on this socket"};
    }
    const ssize_t n = ::send(m_fd.get(), &k, bytes, MSG_DONTWAIT);
    if (n < 0) {
        return Error{sysError("send", m_options.interface_name, errno)};
    }
    if (static_cast<std::size_t>(n) != bytes) {
        return Error{"send(" + m_options.interface_name + "): short write"};
    }
    return {};
}

}  // namespace navmap::ipc
