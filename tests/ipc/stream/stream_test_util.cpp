// SPDX-License-Identifier: Apache-2.0
#include "stream_test_util.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <turbojpeg.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>

namespace navmap::stream_test {

long rssKb() {
    std::ifstream in("/proc/self/status");
    std::string key;
    while (in >> key) {
        if (key == "VmRSS:") {
            long kb = 0;
            in >> kb;
            return kb;
        }
    }
    return 0;
}

std::string uniqueSocketPath(const std::string& tag) {
    return "/tmp/navmap-" + tag + "-" + std::to_string(getpid()) + ".sock";
}

std::vector<std::uint8_t> sequencePattern(int width, int height, std::uint64_t seq) {
    std::vector<std::uint8_t> px(static_cast<std::size_t>(width) * height * 4);
    for (std::size_t i = 0; i < px.size(); i += 4) {
        px[i] = static_cast<std::uint8_t>(seq);
        px[i + 1] = static_cast<std::uint8_t>(seq >> 8);
        px[i + 2] = static_cast<std::uint8_t>(seq >> 16);
        px[i + 3] = 255;
    }
    return px;
}

bool wholePublisherFrame(const std::vector<std::uint8_t>& pixels, std::size_t bytes) {
    if (pixels.size() != bytes || pixels.size() < 4) return false;
    for (std::size_t i = 4; i < pixels.size(); i += 4) {
        if (std::memcmp(pixels.data(), pixels.data() + i, 4) != 0) return false;
    }
    return true;
}

Publisher::Publisher(ipc::FrameServer& server, std::string view, int width, int height, int fps) {
    m_thread = std::thread([this, &server, view = std::move(view), width, height, fps] {
        auto next = std::chrono::steady_clock::now();
        std::uint64_t i = 0;
        std::vector<std::uint8_t> px;
        while (m_run) {
            ++i;
            px = sequencePattern(width, height, i);
            ipc::FrameView f;
            f.pixels = px.data();
            f.width = width;
            f.height = height;
            f.source_time_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                                   std::chrono::system_clock::now().time_since_epoch())
                                   .count() -
                               2000000;  // "CAN data 2 ms old"
            // Ring sequences restart at 1 when a ring is created; restart with them so every
            // frame's pixels carry its ring sequence number.
            if (server.publish(view, f) == 0) {
                i = 0;
            }
            m_count.fetch_add(1);
            if (fps > 0) {
                next += std::chrono::nanoseconds(1000000000LL / fps);
                std::this_thread::sleep_until(next);
            } else {
                std::this_thread::yield();
            }
        }
    });
}

Publisher::~Publisher() { stop(); }

void Publisher::stop() {
    m_run = false;
    if (m_thread.joinable()) {
        m_thread.join();
    }
}

int connectUnixRaw(const std::string& path) {
    const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    std::strncpy(a.sun_path, path.c_str(), sizeof(a.sun_path) - 1);
    if (connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0) {
        close(fd);
        return -1;
    }
    return fd;
}

int connectTcpRaw(int port) {
    const int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0) {
        close(fd);
        return -1;
    }
    return fd;
}

bool sendAllRaw(int fd, const std::string& data) {
    std::size_t off = 0;
    while (off < data.size()) {
        const ssize_t n = send(fd, data.data() + off, data.size() - off, MSG_NOSIGNAL);
        if (n <= 0) {
            return false;
        }
        off += static_cast<std::size_t>(n);
    }
    return true;
}

std::string readUntilClose(int fd, std::chrono::milliseconds timeout) {
    std::string out;
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
        if (left <= 0) {
            break;
        }
        pollfd p{fd, POLLIN, 0};
        if (poll(&p, 1, static_cast<int>(left)) <= 0) {
            break;
        }
        char buf[65536];
        const ssize_t n = recv(fd, buf, sizeof(buf), 0);
        if (n <= 0) {
            break;
        }
        out.append(buf, static_cast<std::size_t>(n));
    }
    return out;
}

std::string httpExchange(int port, const std::string& request, std::chrono::milliseconds timeout) {
    const int fd = connectTcpRaw(port);
    if (fd < 0) {
        return {};
    }
    sendAllRaw(fd, request);
    std::string r = readUntilClose(fd, timeout);
    close(fd);
    return r;
}

int freeTcpPort() {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    const bool ok = fd >= 0 && bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0 &&
                    getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) == 0;
    if (fd >= 0) close(fd);
    return ok ? ntohs(a.sin_port) : -1;
}

std::string httpGet(int port, const std::string& target, const std::string& headers) {
    return httpExchange(
        port, "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\n" + headers + "\r\n");
}

namespace {

// The first line the peer sends (without '\n'), or what came before it closed; 3 s at most.
std::string readLine(int fd, int* ring_fd) {
    std::string line;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(3);
    while (line.find('\n') == std::string::npos) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
        pollfd p{fd, POLLIN, 0};
        if (left <= 0 || poll(&p, 1, static_cast<int>(left)) <= 0) {
            break;
        }
        char buf[4096];
        iovec iov{buf, sizeof(buf)};
        alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int))] = {};
        msghdr msg{};
        msg.msg_iov = &iov;
        msg.msg_iovlen = 1;
        msg.msg_control = control;
        msg.msg_controllen = sizeof(control);
        const ssize_t n = recvmsg(fd, &msg, MSG_CMSG_CLOEXEC);
        for (cmsghdr* cm = CMSG_FIRSTHDR(&msg); n >= 0 && cm != nullptr; cm = CMSG_NXTHDR(&msg, cm)) {
            if (cm->cmsg_level == SOL_SOCKET && cm->cmsg_type == SCM_RIGHTS) {
                int f = -1;
                std::memcpy(&f, CMSG_DATA(cm), sizeof(int));
                if (ring_fd != nullptr && *ring_fd < 0) {
                    *ring_fd = f;
                } else {
                    close(f);
                }
            }
        }
        if (n <= 0) {
            break;
        }
        line.append(buf, static_cast<std::size_t>(n));
    }
    return line.substr(0, line.find('\n'));
}

}  // namespace

RawShmClient::~RawShmClient() {
    if (ring_fd >= 0) {
        close(ring_fd);
    }
    if (fd >= 0) {
        close(fd);
    }
}

std::unique_ptr<RawShmClient> rawShmHandshake(const std::string& path, const std::string& line) {
    auto c = std::make_unique<RawShmClient>();
    c->fd = connectUnixRaw(path);
    if (c->fd < 0 || !sendAllRaw(c->fd, line)) {
        return c;
    }
    c->reply = readLine(c->fd, &c->ring_fd);
    return c;
}

std::string holdConnections(const std::string& path, const std::string& line, int count) {
    std::string out;
    for (int i = 0; i < count; ++i) {
        const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
        sockaddr_un a{};
        a.sun_family = AF_UNIX;
        std::strncpy(a.sun_path, path.c_str(), sizeof(a.sun_path) - 1);
        if (connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0) {
            out += std::string("connect: ") + std::strerror(errno) + "\n";
            close(fd);
            continue;
        }
        sendAllRaw(fd, line);  // a refused peer may be gone already: its answer is still readable
        out += readLine(fd, nullptr) + "\n";
        // Left open on purpose: the process holds its connections until it exits.
    }
    return out;
}

MjpegReader::MjpegReader(int port, const std::string& target) {
    m_fd = connectTcpRaw(port);
    if (m_fd < 0) {
        return;
    }
    sendAllRaw(m_fd, "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\n\r\n");
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (m_buf.find("\r\n\r\n") == std::string::npos) {
        if (!fill(deadline)) {
            return;
        }
    }
    const auto end = m_buf.find("\r\n\r\n");
    m_head = m_buf.substr(0, end);
    m_buf.erase(0, end + 4);
    m_head_ok = m_head.rfind("HTTP/1.0 200", 0) == 0;
}

MjpegReader::~MjpegReader() {
    if (m_fd >= 0) {
        close(m_fd);
    }
}

bool MjpegReader::fill(std::chrono::steady_clock::time_point deadline) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0) {
        return false;
    }
    pollfd p{m_fd, POLLIN, 0};
    if (poll(&p, 1, static_cast<int>(left)) <= 0) {
        return false;
    }
    char buf[65536];
    const ssize_t n = recv(m_fd, buf, sizeof(buf), 0);
    if (n <= 0) {
        return false;
    }
    m_buf.append(buf, static_cast<std::size_t>(n));
    return true;
}

std::vector<std::uint8_t> MjpegReader::next(std::chrono::milliseconds timeout, std::uint64_t* sequence) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (m_buf.find("\r\n\r\n") == std::string::npos) {
        if (!fill(deadline)) {
            return {};
        }
    }
    const auto end = m_buf.find("\r\n\r\n");
    const std::string head = m_buf.substr(0, end);
    if (head.rfind("--navmapframe\r\n", 0) != 0) {
        return {};
    }
    const auto cl = head.find("Content-Length: ");
    if (cl == std::string::npos) {
        return {};
    }
    const std::size_t len = std::stoul(head.substr(cl + 16));
    if (sequence != nullptr) {
        const auto sq = head.find("X-Navmap-Sequence: ");
        *sequence = sq == std::string::npos ? 0 : std::stoull(head.substr(sq + 19));
    }
    while (m_buf.size() < end + 4 + len + 2) {
        if (!fill(deadline)) {
            return {};
        }
    }
    std::vector<std::uint8_t> jpeg(m_buf.begin() + static_cast<std::ptrdiff_t>(end + 4),
                                   m_buf.begin() + static_cast<std::ptrdiff_t>(end + 4 + len));
    m_buf.erase(0, end + 4 + len + 2);
    return jpeg;
}

bool decodeJpeg(const std::vector<std::uint8_t>& jpeg, int* width, int* height, std::vector<std::uint8_t>* rgba) {
    tjhandle h = tjInitDecompress();
    int sub = 0, cs = 0;
    bool ok = tjDecompressHeader3(h, jpeg.data(), jpeg.size(), width, height, &sub, &cs) == 0;
    if (ok) {
        rgba->resize(static_cast<std::size_t>(*width) * *height * 4);
        ok = tjDecompress2(h, jpeg.data(), jpeg.size(), rgba->data(), *width, 0, *height, TJPF_RGBA, 0) == 0;
    }
    tjDestroy(h);
    return ok;
}

}  // namespace navmap::stream_test
