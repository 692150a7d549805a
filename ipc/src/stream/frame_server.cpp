#include "navmap/ipc/frame_server.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <linux/sockios.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <iomanip>
#include <map>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "navmap/ipc/frame_header.h"
#include "navmap/ipc/frame_ring.h"
#include "navmap/ipc/stream_http_request.h"
#include "frame_encoder.h"
#include "stream_page.h"
#include "navmap/ipc/net/sys_error.h"
#include "navmap/ipc/net/unique_fd.h"
#include "stream_socket.h"

namespace navmap::ipc {

using stream_detail::EncodedFrame;
using stream_detail::EncodeKind;
using stream_detail::FrameEncoder;
using net::sysError;
using net::UniqueFd;

namespace {

using Clock = std::chrono::steady_clock;

enum class Via { Unix, Tcp, Http };
enum class Phase { Handshake, Stream, HttpHead, Mjpeg, Draining };

// One ring per (profile, format), shared by all its clients; the profile is a rendered profile's
// name (or the view when the server has no list of rendered profiles). The caches hold the newest
// frame in the forms the socket transports need, so N clients cost one copy/compression/encode.
// zlib and JPEG come from the encoder thread (FrameEncoder), never from the I/O thread.
struct RingEntry {
    std::string key;   // what publish() names
    std::string view;
    std::shared_ptr<FrameRing> ring;
    std::size_t clients = 0;
    int maxFps = 0;
    std::uint64_t rawSeq = 0;
    FrameHeader rawHeader;
    std::vector<std::uint8_t> raw;
    std::uint64_t zlibAsked = 0;  // newest sequence handed to the encoder
    std::uint64_t jpegAsked = 0;
    std::shared_ptr<const EncodedFrame> zlib;  // newest finished encodes
    std::shared_ptr<const EncodedFrame> jpeg;
};

struct Conn {
    UniqueFd fd;
    Via via = Via::Unix;
    Phase phase = Phase::Handshake;
    std::string peer;
    std::optional<uid_t> uid;  // Unix peers (SO_PEERCRED)
    std::string in;
    std::vector<std::uint8_t> out;
    std::size_t outPos = 0;
    bool closeWhenFlushed = false;
    bool dead = false;
    std::shared_ptr<RingEntry> ring;
    StreamPayload payload = StreamPayload::Shm;
    bool hold = false;  // shm: holds frames in place until its ack (pinned slots)
    int fps = 0;
    bool awaitingAck = false;
    int pinnedSlot = -1;  // shm: the slot of the notified frame, pinned until the ack
    bool pending = false;
    std::uint64_t lastSent = 0;
    std::uint64_t seen = 0;  // newest frame (in this client's encoding) it has been offered
    std::uint64_t dropped = 0;
    Clock::time_point since;
    Clock::time_point streamSince;  // handshake done: the first frame is due within handshakeTimeout
    Clock::time_point lastProgress;
    Clock::time_point ackSince;
    Clock::time_point lastOffer;
    bool offered = false;
    bool deferred = false;
    Clock::time_point deferredUntil;
    std::uint64_t bytesSent = 0;   // accepted by the kernel
    std::uint64_t bytesAcked = 0;  // TCP: left the kernel's send queue (the peer took them)

    bool outPending() const { return outPos < out.size(); }
    bool busy() const { return outPending() || awaitingAck; }
};

struct PublishTarget {
    std::string key;
    std::shared_ptr<FrameRing> ring;
};
using PublishSet = std::vector<PublishTarget>;

// A status from the render thread on its way to the server thread: header and text, ready to queue.
struct PendingStatus {
    std::string key;  // what publish() names: the profile
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    std::shared_ptr<const std::string> bytes;
};

std::string jsonEscape(const std::string& s) {
    return nlohmann::json(s).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

const char* viaName(Via via) { return via == Via::Unix ? "unix" : via == Via::Tcp ? "tcp" : "http"; }

// Compares a secret in time that depends only on the length of the expected value, not on where
// the first difference is (hand-written: no Debian package in the build has a constant-time
// compare without pulling in a crypto library for these few lines).
bool equalConstantTime(std::string_view given, std::string_view expected) {
    unsigned diff = given.size() == expected.size() ? 0U : 1U;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        const unsigned char g = i < given.size() ? static_cast<unsigned char>(given[i]) : 0;
        diff |= static_cast<unsigned>(g ^ static_cast<unsigned char>(expected[i]));
    }
    return diff == 0;
}

bool isLoopback(const std::string& address) {
    return address.rfind("127.", 0) == 0 || address == "::1";
}

// fps 0 asks for every frame: for scheduling that is the highest rate there is.
int effectiveFps(int fps) { return fps == 0 ? kMaxStreamFps : fps; }

// Control bytes other than tab, CR and LF: no JSON line or HTTP head contains them.
bool hasControlBytes(const std::string& s) {
    return std::any_of(s.begin(), s.end(), [](char ch) {
        const auto b = static_cast<unsigned char>(ch);
        return (b < 0x20 && b != '\t' && b != '\r' && b != '\n') || b == 0x7F;
    });
}

}  // namespace

class FrameServer::Impl {
public:
    explicit Impl(FrameServerOptions options)
        : m_options(std::move(options)), m_encoder(m_options.jpegQuality, [this] { wake(); }) {}
    ~Impl() { stop(); }

    Status start();
    void stop();
    std::size_t publish(const std::string& profile, const FrameView& frame);
    Status publishStatus(const std::string& key, int width, int height, std::string json);
    FrameServerStats stats() const {
        std::lock_guard lock(m_statsMutex);
        FrameServerStats s = m_stats;
        s.published = m_published.load(std::memory_order_relaxed);
        s.publishMsLast = static_cast<double>(m_publishNsLast.load(std::memory_order_relaxed)) / 1e6;
        s.publishMsMax = static_cast<double>(m_publishNsMax.load(std::memory_order_relaxed)) / 1e6;
        return s;
    }
    std::vector<ActiveProfile> activeProfiles() const {
        std::lock_guard lock(m_statsMutex);
        return m_active;
    }
    void collectMetrics(MetricsRegistry& registry) const;

    FrameServerOptions m_options;
    int m_tcpPort = -1;
    int m_httpPort = -1;

private:
    void run();
    void acceptAll(int listenFd, Via via);
    void onReadable(Conn& c);
    void processInput(Conn& c);
    void onHandshake(Conn& c, const std::string& line);
    void onHttpRequest(Conn& c, const std::string& head);
    void onStreamBytes(Conn& c);
    void flush(Conn& c);
    void queue(Conn& c, const void* data, std::size_t n);
    void finishWith(Conn& c, const std::string& bytes);  // send, then half-close and drain
    void handshakeError(Conn& c, const std::string& message);
    void protocolError(Conn& c, const std::string& message);
    void httpReply(Conn& c, int code, const char* reason, const char* contentType, const std::string& body,
                   const char* extraHeaders = "");
    void refuseAtAccept(UniqueFd& fd, Via via, const std::string& peer, std::uint64_t FrameServerStats::*counter,
                        const std::string& message);
    void closeWith(Conn& c, const std::string& bytes);
    std::string checkHttpAccess(const Conn& c, const StreamHttpRequest& req, int* code);
    Result<std::string> resolveProfile(const StreamProfile& profile);
    Status attach(Conn& c, const std::string& key, const StreamProfile& profile);
    void unpin(Conn& c);
    void offer(Conn& c, Clock::time_point now);
    void sendFrame(Conn& c);
    bool fillRaw(RingEntry& e, std::uint64_t seq);
    std::uint64_t available(const Conn& c) const;
    void offerIfNew(Conn& c, Clock::time_point now);
    void requestEncodes();
    void wake() noexcept;
    void deliverNewFrames();
    void deliverStatuses();
    void checkTimeouts();
    void reap();
    void refreshRings();
    std::string statusJson() const;

    std::vector<std::unique_ptr<Conn>> m_conns;
    std::vector<std::shared_ptr<RingEntry>> m_rings;  // server thread
    UniqueFd m_unixFd;
    UniqueFd m_tcpFd;
    UniqueFd m_httpFd;
    UniqueFd m_wakeFd;
    std::thread m_thread;
    std::atomic<bool> m_running{false};
    FrameEncoder m_encoder;  // zlib/JPEG off the I/O thread
    std::uint64_t m_ringCounter = 0;
    std::uint64_t m_retiredPinnedOverwrites = 0;  // of rings freed since (server thread)
    PeerAllowList m_allowed;  // allowedPeers plus unixGroup

    mutable std::mutex m_publishMutex;  // guards the pointer swap only, never I/O
    std::shared_ptr<const PublishSet> m_publishSet = std::make_shared<PublishSet>();
    std::mutex m_statusMutex;  // guards the hand-over of statuses only, never I/O
    std::vector<PendingStatus> m_statuses;

    mutable std::mutex m_statsMutex;
    FrameServerStats m_stats;
    std::vector<ActiveProfile> m_active;
    std::atomic<std::uint64_t> m_published{0};
    std::atomic<std::int64_t> m_publishNsLast{0};
    std::atomic<std::int64_t> m_publishNsMax{0};
};

Status FrameServer::Impl::start() {
    if (m_running) {
        return {};
    }
    if (m_options.ringSlots < 2 || m_options.ringSlots > 64) {
        return Error{"FrameServer: ringSlots must be in [2, 64]"};
    }
    if (m_options.maxClientsPerTransport < 1 || m_options.maxClientsPerUid < 1) {
        return Error{"FrameServer: maxClientsPerTransport and maxClientsPerUid must be at least 1"};
    }
    m_allowed = m_options.allowedPeers;
    if (m_options.unixGroup) {
        m_allowed.gids.push_back(*m_options.unixGroup);
    }
    const int wake = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    if (wake < 0) {
        return Error{sysError("eventfd", "frame server wake-up")};
    }
    m_wakeFd.reset(wake);
    if (!m_options.unixPath.empty()) {
        auto fd = stream_detail::listenUnix(m_options.unixPath, m_options.unixMode, m_options.unixGroup);
        if (!fd) {
            return Error{fd.error().message};
        }
        m_unixFd.reset(fd.value());
    }
    if (m_options.tcpPort >= 0) {
        auto fd = stream_detail::listenTcp(m_options.bindAddress, m_options.tcpPort);
        if (!fd) {
            return Error{fd.error().message};
        }
        m_tcpFd.reset(fd.value());
        m_tcpPort = stream_detail::boundPort(fd.value());
    }
    if (m_options.httpPort >= 0) {
        auto fd = stream_detail::listenTcp(m_options.bindAddress, m_options.httpPort);
        if (!fd) {
            return Error{fd.error().message};
        }
        m_httpFd.reset(fd.value());
        m_httpPort = stream_detail::boundPort(fd.value());
    }
    if (auto st = m_encoder.start(); !st) {
        return st;
    }
    m_running = true;
    m_thread = std::thread([this] { run(); });
    return {};
}

void FrameServer::Impl::stop() {
    if (m_running.exchange(false)) {
        const std::uint64_t one = 1;
        [[maybe_unused]] const auto n = ::write(m_wakeFd.get(), &one, sizeof(one));
        m_thread.join();
    }
    m_encoder.stop();  // before the wake-up eventfd goes
    m_conns.clear();
    m_rings.clear();
    {
        std::lock_guard lock(m_publishMutex);
        m_publishSet = std::make_shared<PublishSet>();
    }
    if (m_unixFd.valid()) {
        m_unixFd.reset();
        ::unlink(m_options.unixPath.c_str());
    }
    m_tcpFd.reset();
    m_httpFd.reset();
    m_wakeFd.reset();
}

void FrameServer::Impl::wake() noexcept {
    // eventfd writes never block (the counter saturates far away).
    const std::uint64_t one = 1;
    [[maybe_unused]] const auto n = ::write(m_wakeFd.get(), &one, sizeof(one));
}

std::size_t FrameServer::Impl::publish(const std::string& profile, const FrameView& frame) {
    const auto t0 = Clock::now();
    std::shared_ptr<const PublishSet> set;
    {
        std::lock_guard lock(m_publishMutex);
        set = m_publishSet;
    }
    std::size_t written = 0;
    for (const auto& t : *set) {
        if (t.key == profile && t.ring->write(frame) != 0) {
            ++written;
        }
    }
    if (written > 0) {
        m_published.fetch_add(1, std::memory_order_relaxed);
        // Wake the server thread; eventfd writes never block (the counter saturates far away).
        const std::uint64_t one = 1;
        [[maybe_unused]] const auto n = ::write(m_wakeFd.get(), &one, sizeof(one));
        const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count();
        m_publishNsLast.store(ns, std::memory_order_relaxed);
        if (ns > m_publishNsMax.load(std::memory_order_relaxed)) {
            m_publishNsMax.store(ns, std::memory_order_relaxed);
        }
    }
    return written;
}

Status FrameServer::Impl::publishStatus(const std::string& key, int width, int height, std::string json) {
    const auto* text = reinterpret_cast<const std::uint8_t*>(json.data());
    if (auto s = validateTextPayload(FrameKind::Status, text, json.size()); !s) {
        return Error{"publishStatus(" + key + "): " + s.message()};
    }
    if (const auto j = nlohmann::json::parse(json, nullptr, false); j.is_discarded() || !j.is_object()) {
        return Error{"publishStatus(" + key + "): status: not a JSON object"};
    }
    if (width <= 0 || height <= 0) {
        return Error{"publishStatus(" + key + "): bad size " + std::to_string(width) + "x" + std::to_string(height)};
    }
    // Header and text are built here, once; the server thread only queues the bytes per client.
    FrameHeader h;
    h.kind = FrameKind::Status;
    h.payloadBytes = static_cast<std::uint32_t>(json.size());
    const auto hb = encodeFrameHeader(h);
    auto bytes = std::make_shared<std::string>(hb.begin(), hb.end());
    bytes->append(json);
    PendingStatus st{key, static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height), std::move(bytes)};
    {
        std::lock_guard lock(m_statusMutex);
        const auto same = std::find_if(m_statuses.begin(), m_statuses.end(), [&](const PendingStatus& p) {
            return p.key == st.key && p.width == st.width && p.height == st.height;
        });
        if (same != m_statuses.end()) {
            *same = std::move(st);  // not sent yet: the newer status replaces it
        } else {
            m_statuses.push_back(std::move(st));
        }
    }
    wake();
    return {};
}

void FrameServer::Impl::run() {
    std::vector<pollfd> pfds;
    while (m_running) {
        pfds.clear();
        pfds.push_back({m_wakeFd.get(), POLLIN, 0});
        pfds.push_back({m_unixFd.get(), POLLIN, 0});  // fd -1 is ignored by poll()
        pfds.push_back({m_tcpFd.get(), POLLIN, 0});
        pfds.push_back({m_httpFd.get(), POLLIN, 0});
        const std::size_t polled = m_conns.size();
        for (const auto& c : m_conns) {
            short ev = POLLIN;
            if (c->outPending()) {
                ev |= POLLOUT;
            }
            pfds.push_back({c->fd.get(), ev, 0});
        }
        // Wake at least every 20 ms (stall checks), earlier when a rate-capped frame falls due.
        auto wait = std::chrono::milliseconds(20);
        const auto now = Clock::now();
        for (const auto& c : m_conns) {
            if (c->deferred) {
                wait = std::min(wait, std::chrono::ceil<std::chrono::milliseconds>(
                                          std::max(c->deferredUntil - now, Clock::duration::zero())));
            }
        }
        const int n = ::poll(pfds.data(), pfds.size(), static_cast<int>(wait.count()));
        if (n < 0 && errno != EINTR) {
            std::lock_guard lock(m_statsMutex);
            m_stats.lastError = sysError("poll", "frame server");
        }
        if (n > 0) {
            if ((pfds[0].revents & POLLIN) != 0) {
                std::uint64_t v = 0;
                [[maybe_unused]] const auto r = ::read(m_wakeFd.get(), &v, sizeof(v));
            }
            if ((pfds[1].revents & POLLIN) != 0) {
                acceptAll(m_unixFd.get(), Via::Unix);
            }
            if ((pfds[2].revents & POLLIN) != 0) {
                acceptAll(m_tcpFd.get(), Via::Tcp);
            }
            if ((pfds[3].revents & POLLIN) != 0) {
                acceptAll(m_httpFd.get(), Via::Http);
            }
            for (std::size_t i = 0; i < polled; ++i) {
                Conn& c = *m_conns[i];
                const short re = pfds[4 + i].revents;
                if (c.dead) {
                    continue;
                }
                if ((re & (POLLIN | POLLHUP | POLLERR)) != 0) {
                    onReadable(c);
                }
                if (!c.dead && (re & POLLOUT) != 0) {
                    flush(c);
                }
            }
        }
        deliverStatuses();  // before frames: a status published before a frame arrives before it
        deliverNewFrames();
        checkTimeouts();
        reap();
    }
}

void FrameServer::Impl::acceptAll(int listenFd, Via via) {
    for (;;) {
        const int fd = ::accept4(listenFd, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (fd < 0) {
            if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
                std::lock_guard lock(m_statsMutex);
                m_stats.lastError = sysError("accept", via == Via::Unix ? m_options.unixPath : "tcp");
            }
            return;
        }
        UniqueFd owned(fd);
        const std::string peer = std::string(viaName(via)) + "#" + std::to_string(fd);
        {
            std::lock_guard lock(m_statsMutex);
            ++m_stats.accepted;
        }
        // Who may connect, and how many: refusals are answered and closed at once, so they never
        // hold a slot (a refused peer that keeps reconnecting costs one accept each time).
        std::optional<uid_t> uid;
        if (via == Via::Unix) {
            auto cred = peerCredentials(fd, m_options.unixPath);
            if (!cred) {
                refuseAtAccept(owned, via, peer, &FrameServerStats::refusedPeer, cred.error().message);
                continue;
            }
            if (!peerAllowed(m_allowed, cred.value())) {
                refuseAtAccept(owned, via, peer, &FrameServerStats::refusedPeer,
                               peerRefusal(cred.value(), m_options.unixPath));
                continue;
            }
            uid = cred.value().uid;
        }
        const auto sameVia = static_cast<std::size_t>(
            std::count_if(m_conns.begin(), m_conns.end(), [&](const auto& c) { return c->via == via; }));
        if (sameVia >= m_options.maxClientsPerTransport) {
            refuseAtAccept(owned, via, peer, &FrameServerStats::refusedTransportFull,
                           std::string("too many ") + viaName(via) + " clients (limit " +
                               std::to_string(m_options.maxClientsPerTransport) + ")");
            continue;
        }
        if (uid) {
            const auto sameUid = static_cast<std::size_t>(
                std::count_if(m_conns.begin(), m_conns.end(), [&](const auto& c) { return c->uid == uid; }));
            if (sameUid >= m_options.maxClientsPerUid) {
                refuseAtAccept(owned, via, peer, &FrameServerStats::refusedUidFull,
                               "too many connections from uid " + std::to_string(*uid) + " (limit " +
                                   std::to_string(m_options.maxClientsPerUid) + ")");
                continue;
            }
        }
        auto c = std::make_unique<Conn>();
        c->fd = std::move(owned);
        c->via = via;
        c->uid = uid;
        c->phase = via == Via::Http ? Phase::HttpHead : Phase::Handshake;
        c->since = c->lastProgress = Clock::now();
        c->peer = uid ? peer + " (uid " + std::to_string(*uid) + ")" : peer;
        if (via != Via::Unix) {
            // A small kernel queue keeps frames fresh (a slow reader gets the newest frame, not a
            // backlog) and lets a reader that stopped show up as a stall within a few frames.
            const int sndbuf = 256 * 1024;
            ::setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &sndbuf, sizeof(sndbuf));
            const int one = 1;
            ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
        }
        m_conns.push_back(std::move(c));
        refreshRings();
    }
}

void FrameServer::Impl::refuseAtAccept(UniqueFd& fd, Via via, const std::string& peer,
                                       std::uint64_t FrameServerStats::*counter, const std::string& message) {
    {
        std::lock_guard lock(m_statsMutex);
        ++(m_stats.*counter);
        m_stats.lastError = peer + ": refused: " + message;
    }
    // Read what already arrived (usually the handshake), so closing does not turn into a reset
    // that could destroy the answer on its way; then answer without waiting and close.
    char buf[4096];
    for (int i = 0; i < 16 && ::recv(fd.get(), buf, sizeof(buf), MSG_DONTWAIT) > 0; ++i) {
    }
    std::string reply;
    if (via == Via::Http) {
        const std::string body = message + "\n";
        reply = "HTTP/1.0 503 Service Unavailable\r\nContent-Type: text/plain\r\nContent-Length: " +
                std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body;
    } else {
        reply = "{\"ok\":false,\"error\":" + jsonEscape(message) + "}\n";
    }
    [[maybe_unused]] const auto n = ::send(fd.get(), reply.data(), reply.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    ::shutdown(fd.get(), SHUT_WR);
    fd.reset();
    std::lock_guard lock(m_statsMutex);
    ++m_stats.disconnects;
}

void FrameServer::Impl::onReadable(Conn& c) {
    char buf[65536];
    for (int rounds = 0; rounds < 16; ++rounds) {
        const ssize_t n = ::recv(c.fd.get(), buf, sizeof(buf), MSG_DONTWAIT);
        if (n > 0) {
            if (c.phase == Phase::Draining || c.phase == Phase::Mjpeg) {
                continue;  // nothing more is expected from them; discard
            }
            c.in.append(buf, static_cast<std::size_t>(n));
            processInput(c);
            if (c.dead || c.phase == Phase::Draining) {
                continue;
            }
        } else if (n == 0) {
            c.dead = true;
            return;
        } else {
            if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
                c.dead = true;
            }
            return;
        }
    }
}

void FrameServer::Impl::processInput(Conn& c) {
    switch (c.phase) {
        case Phase::Handshake: {
            if (hasControlBytes(c.in)) {
                handshakeError(c, "handshake: binary data (expected one JSON line)");
                return;
            }
            const auto nl = c.in.find('\n');
            if (nl == std::string::npos) {
                if (c.in.size() > kMaxHandshakeBytes) {
                    handshakeError(c, "handshake: longer than " + std::to_string(kMaxHandshakeBytes) + " bytes");
                }
                return;
            }
            const std::string line = c.in.substr(0, nl + 1);
            c.in.erase(0, nl + 1);
            onHandshake(c, line);
            if (!c.dead && c.phase == Phase::Stream && !c.in.empty()) {
                onStreamBytes(c);
            }
            return;
        }
        case Phase::Stream:
            onStreamBytes(c);
            return;
        case Phase::HttpHead: {
            if (hasControlBytes(c.in) || std::any_of(c.in.begin(), c.in.end(), [](char ch) {
                    return static_cast<unsigned char>(ch) >= 0x80;
                })) {
                httpReply(c, 400, "Bad Request", "text/plain", "bad request: binary data\n");
                return;
            }
            auto end = c.in.find("\r\n\r\n");
            std::size_t endLen = 4;
            if (end == std::string::npos) {
                end = c.in.find("\n\n");
                endLen = 2;
            }
            if ((end == std::string::npos ? c.in.size() : end) > kMaxHttpRequestBytes) {
                httpReply(c, 431, "Request Header Fields Too Large", "text/plain", "request head too large\n");
                return;
            }
            if (end == std::string::npos) {
                if (c.in.size() >= 4 && c.in.compare(0, 4, "GET ") != 0 && c.in.find('\n') != std::string::npos &&
                           c.in.find("HTTP/1.") == std::string::npos) {
                    // The first line is complete and is no HTTP request line: answer now.
                    httpReply(c, 400, "Bad Request", "text/plain", "bad request line\n");
                }
                return;
            }
            const std::string head = c.in.substr(0, end + endLen);
            c.in.clear();
            onHttpRequest(c, head);
            return;
        }
        case Phase::Mjpeg:
        case Phase::Draining:
            c.in.clear();
            return;
    }
}

void FrameServer::Impl::onHandshake(Conn& c, const std::string& line) {
    auto req = parseStreamRequest(line);
    if (!req) {
        handshakeError(c, req.error().message);
        return;
    }
    const StreamRequest& r = req.value();
    if (r.payload == StreamPayload::Shm && c.via != Via::Unix) {
        handshakeError(c, "handshake: payload \"shm\" needs the Unix socket; use \"raw\" or \"zlib\" over TCP");
        return;
    }
    auto key = resolveProfile(r.profile);
    if (!key) {
        handshakeError(c, "handshake: " + key.error().message);
        return;
    }
    if (auto s = attach(c, key.value(), r.profile); !s) {
        handshakeError(c, s.message());
        return;
    }
    c.payload = r.payload;
    c.hold = r.hold;
    c.fps = r.profile.fps;
    c.ring->maxFps = std::max(c.ring->maxFps, effectiveFps(c.fps));
    const FrameRingLayout& l = c.ring->ring->layout();
    nlohmann::json reply;
    reply["ok"] = true;
    reply["version"] = 1;
    reply["profile"] = {{"name", r.profile.name}, {"width", r.profile.width}, {"height", r.profile.height},
                        {"fps", r.profile.fps}, {"view", r.profile.view},
                        {"format", pixelFormatName(r.profile.format)}};
    reply["payload"] = streamPayloadName(r.payload);
    if (r.hold) {
        reply["hold"] = true;
    }
    reply["stride"] = l.stride;
    reply["header_bytes"] = kFrameHeaderBytes;
    if (r.payload == StreamPayload::Shm) {
        reply["ring"] = {{"slots", l.slots}, {"slot_bytes", l.slotBytes}, {"total_bytes", l.totalBytes},
                         {"header_offset", kSlotHeaderOffset}, {"pixel_offset", kSlotPixelOffset}};
    }
    const std::string text = reply.dump() + "\n";
    if (r.payload == StreamPayload::Shm) {
        // The reply and the read-only memfd travel in one sendmsg() (SCM_RIGHTS), like wl_shm.
        auto ro = c.ring->ring->openReadOnly();
        if (!ro) {
            handshakeError(c, ro.error().message);
            return;
        }
        UniqueFd roFd(ro.value());
        iovec iov{const_cast<char*>(text.data()), text.size()};
        alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int))] = {};
        msghdr msg{};
        msg.msg_iov = &iov;
        msg.msg_iovlen = 1;
        msg.msg_control = control;
        msg.msg_controllen = sizeof(control);
        cmsghdr* cm = CMSG_FIRSTHDR(&msg);
        cm->cmsg_level = SOL_SOCKET;
        cm->cmsg_type = SCM_RIGHTS;
        cm->cmsg_len = CMSG_LEN(sizeof(int));
        const int f = roFd.get();
        std::memcpy(CMSG_DATA(cm), &f, sizeof(int));
        const ssize_t n = ::sendmsg(c.fd.get(), &msg, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n < 0) {
            std::lock_guard lock(m_statsMutex);
            m_stats.lastError = sysError("sendmsg", c.peer);
            c.dead = true;
            return;
        }
        if (static_cast<std::size_t>(n) < text.size()) {
            queue(c, text.data() + n, text.size() - static_cast<std::size_t>(n));
        }
    } else {
        queue(c, text.data(), text.size());
    }
    c.phase = Phase::Stream;
    c.lastProgress = c.streamSince = Clock::now();
    refreshRings();
    offerIfNew(c, Clock::now());
}

void FrameServer::Impl::onStreamBytes(Conn& c) {
    // After the handshake a shm client sends one 'A' per frame it has copied (its credit back);
    // socket-payload clients send nothing.
    std::size_t i = 0;
    for (; i < c.in.size(); ++i) {
        const auto b = static_cast<unsigned char>(c.in[i]);
        if (c.payload == StreamPayload::Shm && b == 'A' && c.awaitingAck) {
            c.awaitingAck = false;
            unpin(c);  // the client is done with the frame: its slot may be written again
            c.lastProgress = Clock::now();
            if (c.pending && !c.busy()) {
                sendFrame(c);
            }
            continue;
        }
        char msg[96];
        std::snprintf(msg, sizeof(msg), "unexpected byte 0x%02x after the handshake%s", b,
                      c.payload == StreamPayload::Shm && b == 'A' ? " (ack without a frame)" : "");
        protocolError(c, msg);
        return;
    }
    c.in.clear();
}

Result<std::string> FrameServer::Impl::resolveProfile(const StreamProfile& profile) {
    const auto& rendered = m_options.renderedProfiles;
    if (rendered.empty()) {
        return profile.view;
    }
    const auto describe = [](const std::string& view, int w, int h) {
        return view + " " + std::to_string(w) + "x" + std::to_string(h);
    };
    const auto refuse = [this](std::string message) -> Result<std::string> {
        std::lock_guard lock(m_statsMutex);
        ++m_stats.refusedNotRendered;
        return Error{std::move(message)};
    };
    // By name first: two profiles may share a view and size and differ in style (glowing roads).
    for (const auto& r : rendered) {
        if (r.name == profile.name) {
            if (r.view == profile.view && r.width == profile.width && r.height == profile.height) {
                return r.name;
            }
            return refuse("profile " + r.name + " is rendered as " + describe(r.view, r.width, r.height) + ", not " +
                          describe(profile.view, profile.width, profile.height));
        }
    }
    // Another name: the first rendered profile of that view and size.
    for (const auto& r : rendered) {
        if (r.view == profile.view && r.width == profile.width && r.height == profile.height) {
            return r.name;
        }
    }
    std::string list;
    for (const auto& r : rendered) {
        list += (list.empty() ? "" : ", ") + r.name + " (" + describe(r.view, r.width, r.height) + ")";
    }
    return refuse(describe(profile.view, profile.width, profile.height) + " is not rendered here; rendered: " + list);
}

void FrameServer::Impl::unpin(Conn& c) {
    if (c.pinnedSlot >= 0 && c.ring) {
        c.ring->ring->unpin(static_cast<std::uint32_t>(c.pinnedSlot));
    }
    c.pinnedSlot = -1;
}

Status FrameServer::Impl::attach(Conn& c, const std::string& key, const StreamProfile& profile) {
    for (const auto& e : m_rings) {
        const FrameRingLayout& l = e->ring->layout();
        if (e->key == key && static_cast<int>(l.width) == profile.width && static_cast<int>(l.height) == profile.height &&
            l.format == profile.format) {
            c.ring = e;
            ++e->clients;
            e->maxFps = std::max(e->maxFps, effectiveFps(profile.fps));
            return {};
        }
    }
    // The memory ceiling: a new ring must fit next to the ones that exist.
    const FrameRingLayout want = FrameRingLayout::make(m_options.ringSlots, static_cast<std::uint32_t>(profile.width),
                                                       static_cast<std::uint32_t>(profile.height), profile.format);
    std::size_t used = 0;
    for (const auto& e : m_rings) {
        used += e->ring->layout().totalBytes;
    }
    if (m_options.ringMemoryBytes > 0 && used + want.totalBytes > m_options.ringMemoryBytes) {
        {
            std::lock_guard lock(m_statsMutex);
            ++m_stats.refusedRingMemory;
        }
        const auto size = [](std::size_t b) {
            std::ostringstream os;
            os << std::fixed << std::setprecision(1);
            if (b < (std::size_t{1} << 20)) {
                os << static_cast<double>(b) / 1024 << " KiB";
            } else {
                os << static_cast<double>(b) / (1 << 20) << " MiB";
            }
            return os.str();
        };
        return Error{"ring memory: " + profile.view + " " + std::to_string(profile.width) + "x" +
                     std::to_string(profile.height) + " " + pixelFormatName(profile.format) + " needs " +
                     size(want.totalBytes) + ", " + size(used) + " of " + size(m_options.ringMemoryBytes) +
                     " are in use; try again later"};
    }
    const std::string name = "navmap-ring-" + key + "-" + std::to_string(profile.width) + "x" +
                             std::to_string(profile.height) + "-" + pixelFormatName(profile.format) + "-" +
                             std::to_string(++m_ringCounter);
    auto ring = FrameRing::create(name, m_options.ringSlots, static_cast<std::uint32_t>(profile.width),
                                  static_cast<std::uint32_t>(profile.height), profile.format);
    if (!ring) {
        return Error{ring.error().message};
    }
    auto e = std::make_shared<RingEntry>();
    e->key = key;
    e->view = profile.view;
    e->ring = std::shared_ptr<FrameRing>(std::move(ring.value()));
    e->clients = 1;
    e->maxFps = effectiveFps(profile.fps);
    m_rings.push_back(e);
    c.ring = e;
    return {};
}

void FrameServer::Impl::queue(Conn& c, const void* data, std::size_t n) {
    if (!c.outPending()) {
        c.out.clear();
        c.outPos = 0;
        if (c.via == Via::Unix) {
            c.lastProgress = Clock::now();
        }
    }
    const auto* p = static_cast<const std::uint8_t*>(data);
    c.out.insert(c.out.end(), p, p + n);
}

void FrameServer::Impl::flush(Conn& c) {
    while (c.outPending()) {
        const ssize_t n = ::send(c.fd.get(), c.out.data() + c.outPos, c.out.size() - c.outPos, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n > 0) {
            c.outPos += static_cast<std::size_t>(n);
            c.bytesSent += static_cast<std::uint64_t>(n);
            if (c.via == Via::Unix) {
                c.lastProgress = Clock::now();  // Unix socket buffers are small: a send is progress
            }
            continue;
        }
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) {
            return;
        }
        c.dead = true;
        return;
    }
    c.out.clear();
    c.outPos = 0;
    if (c.closeWhenFlushed) {
        // Half-close and read until the peer closes, so unread input cannot turn into a reset
        // that destroys the reply on its way.
        ::shutdown(c.fd.get(), SHUT_WR);
        c.closeWhenFlushed = false;
        c.phase = Phase::Draining;
        c.since = Clock::now();
        return;
    }
    if (c.pending && !c.busy() && (c.phase == Phase::Stream || c.phase == Phase::Mjpeg)) {
        sendFrame(c);
    }
}

void FrameServer::Impl::finishWith(Conn& c, const std::string& bytes) {
    queue(c, bytes.data(), bytes.size());
    c.closeWhenFlushed = true;
    c.phase = Phase::Draining;
    c.since = Clock::now();
    flush(c);
}

void FrameServer::Impl::handshakeError(Conn& c, const std::string& message) {
    {
        std::lock_guard lock(m_statsMutex);
        ++m_stats.handshakeErrors;
        m_stats.lastError = c.peer + ": " + message;
    }
    finishWith(c, "{\"ok\":false,\"error\":" + jsonEscape(message) + "}\n");
}

void FrameServer::Impl::protocolError(Conn& c, const std::string& message) {
    {
        std::lock_guard lock(m_statsMutex);
        ++m_stats.protocolErrors;
        m_stats.lastError = c.peer + ": " + message;
    }
    // The error travels as a header of kind Error after whatever frame is in flight.
    FrameHeader h;
    h.kind = FrameKind::Error;
    h.payloadBytes = static_cast<std::uint32_t>(message.size());
    const auto hb = encodeFrameHeader(h);
    c.in.clear();
    c.pending = false;
    c.awaitingAck = false;
    unpin(c);
    finishWith(c, std::string(hb.begin(), hb.end()) + message);
}

void FrameServer::Impl::httpReply(Conn& c, int code, const char* reason, const char* contentType,
                                  const std::string& body, const char* extraHeaders) {
    if (code >= 400) {
        std::lock_guard lock(m_statsMutex);
        ++m_stats.httpErrors;
        m_stats.lastError = c.peer + ": HTTP " + std::to_string(code) + " " + body;
    }
    std::ostringstream os;
    os << "HTTP/1.0 " << code << ' ' << reason << "\r\nContent-Type: " << contentType
       << "\r\nContent-Length: " << body.size() << "\r\nCache-Control: no-store\r\nConnection: close\r\n"
       << extraHeaders << "\r\n"
       << body;
    finishWith(c, os.str());
}

std::string FrameServer::Impl::checkHttpAccess(const Conn& c, const StreamHttpRequest& req, int* code) {
    // Host: a page from another origin that reaches this port (DNS rebinding) carries its own
    // host name; only this server's address, and localhost when that is a loopback address, pass.
    const auto host = req.headers.find("host");
    if (host == req.headers.end() || host->second.empty()) {
        std::lock_guard lock(m_statsMutex);
        ++m_stats.refusedHost;
        *code = 400;
        return "missing Host header\n";
    }
    std::string address = m_options.bindAddress;
    if (address == "0.0.0.0" || address == "::") {
        // Bound to every address: the one this connection came in on.
        sockaddr_storage ss{};
        socklen_t len = sizeof(ss);
        char text[INET6_ADDRSTRLEN] = {};
        if (::getsockname(c.fd.get(), reinterpret_cast<sockaddr*>(&ss), &len) == 0) {
            if (ss.ss_family == AF_INET) {
                ::inet_ntop(AF_INET, &reinterpret_cast<sockaddr_in*>(&ss)->sin_addr, text, sizeof(text));
            } else if (ss.ss_family == AF_INET6) {
                ::inet_ntop(AF_INET6, &reinterpret_cast<sockaddr_in6*>(&ss)->sin6_addr, text, sizeof(text));
            }
        }
        address = text;
        if (address.rfind("::ffff:", 0) == 0 && address.find('.') != std::string::npos) {
            address.erase(0, 7);  // an IPv4 peer on an IPv6 socket
        }
    }
    const std::string& value = host->second;
    std::string name;
    std::string port;
    if (!value.empty() && value.front() == '[') {
        const auto close = value.find(']');
        if (close != std::string::npos) {
            name = value.substr(1, close - 1);
            if (close + 1 < value.size() && value[close + 1] == ':') {
                port = value.substr(close + 2);
            } else if (close + 1 != value.size()) {
                name.clear();
            }
        }
    } else {
        const auto colon = value.find(':');
        name = value.substr(0, colon);
        port = colon == std::string::npos ? "" : value.substr(colon + 1);
    }
    std::string lower = name;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char ch) { return std::tolower(ch); });
    const bool nameOk = !name.empty() && (name == address || (lower == "localhost" && isLoopback(address)));
    const bool portOk = port.empty() ? m_httpPort == 80 : port == std::to_string(m_httpPort);
    if (!nameOk || !portOk) {
        std::lock_guard lock(m_statsMutex);
        ++m_stats.refusedHost;
        *code = 421;
        const std::string self = (address.find(':') != std::string::npos ? "[" + address + "]" : address) + ":" +
                                 std::to_string(m_httpPort);
        return "Host \"" + value.substr(0, 128) + "\" is not this server (expected " + self +
               (isLoopback(address) ? " or localhost:" + std::to_string(m_httpPort) : "") + ")\n";
    }
    if (!m_options.httpToken.empty()) {
        std::string_view given;
        bool present = false;
        if (const auto auth = req.headers.find("authorization"); auth != req.headers.end()) {
            std::string_view v = auth->second;
            if (v.size() > 7 && (v.substr(0, 7) == "Bearer " || v.substr(0, 7) == "bearer ")) {
                given = v.substr(7);
                present = true;
            }
        }
        if (const auto q = req.query.find("token"); !present && q != req.query.end()) {
            given = q->second;
            present = true;
        }
        if (!present || !equalConstantTime(given, m_options.httpToken)) {
            std::lock_guard lock(m_statsMutex);
            ++m_stats.refusedToken;
            *code = 401;
            return present ? "wrong token\n"
                           : "this server needs a token: Authorization: Bearer <token>, or ?token=<token>\n";
        }
    }
    return {};
}

void FrameServer::Impl::onHttpRequest(Conn& c, const std::string& head) {
    auto parsed = parseStreamHttpRequest(head);
    if (!parsed) {
        httpReply(c, 400, "Bad Request", "text/plain", parsed.error().message + "\n");
        return;
    }
    const StreamHttpRequest& req = parsed.value();
    int denied = 0;
    if (const std::string why = checkHttpAccess(c, req, &denied); !why.empty()) {
        if (denied == 401) {
            httpReply(c, 401, "Unauthorized", "text/plain", why, "WWW-Authenticate: Bearer realm=\"navmap\"\r\n");
        } else if (denied == 421) {
            httpReply(c, 421, "Misdirected Request", "text/plain", why);
        } else {
            httpReply(c, 400, "Bad Request", "text/plain", why);
        }
        return;
    }
    if (req.method != "GET") {
        httpReply(c, 405, "Method Not Allowed", "text/plain", "only GET\n");
        return;
    }
    if (req.path == "/" || req.path == "/index.html") {
        std::vector<std::string> names;
        for (const auto& r : m_options.renderedProfiles) {
            names.push_back(r.name);
        }
        httpReply(c, 200, "OK", "text/html; charset=utf-8", stream_detail::viewerPage(m_options.mjpegProfile, names));
    } else if (req.path == "/status") {
        httpReply(c, 200, "OK", "application/json", statusJson());
    } else if (req.path == "/metrics") {
        // One registry per scrape: the server's families, then the daemon's; a family declared
        // twice is a bug, answered with 500 and its name instead of a malformed exposition.
        MetricsRegistry registry;
        try {
            collectMetrics(registry);
            if (m_options.metrics) {
                m_options.metrics(registry);
            }
        } catch (const std::logic_error& e) {
            httpReply(c, 500, "Internal Server Error", "text/plain", std::string("metrics: ") + e.what() + "\n");
            return;
        }
        httpReply(c, 200, "OK", "text/plain; version=0.0.4", registry.text());
    } else if (req.path == "/stream.mjpg") {
        // The query selects the profile exactly like a handshake: ?profile=hud or
        // ?width=640&height=240&view=bird&fps=10. It goes through the same validation.
        nlohmann::json j;
        j["version"] = 1;
        bool hasProfile = false;
        for (const auto& [k, v] : req.query) {
            if (k == "token") {
                continue;  // checked above
            }
            const bool numeric = !v.empty() && v.size() < 10 && std::all_of(v.begin(), v.end(), [](char ch) {
                return ch >= '0' && ch <= '9';
            });
            if (numeric) {
                j[k] = std::stoi(v);
            } else {
                j[k] = v;
            }
            hasProfile = hasProfile || k == "profile" || k == "width";
        }
        if (!hasProfile) {
            j["profile"] = m_options.mjpegProfile;
        }
        // A rendered profile by its name (?profile=rear) stands for its view and size.
        if (j.contains("profile") && j["profile"].is_string() && !j.contains("width")) {
            for (const auto& r : m_options.renderedProfiles) {
                if (r.name == j["profile"].get<std::string>()) {
                    j["width"] = r.width;
                    j["height"] = r.height;
                    j["view"] = r.view;
                }
            }
        }
        j["format"] = "rgba8";
        j["payload"] = "raw";
        auto r = parseStreamRequest(j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
        if (!r) {
            httpReply(c, 400, "Bad Request", "text/plain", r.error().message + "\n");
            return;
        }
        auto key = resolveProfile(r.value().profile);
        if (!key) {
            httpReply(c, 400, "Bad Request", "text/plain", key.error().message + "\n");
            return;
        }
        if (auto s = attach(c, key.value(), r.value().profile); !s) {
            const bool full = s.message().rfind("ring memory:", 0) == 0;
            httpReply(c, full ? 503 : 500, full ? "Service Unavailable" : "Internal Server Error", "text/plain",
                      s.message() + "\n");
            return;
        }
        c.fps = r.value().profile.fps;
        c.phase = Phase::Mjpeg;
        c.streamSince = Clock::now();
        static const char kHead[] =
            "HTTP/1.0 200 OK\r\nContent-Type: multipart/x-mixed-replace; boundary=navmapframe\r\n"
            "Cache-Control: no-store\r\nConnection: close\r\n\r\n";
        queue(c, kHead, sizeof(kHead) - 1);
        flush(c);
        refreshRings();
        offerIfNew(c, Clock::now());
    } else {
        httpReply(c, 404, "Not Found", "text/plain", "no such page: " + req.path.substr(0, 128) + "\n");
    }
}

void FrameServer::Impl::offer(Conn& c, Clock::time_point now) {
    // Frame-rate cap per client, with 25% slack for render-time jitter.
    if (c.fps > 0 && c.offered) {
        const auto period = std::chrono::nanoseconds(1000000000LL / c.fps);
        if (now - c.lastOffer < period * 3 / 4) {
            // Too early for this client; if no newer frame comes, it still gets this one when due.
            c.deferredUntil = c.lastOffer + period * 3 / 4;
            c.deferred = true;
            return;
        }
    }
    c.deferred = false;
    c.lastOffer = now;
    c.offered = true;
    if (c.busy()) {
        if (c.pending) {
            // The frame waiting for this client is replaced by a newer one: that one is dropped.
            ++c.dropped;
            std::lock_guard lock(m_statsMutex);
            ++m_stats.framesDropped;
        }
        c.pending = true;
        return;
    }
    c.pending = true;
    sendFrame(c);
}

bool FrameServer::Impl::fillRaw(RingEntry& e, std::uint64_t seq) {
    if (e.rawSeq == seq) {
        return true;
    }
    e.raw.resize(e.ring->layout().pixelBytes());
    if (!e.ring->read(seq, &e.rawHeader, e.raw.data())) {
        return false;
    }
    e.rawSeq = seq;
    return true;
}

std::uint64_t FrameServer::Impl::available(const Conn& c) const {
    const RingEntry& e = *c.ring;
    if (c.phase == Phase::Mjpeg) {
        return e.jpeg ? e.jpeg->sequence : 0;
    }
    if (c.payload == StreamPayload::Zlib) {
        return e.zlib ? e.zlib->sequence : 0;
    }
    return e.ring->latestSequence();
}

void FrameServer::Impl::offerIfNew(Conn& c, Clock::time_point now) {
    const std::uint64_t seq = available(c);
    if (seq > c.seen) {
        c.seen = seq;
        offer(c, now);
    }
}

void FrameServer::Impl::sendFrame(Conn& c) {
    RingEntry& e = *c.ring;
    c.pending = false;
    const bool mjpeg = c.phase == Phase::Mjpeg;
    std::uint64_t seq = 0;
    FrameHeader h;
    std::shared_ptr<const EncodedFrame> encoded;
    if (mjpeg || c.payload == StreamPayload::Zlib) {
        // Encoded by the encoder thread; the newest finished one.
        encoded = mjpeg ? e.jpeg : e.zlib;
        if (!encoded || encoded->sequence <= c.lastSent) {
            return;
        }
        seq = encoded->sequence;
        h = encoded->header;
    } else {
        // The newest frame; if the render thread overwrites it meanwhile, take the one after.
        bool ok = false;
        for (int attempt = 0; attempt < 4 && !ok; ++attempt) {
            seq = e.ring->latestSequence();
            if (seq == 0 || seq <= c.lastSent) {
                return;
            }
            if (c.payload == StreamPayload::Shm && !c.hold) {
                ok = e.ring->read(seq, &h, nullptr);
            } else if (c.payload == StreamPayload::Shm) {
                // A client that holds frames: the slot is pinned from the notification until the
                // ack, and the writer leaves it alone while another one is free (copying clients
                // pin nothing: their seqlock copy tells them when a frame was overwritten).
                const int slot = e.ring->pin(seq);
                ok = slot >= 0 && e.ring->read(seq, &h, nullptr);
                if (slot >= 0 && !ok) {
                    e.ring->unpin(static_cast<std::uint32_t>(slot));
                } else if (ok) {
                    c.pinnedSlot = slot;
                }
            } else {
                ok = fillRaw(e, seq);
                h = e.rawHeader;
            }
        }
        if (!ok) {
            c.pending = true;  // try again on the next wake-up
            return;
        }
    }
    h.dropped = c.dropped;
    if (mjpeg) {
        std::ostringstream os;
        os << "--navmapframe\r\nContent-Type: image/jpeg\r\nContent-Length: " << encoded->bytes.size()
           << "\r\nX-Navmap-Sequence: " << seq << "\r\nX-Navmap-Source-Time-Ns: " << h.sourceTimeNs
           << "\r\nX-Navmap-Dropped: " << c.dropped << "\r\n\r\n";
        const std::string partHead = os.str();
        queue(c, partHead.data(), partHead.size());
        queue(c, encoded->bytes.data(), encoded->bytes.size());
        queue(c, "\r\n", 2);
    } else if (c.payload == StreamPayload::Shm) {
        h.encoding = FrameEncoding::Shm;
        h.payloadBytes = 0;
        const auto hb = encodeFrameHeader(h);
        queue(c, hb.data(), hb.size());
        c.awaitingAck = true;
        c.ackSince = Clock::now();
    } else if (c.payload == StreamPayload::Raw) {
        h.encoding = FrameEncoding::Raw;
        h.payloadBytes = static_cast<std::uint32_t>(e.raw.size());
        const auto hb = encodeFrameHeader(h);
        queue(c, hb.data(), hb.size());
        queue(c, e.raw.data(), e.raw.size());
    } else {
        h.encoding = FrameEncoding::Zlib;
        h.payloadBytes = static_cast<std::uint32_t>(encoded->bytes.size());
        const auto hb = encodeFrameHeader(h);
        queue(c, hb.data(), hb.size());
        queue(c, encoded->bytes.data(), encoded->bytes.size());
    }
    c.lastSent = seq;
    {
        std::lock_guard lock(m_statsMutex);
        ++m_stats.framesSent;
    }
    flush(c);
}

void FrameServer::Impl::requestEncodes() {
    // Results first: they become the rings' newest encoded frames.
    for (auto& r : m_encoder.takeResults()) {
        for (const auto& e : m_rings) {
            if (e->ring.get() == r.ring) {
                auto& slot = r.kind == EncodeKind::Zlib ? e->zlib : e->jpeg;
                if (!slot || r.frame->sequence > slot->sequence) {
                    slot = std::move(r.frame);
                }
                break;
            }
        }
    }
    // Then one request per ring and format that has clients and a newer frame than last asked.
    for (const auto& e : m_rings) {
        bool zlib = false;
        bool jpeg = false;
        for (const auto& c : m_conns) {
            if (c->dead || c->ring != e) {
                continue;
            }
            jpeg = jpeg || c->phase == Phase::Mjpeg;
            zlib = zlib || (c->phase == Phase::Stream && c->payload == StreamPayload::Zlib);
        }
        const std::uint64_t seq = e->ring->latestSequence();
        if (seq == 0) {
            continue;
        }
        if (zlib && seq > e->zlibAsked) {
            e->zlibAsked = seq;
            m_encoder.request(e->ring, seq, EncodeKind::Zlib);
        }
        if (jpeg && seq > e->jpegAsked) {
            e->jpegAsked = seq;
            m_encoder.request(e->ring, seq, EncodeKind::Jpeg);
        }
    }
}

void FrameServer::Impl::deliverNewFrames() {
    const auto now = Clock::now();
    std::uint64_t pinnedOverwrites = m_retiredPinnedOverwrites;
    for (const auto& e : m_rings) {
        pinnedOverwrites += e->ring->pinnedOverwrites();
    }
    {
        std::lock_guard lock(m_statsMutex);
        m_stats.pinnedOverwrites = pinnedOverwrites;
    }
    for (const auto& c : m_conns) {
        if (c->deferred && !c->dead && now >= c->deferredUntil) {
            offer(*c, now);
        }
    }
    requestEncodes();
    for (const auto& c : m_conns) {
        if (!c->dead && c->ring && (c->phase == Phase::Stream || c->phase == Phase::Mjpeg)) {
            offerIfNew(*c, now);
        }
    }
}

void FrameServer::Impl::deliverStatuses() {
    std::vector<PendingStatus> statuses;
    {
        std::lock_guard lock(m_statusMutex);
        statuses.swap(m_statuses);
    }
    const auto now = Clock::now();
    std::uint64_t sent = 0;
    for (const auto& st : statuses) {
        for (const auto& cp : m_conns) {
            Conn& c = *cp;
            // Only streaming socket clients that have had no frame yet; MJPEG has no place for it.
            if (c.dead || c.phase != Phase::Stream || !c.ring || c.lastSent != 0 || c.ring->key != st.key) {
                continue;
            }
            const FrameRingLayout& l = c.ring->ring->layout();
            if (l.width != st.width || l.height != st.height) {
                continue;
            }
            if (c.outPending()) {
                continue;  // it has not taken what it got (the handshake reply, the last status): no pile-up
            }
            queue(c, st.bytes->data(), st.bytes->size());
            c.streamSince = now;  // the daemon is working on this client's frame: its first-frame wait restarts
            ++sent;
            flush(c);
        }
    }
    if (sent > 0) {
        std::lock_guard lock(m_statsMutex);
        m_stats.statusesSent += sent;
    }
}

void FrameServer::Impl::checkTimeouts() {
    const auto now = Clock::now();
    const auto limit = m_options.stallTimeout;
    for (const auto& cp : m_conns) {
        Conn& c = *cp;
        if (c.dead) {
            continue;
        }
        // TCP: a send() only proves the kernel had room (hundreds of kB); progress is the peer
        // taking bytes out of the send queue (SIOCOUTQ = bytes not yet acknowledged).
        int outq = 0;
        if (c.via != Via::Unix && ::ioctl(c.fd.get(), SIOCOUTQ, &outq) == 0) {
            const std::uint64_t acked = c.bytesSent - std::min<std::uint64_t>(c.bytesSent, static_cast<std::uint64_t>(outq));
            if (acked > c.bytesAcked || (outq == 0 && !c.outPending())) {
                c.bytesAcked = acked;
                c.lastProgress = now;
            }
        }
        // Every connection must earn its slot: a handshake within handshakeTimeout of the accept,
        // then a first frame within handshakeTimeout of the handshake.
        const auto earn = m_options.handshakeTimeout;
        const auto within = [&] { return " within " + std::to_string(earn.count()) + " ms"; };
        if ((c.phase == Phase::Handshake || c.phase == Phase::HttpHead) && now - c.since > earn) {
            const std::string why = (c.phase == Phase::HttpHead ? "no complete request head" : "no complete handshake") +
                                    within();
            {
                std::lock_guard lock(m_statsMutex);
                ++m_stats.handshakeTimeouts;
                m_stats.lastError = c.peer + ": disconnected, " + why;
            }
            closeWith(c, c.phase == Phase::HttpHead
                             ? "HTTP/1.0 408 Request Timeout\r\nContent-Type: text/plain\r\nContent-Length: " +
                                   std::to_string(why.size() + 1) + "\r\nConnection: close\r\n\r\n" + why + "\n"
                             : "{\"ok\":false,\"error\":" + jsonEscape(why) + "}\n");
            continue;
        }
        if ((c.phase == Phase::Stream || c.phase == Phase::Mjpeg) && c.lastSent == 0 && now - c.streamSince > earn) {
            const FrameRingLayout& l = c.ring->ring->layout();
            const std::string why = "no frame" + within() + " of the handshake (nothing published for " + c.ring->view +
                                    " " + std::to_string(l.width) + "x" + std::to_string(l.height) + ")";
            {
                std::lock_guard lock(m_statsMutex);
                ++m_stats.firstFrameTimeouts;
                m_stats.lastError = c.peer + ": disconnected, " + why;
            }
            std::string last;
            if (c.phase == Phase::Stream && !c.outPending()) {
                // The server's last word, as a header of kind Error (docs/frame-protocol.md).
                FrameHeader h;
                h.kind = FrameKind::Error;
                const std::string text = "disconnected, " + why;
                h.payloadBytes = static_cast<std::uint32_t>(text.size());
                const auto hb = encodeFrameHeader(h);
                last = std::string(hb.begin(), hb.end()) + text;
            }
            closeWith(c, last);
            continue;
        }
        std::string why;
        if (c.phase == Phase::Draining && now - c.since > limit) {
            why = "did not close";
        } else if (c.awaitingAck && now - c.ackSince > limit) {
            why = "no ack";
        } else if ((c.outPending() || outq > 0) && now - c.lastProgress > limit) {
            why = "not reading";
        }
        if (why.empty()) {
            continue;
        }
        std::lock_guard lock(m_statsMutex);
        ++m_stats.stallDisconnects;
        m_stats.lastError = c.peer + ": disconnected, " + why + " for " + std::to_string(limit.count()) + " ms";
        c.dead = true;
    }
}

void FrameServer::Impl::closeWith(Conn& c, const std::string& bytes) {
    // One try without waiting: the connection is being dropped and must not hold its slot.
    if (!bytes.empty() && !c.outPending()) {
        [[maybe_unused]] const auto n = ::send(c.fd.get(), bytes.data(), bytes.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    }
    ::shutdown(c.fd.get(), SHUT_WR);
    c.dead = true;
}

void FrameServer::Impl::reap() {
    bool changed = false;
    for (auto it = m_conns.begin(); it != m_conns.end();) {
        if ((*it)->dead) {
            unpin(**it);
            if ((*it)->ring) {
                --(*it)->ring->clients;
            }
            it = m_conns.erase(it);  // closes the socket
            changed = true;
            std::lock_guard lock(m_statsMutex);
            ++m_stats.disconnects;
        } else {
            ++it;
        }
    }
    if (changed) {
        const auto before = m_rings.size();
        for (const auto& e : m_rings) {
            if (e->clients == 0) {
                m_retiredPinnedOverwrites += e->ring->pinnedOverwrites();
            }
        }
        std::erase_if(m_rings, [](const auto& e) { return e->clients == 0; });
        for (const auto& e : m_rings) {
            int fps = 0;
            for (const auto& c : m_conns) {
                if (c->ring == e) {
                    fps = std::max(fps, effectiveFps(c->fps));
                }
            }
            e->maxFps = fps;
        }
        (void)before;
        refreshRings();
    }
}

void FrameServer::Impl::refreshRings() {
    auto set = std::make_shared<PublishSet>();
    std::vector<ActiveProfile> active;
    for (const auto& e : m_rings) {
        set->push_back({e->key, e->ring});
        const FrameRingLayout& l = e->ring->layout();
        bool merged = false;
        for (auto& a : active) {
            if (a.profile == e->key && a.width == static_cast<int>(l.width) && a.height == static_cast<int>(l.height)) {
                a.clients += e->clients;
                a.maxFps = std::max(a.maxFps, e->maxFps);
                merged = true;
            }
        }
        if (!merged) {
            active.push_back({e->key, e->view, static_cast<int>(l.width), static_cast<int>(l.height), e->maxFps, e->clients});
        }
    }
    {
        std::lock_guard lock(m_publishMutex);
        m_publishSet = std::move(set);
    }
    std::lock_guard lock(m_statsMutex);
    m_active = std::move(active);
    m_stats.rings = m_rings.size();
    m_stats.ringBytes = 0;
    for (const auto& e : m_rings) {
        m_stats.ringBytes += e->ring->layout().totalBytes;
    }
    m_stats.connections = m_conns.size();
    m_stats.clients = m_stats.shmClients = m_stats.tcpClients = m_stats.mjpegClients = 0;
    for (const auto& c : m_conns) {
        if (c->dead || !c->ring) {
            continue;
        }
        ++m_stats.clients;
        if (c->phase == Phase::Mjpeg) {
            ++m_stats.mjpegClients;
        } else if (c->payload == StreamPayload::Shm) {
            ++m_stats.shmClients;
        } else {
            ++m_stats.tcpClients;
        }
    }
}

void FrameServer::Impl::collectMetrics(MetricsRegistry& r) const {
    const FrameServerStats s = stats();
    const stream_detail::EncoderStats es = m_encoder.stats();  // zlib and JPEG: the encoder thread
    auto d = [](auto v) { return static_cast<double>(v); };
    r.gauge("navmap_stream_clients", "Frame-stream clients connected now, by transport.")
        .sample({{"transport", "shm"}}, d(s.shmClients))
        .sample({{"transport", "tcp"}}, d(s.tcpClients))
        .sample({{"transport", "mjpeg"}}, d(s.mjpegClients));
    r.gauge("navmap_stream_rings", "Shared-memory rings (one per profile and pixel format with clients).").sample(d(s.rings));
    r.counter("navmap_stream_frames_published_total", "Frames published by the render loop.").sample(d(s.published));
    r.counter("navmap_stream_frames_sent_total", "Frames handed to clients.").sample(d(s.framesSent));
    r.counter("navmap_stream_statuses_sent_total", "Status headers handed to clients waiting for their first frame.")
        .sample(d(s.statusesSent));
    r.counter("navmap_stream_frames_dropped_total", "Frames skipped because a client was busy.").sample(d(s.framesDropped));
    r.counter("navmap_stream_held_frames_overwritten_total",
              "Frames written over a slot a client held, because every slot of its ring was held.")
        .sample(d(s.pinnedOverwrites));
    r.counter("navmap_stream_connections_total", "Connections accepted.").sample(d(s.accepted));
    r.counter("navmap_stream_errors_total", "Rejected input, by kind.")
        .sample({{"kind", "handshake"}}, d(s.handshakeErrors))
        .sample({{"kind", "protocol"}}, d(s.protocolErrors))
        .sample({{"kind", "http"}}, d(s.httpErrors));
    r.counter("navmap_stream_stall_disconnects_total", "Clients disconnected after the stall timeout.")
        .sample(d(s.stallDisconnects));
    r.counter("navmap_stream_timeouts_total",
              "Connections closed for not finishing the handshake, or not getting a first frame, in time.")
        .sample({{"kind", "handshake"}}, d(s.handshakeTimeouts))
        .sample({{"kind", "first_frame"}}, d(s.firstFrameTimeouts));
    r.counter("navmap_stream_refusals_total", "Connections and requests refused, by reason.")
        .sample({{"reason", "peer"}}, d(s.refusedPeer))
        .sample({{"reason", "transport_full"}}, d(s.refusedTransportFull))
        .sample({{"reason", "uid_full"}}, d(s.refusedUidFull))
        .sample({{"reason", "not_rendered"}}, d(s.refusedNotRendered))
        .sample({{"reason", "ring_memory"}}, d(s.refusedRingMemory))
        .sample({{"reason", "http_host"}}, d(s.refusedHost))
        .sample({{"reason", "http_token"}}, d(s.refusedToken));
    r.gauge("navmap_stream_ring_bytes", "Shared memory of all rings, and its ceiling (0: none).")
        .sample({{"stat", "used"}}, d(s.ringBytes))
        .sample({{"stat", "limit"}}, d(m_options.ringMemoryBytes));
    r.gauge("navmap_stream_publish_seconds", "Render-thread cost of publish().")
        .sample({{"stat", "last"}}, s.publishMsLast / 1000.0)
        .sample({{"stat", "max"}}, s.publishMsMax / 1000.0);
    r.counter("navmap_stream_encodes_total", "Frames compressed (zlib) or JPEG-encoded by the encoder thread.")
        .sample(d(es.encoded));
    r.counter("navmap_stream_encodes_superseded_total", "Encode requests replaced by a newer frame before they started.")
        .sample(d(es.replaced));
    r.gauge("navmap_stream_encode_seconds", "Encoder-thread time per frame.")
        .sample({{"format", "zlib"}, {"stat", "last"}}, es.zlibMsLast / 1000.0)
        .sample({{"format", "zlib"}, {"stat", "max"}}, es.zlibMsMax / 1000.0)
        .sample({{"format", "jpeg"}, {"stat", "last"}}, es.jpegMsLast / 1000.0)
        .sample({{"format", "jpeg"}, {"stat", "max"}}, es.jpegMsMax / 1000.0);
}

std::string FrameServer::Impl::statusJson() const {
    const FrameServerStats s = stats();
    nlohmann::json j;
    j["stream"] = {{"clients", s.clients},
                   {"shm_clients", s.shmClients},
                   {"tcp_clients", s.tcpClients},
                   {"mjpeg_clients", s.mjpegClients},
                   {"rings", s.rings},
                   {"published", s.published},
                   {"sent", s.framesSent},
                   {"statuses_sent", s.statusesSent},
                   {"dropped", s.framesDropped},
                   {"stall_disconnects", s.stallDisconnects},
                   {"timeouts", {{"handshake", s.handshakeTimeouts}, {"first_frame", s.firstFrameTimeouts}}},
                   {"refusals",
                    {{"peer", s.refusedPeer},
                     {"transport_full", s.refusedTransportFull},
                     {"uid_full", s.refusedUidFull},
                     {"not_rendered", s.refusedNotRendered},
                     {"ring_memory", s.refusedRingMemory},
                     {"http_host", s.refusedHost},
                     {"http_token", s.refusedToken}}},
                   {"ring_bytes", s.ringBytes},
                   {"publish_ms_last", s.publishMsLast}};
    nlohmann::json profiles = nlohmann::json::array();
    for (const auto& a : activeProfiles()) {
        profiles.push_back({{"view", a.view}, {"width", a.width}, {"height", a.height}, {"fps", a.maxFps},
                            {"clients", a.clients}});
    }
    j["stream"]["profiles"] = profiles;
    j["daemon"] = nullptr;
    if (m_options.statusJson) {
        const std::string d = m_options.statusJson();
        auto parsed = nlohmann::json::parse(d, nullptr, false);
        j["daemon"] = parsed.is_discarded() ? nlohmann::json(d) : parsed;
    }
    return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

// --- FrameServer ---

FrameServer::FrameServer(FrameServerOptions options) : m_impl(std::make_unique<Impl>(std::move(options))) {}
FrameServer::~FrameServer() = default;
Status FrameServer::start() { return m_impl->start(); }
void FrameServer::stop() { m_impl->stop(); }
std::size_t FrameServer::publish(const std::string& profile, const FrameView& frame) { return m_impl->publish(profile, frame); }
Status FrameServer::publishStatus(const std::string& profile, int width, int height, std::string json) {
    return m_impl->publishStatus(profile, width, height, std::move(json));
}
std::vector<ActiveProfile> FrameServer::activeProfiles() const { return m_impl->activeProfiles(); }
FrameServerStats FrameServer::stats() const { return m_impl->stats(); }
void FrameServer::collectMetrics(MetricsRegistry& registry) const { m_impl->collectMetrics(registry); }
std::string FrameServer::metricsText() const {
    MetricsRegistry registry;
    m_impl->collectMetrics(registry);
    return registry.text();
}
int FrameServer::tcpPort() const noexcept { return m_impl->m_tcpPort; }
int FrameServer::httpPort() const noexcept { return m_impl->m_httpPort; }
const FrameServerOptions& FrameServer::options() const noexcept { return m_impl->m_options; }

}  // namespace navmap::ipc
