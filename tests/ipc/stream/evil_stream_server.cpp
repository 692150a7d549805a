// SPDX-License-Identifier: Apache-2.0
#include "evil_stream_server.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/client/frame_ring.h"
#include "navmap/ipc/client/stream_profile.h"
#include "navmap/ipc/net/unique_fd.h"
#include "stream_test_util.h"

namespace navmap::stream_test {

using ipc::net::UniqueFd;
using Clock = std::chrono::steady_clock;

namespace {

constexpr std::uint32_t kSlots = 3;
std::atomic<int> g_servers{0};

// What navmapd answers (FrameStreamTransport::handshakeReply).
nlohmann::json honestReply(const ipc::StreamRequest& r, const ipc::FrameRingLayout& l) {
    nlohmann::json reply;
    reply["ok"] = true;
    reply["version"] = 1;
    reply["profile"] = {{"name", r.profile.name},     {"width", r.profile.width},
                        {"height", r.profile.height}, {"fps", r.profile.fps},
                        {"view", r.profile.view},     {"format", ipc::pixelFormatName(r.profile.format)}};
    reply["payload"] = ipc::streamPayloadName(r.payload);
    if (r.hold) {
        reply["hold"] = true;
    }
    if (r.meta) {
        reply["meta"] = ipc::kFrameMetaVersion;
    }
    reply["stride"] = l.stride;
    reply["header_bytes"] = ipc::kFrameHeaderBytes;
    if (r.payload == ipc::StreamPayload::Shm) {
        reply["ring"] = {{"slots", l.slots},
                         {"slot_bytes", l.slot_bytes},
                         {"total_bytes", l.total_bytes},
                         {"header_offset", ipc::kSlotHeaderOffset},
                         {"pixel_offset", ipc::kSlotPixelOffset}};
    }
    return reply;
}

bool writeAll(int fd, const std::uint8_t* data, std::size_t n) {
    while (n > 0) {
        const ssize_t w = ::write(fd, data, n);
        if (w <= 0) {
            return false;
        }
        data += w;
        n -= static_cast<std::size_t>(w);
    }
    return true;
}

// A descriptor of the kind `kind` holding `bytes` (a real ring with frame 1 in it).
UniqueFd makeRingFd(EvilRing kind, const std::vector<std::uint8_t>& bytes, std::string* name) {
    const int n = ++g_servers;
    *name = "evil-ring-" + std::to_string(getpid()) + "-" + std::to_string(n);
    UniqueFd fd;
    std::size_t size = bytes.size();
    switch (kind) {
        case EvilRing::None: return fd;
        case EvilRing::RegularFile: {
            std::string path = "/var/tmp/" + *name + "-XXXXXX";
            fd.reset(::mkstemp(path.data()));
            ::unlink(path.c_str());
            break;
        }
        case EvilRing::UnsealedMemfd: fd.reset(::memfd_create(name->c_str(), MFD_CLOEXEC)); break;
        case EvilRing::Sealed:
        case EvilRing::WritableMemfd:
        case EvilRing::ShortMemfd:
            fd.reset(::memfd_create(name->c_str(), MFD_CLOEXEC | MFD_ALLOW_SEALING));
            if (kind == EvilRing::ShortMemfd) {
                size -= 4096;
            }
            break;
    }
    if (!fd.valid() || !writeAll(fd.get(), bytes.data(), size)) {
        return UniqueFd();
    }
    if (kind == EvilRing::Sealed || kind == EvilRing::ShortMemfd) {
        ::fcntl(fd.get(), F_ADD_SEALS, F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_WRITE | F_SEAL_SEAL);
    } else if (kind == EvilRing::WritableMemfd) {
        ::fcntl(fd.get(), F_ADD_SEALS, F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_SEAL);
    }
    return fd;
}

// Whether process `pid` maps the file `fd` (same inode, our name in the path).
bool peerMaps(pid_t pid, int fd, const std::string& name) {
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        return false;
    }
    std::ifstream maps("/proc/" + std::to_string(pid) + "/maps");
    std::string line;
    const std::string inode = " " + std::to_string(st.st_ino) + " ";
    while (std::getline(maps, line)) {
        if (line.find(inode) != std::string::npos && line.find(name) != std::string::npos) {
            return true;
        }
    }
    return false;
}

// Waits until the peer maps `fd` (true) or closes the connection (false), at most 5 s.
bool waitForMapping(int conn, pid_t pid, int fd, const std::string& name) {
    const auto until = Clock::now() + std::chrono::seconds(5);
    while (Clock::now() < until) {
        if (peerMaps(pid, fd, name)) {
            return true;
        }
        pollfd p{conn, POLLIN, 0};
        if (::poll(&p, 1, 5) > 0) {
            char b = 0;
            if (::recv(conn, &b, 1, MSG_PEEK | MSG_DONTWAIT) <= 0) {
                return false;
            }
        }
    }
    return false;
}

std::string describeStatus(int status) {
    if (WIFEXITED(status)) {
        return "exit " + std::to_string(WEXITSTATUS(status));
    }
    if (WIFSIGNALED(status)) {
        return "killed by signal " + std::to_string(WTERMSIG(status)) + " (" + strsignal(WTERMSIG(status)) + ")";
    }
    return "status " + std::to_string(status);
}

}  // namespace

const char* evilRingName(EvilRing ring) {
    switch (ring) {
        case EvilRing::Sealed: return "sealed memfd";
        case EvilRing::RegularFile: return "regular file";
        case EvilRing::UnsealedMemfd: return "unsealed memfd";
        case EvilRing::WritableMemfd: return "memfd without a write seal";
        case EvilRing::ShortMemfd: return "memfd shorter than the reply";
        case EvilRing::None: return "no descriptor";
    }
    return "?";
}

EvilStreamServer::EvilStreamServer(EvilBehaviour behaviour)
    : m_behaviour(std::move(behaviour)),
      m_path(uniqueSocketPath("evil-" + std::to_string(g_servers.fetch_add(1) + 1))) {
    ::unlink(m_path.c_str());
    m_listen = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    std::snprintf(a.sun_path, sizeof(a.sun_path), "%s", m_path.c_str());
    if (m_listen < 0 || ::bind(m_listen, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0 ||
        ::listen(m_listen, 16) != 0) {
        std::fprintf(stderr, "EvilStreamServer(%s): %s\n", m_path.c_str(), std::strerror(errno));
    }
    m_thread = std::thread([this] { serve(); });
}

EvilStreamServer::~EvilStreamServer() {
    m_run = false;
    m_thread.join();
    ::close(m_listen);
    ::unlink(m_path.c_str());
}

void EvilStreamServer::serve() {
    while (m_run) {
        pollfd p{m_listen, POLLIN, 0};
        if (::poll(&p, 1, 20) <= 0) {
            continue;
        }
        UniqueFd conn(::accept4(m_listen, nullptr, nullptr, SOCK_CLOEXEC));
        if (conn.valid()) {
            serveOne(conn.get());
        }
    }
}

void EvilStreamServer::serveOne(int fd) {
    // The handshake line.
    std::string line;
    const auto until = Clock::now() + std::chrono::seconds(3);
    while (line.find('\n') == std::string::npos && Clock::now() < until) {
        pollfd p{fd, POLLIN, 0};
        if (::poll(&p, 1, 20) <= 0) {
            continue;
        }
        char buf[4096];
        const ssize_t n = ::recv(fd, buf, sizeof(buf), 0);
        if (n <= 0) {
            return;
        }
        line.append(buf, static_cast<std::size_t>(n));
    }
    ++m_handshakes;
    auto req = ipc::parseStreamRequest(line.substr(0, line.find('\n')));
    if (!req) {
        return;
    }
    const ipc::StreamProfile& prof = req.value().profile;
    // A real ring with frame 1 in it: the bytes every kind of descriptor carries.
    auto ring = ipc::FrameRing::create("evil-source", kSlots, static_cast<std::uint32_t>(prof.width),
                                       static_cast<std::uint32_t>(prof.height), prof.format);
    if (!ring) {
        return;
    }
    const auto pixels = sequencePattern(prof.width, prof.height, 1);
    ring.value()->write(ipc::FrameView{
        pixels.data(), prof.width, prof.height, 0, ipc::PixelFormat::Rgba8, 0, 0, m_behaviour.validity, {}});
    const ipc::FrameRingLayout& l = ring.value()->layout();
    std::vector<std::uint8_t> bytes(l.total_bytes);
    if (::pread(ring.value()->fd(), bytes.data(), bytes.size(), 0) != static_cast<ssize_t>(bytes.size())) {
        return;
    }
    nlohmann::json reply = honestReply(req.value(), l);
    if (!m_behaviour.patch.empty()) {
        reply.merge_patch(nlohmann::json::parse(m_behaviour.patch));
    }
    const std::string text = (m_behaviour.line.empty() ? reply.dump() : m_behaviour.line) + "\n";
    std::string name;
    const UniqueFd ring_fd = makeRingFd(m_behaviour.ring, bytes, &name);

    iovec iov{const_cast<char*>(text.data()), text.size()};
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int))] = {};
    msghdr msg{};
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    if (ring_fd.valid()) {
        msg.msg_control = control;
        msg.msg_controllen = sizeof(control);
        cmsghdr* cm = CMSG_FIRSTHDR(&msg);
        cm->cmsg_level = SOL_SOCKET;
        cm->cmsg_type = SCM_RIGHTS;
        cm->cmsg_len = CMSG_LEN(sizeof(int));
        const int f = ring_fd.get();
        std::memcpy(CMSG_DATA(cm), &f, sizeof(int));
    }
    if (::sendmsg(fd, &msg, MSG_NOSIGNAL) != static_cast<ssize_t>(text.size())) {
        return;
    }
    if (m_behaviour.ring == EvilRing::RegularFile || m_behaviour.ring == EvilRing::UnsealedMemfd) {
        // Shrink the file under the client's mapping, the moment there is one.
        ucred cred{};
        socklen_t len = sizeof(cred);
        if (::getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &cred, &len) == 0 &&
            waitForMapping(fd, cred.pid, ring_fd.get(), name) && ::ftruncate(ring_fd.get(), 0) == 0) {
            ++m_truncations;
        }
    }
    // Frame 1 is in slot 0.
    ipc::FrameHeader h;
    h.kind = ipc::FrameKind::Frame;
    h.encoding = req.value().payload == ipc::StreamPayload::Shm ? ipc::FrameEncoding::Shm : ipc::FrameEncoding::Raw;
    h.format = prof.format;
    h.sequence = 1;
    h.width = l.width;
    h.height = l.height;
    h.stride = l.stride;
    h.payload_bytes = h.encoding == ipc::FrameEncoding::Shm ? 0 : static_cast<std::uint32_t>(l.pixelBytes());
    h.validity = m_behaviour.validity;
    const auto& meta = m_behaviour.meta;
    h.meta_bytes = static_cast<std::uint16_t>(m_behaviour.meta_bytes >= 0 ? m_behaviour.meta_bytes : meta.size());
    auto hb = encodeFrameHeader(h);
    if (m_behaviour.edit_header) {
        m_behaviour.edit_header(hb.data());
    }
    if (::send(fd, hb.data(), hb.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(hb.size())) {
        return;
    }
    if (!meta.empty() && ::send(fd, meta.data(), meta.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(meta.size())) {
        return;
    }
    if (h.encoding == ipc::FrameEncoding::Raw) {
        std::vector<std::uint8_t> px(l.pixelBytes());
        std::memcpy(px.data(), bytes.data() + l.slotOffset(0) + ipc::kSlotPixelOffset, px.size());
        ::send(fd, px.data(), px.size(), MSG_NOSIGNAL);
    }
    // Until the client goes (an ack byte or two may come first).
    readUntilClose(fd, std::chrono::seconds(3));
}

bool ChildOutcome::signalled() const { return WIFSIGNALED(wait_status); }

ChildOutcome runInChild(const std::function<std::string()>& work) {
    ChildOutcome out;
    int pipe_fds[2];
    if (::pipe2(pipe_fds, O_CLOEXEC) != 0) {
        out.how = "pipe2 failed";
        return out;
    }
    const pid_t pid = ::fork();
    if (pid == 0) {
        ::close(pipe_fds[0]);
        const std::string r = work();
        writeAll(pipe_fds[1], reinterpret_cast<const std::uint8_t*>(r.data()), r.size());
        ::_exit(0);
    }
    ::close(pipe_fds[1]);
    char buf[4096];
    ssize_t n = 0;
    while ((n = ::read(pipe_fds[0], buf, sizeof(buf))) > 0) {
        out.result.append(buf, static_cast<std::size_t>(n));
    }
    ::close(pipe_fds[0]);
    ::waitpid(pid, &out.wait_status, 0);
    out.how = describeStatus(out.wait_status);
    return out;
}

ChildOutcome runCommand(const std::string& command) {
    ChildOutcome out;
    // exec: the shell becomes the program, so its wait status is the program's (a signal stays one).
    FILE* p = ::popen(("exec " + command + " 2>&1").c_str(), "r");
    if (p == nullptr) {
        out.how = "popen failed";
        return out;
    }
    char buf[4096];
    std::size_t n = 0;
    while ((n = std::fread(buf, 1, sizeof(buf), p)) > 0) {
        out.result.append(buf, n);
    }
    out.wait_status = ::pclose(p);
    out.how = describeStatus(out.wait_status);
    return out;
}

}  // namespace navmap::stream_test
