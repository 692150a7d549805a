// SPDX-License-Identifier: Apache-2.0
// Control socket server on net::PollLoop (the poll() loop of the frame server too, in the
// manner of Redis ae.c/anet.c). Each client has an input buffer split into lines and an output
// buffer drained when the socket is writable, so neither a slow nor a malicious client can block
// the daemon; a connection without traffic for the idle timeout, or one that leaves what it was
// sent unread that long, is closed, so silent clients cannot hold every slot. Slots are capped per
// uid and privileged peers (the HMI) take the slot of the longest-silent unprivileged one when all
// are taken.

#include "navmap/ipc/control/control_server.h"

#include <linux/sockios.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <variant>

#include "navmap/ipc/control/control_protocol.h"
#include "navmap/ipc/net/socket_access.h"
#include "navmap/ipc/net/sys_error.h"

namespace navmap::ipc {

using net::sysError;
using net::UniqueFd;

namespace {

constexpr std::size_t kReadChunk = 64 * 1024;
constexpr std::size_t kMaxReadsPerPoll = 16;  // fairness between clients
constexpr std::size_t kMaxPendingEvents = 1024;

using SteadyClock = std::chrono::steady_clock;

std::string seconds(std::chrono::milliseconds d) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g s", static_cast<double>(d.count()) / 1000.0);
    return buf;
}

/// Bytes (kernel accounting, not exact) the peer has not read yet of what was sent on `fd`; for
/// a Unix stream socket SIOCOUTQ stays above zero until the peer has read every byte.
int unreadBytes(int fd) {
    int n = 0;
    if (::ioctl(fd, SIOCOUTQ, &n) != 0) {
        return 0;  // cannot tell: the idle rule for silent clients still applies
    }
    return n;
}

}  // namespace

struct ControlServer::Client {
    UniqueFd fd;
    uid_t uid = 0;
    pid_t pid = 0;
    bool privileged = false;
    std::string in;
    std::size_t scanned = 0;  // bytes of `in` known to hold no newline
    std::string out;
    std::uint8_t events = 0;  // subscriptions
    bool close_after_flush = false;
    bool dead = false;
    SteadyClock::time_point last_activity{};  // last byte received from it or taken by its socket
    SteadyClock::time_point last_received{};  // last byte received from it (or the accept)
    // Since when bytes sent to it have been waiting unread (set at a send while it had read
    // everything before, cleared when its socket is seen empty); unset: it has read everything.
    std::optional<SteadyClock::time_point> unread_since;
};

ControlServer::ControlServer(ControlServerConfig config, ControlHandler& handler)
    : m_config(std::move(config)), m_handler(handler), m_loop(m_config.socket_path) {}

Result<std::unique_ptr<ControlServer>> ControlServer::create(ControlServerConfig config, ControlHandler& handler) {
    const std::string path = config.socket_path;
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    if (path.empty() || path.size() >= sizeof(addr.sun_path)) {
        return Error{"control socket path \"" + path + "\": length must be 1.." +
                     std::to_string(sizeof(addr.sun_path) - 1) + " bytes"};
    }
    std::memcpy(addr.sun_path, path.data(), path.size());
    std::unique_ptr<ControlServer> s(new ControlServer(std::move(config), handler));

    s->m_listen_fd.reset(::socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
    if (!s->m_listen_fd.valid()) {
        return Error{sysError("socket", path)};
    }
    // A socket file left by a crashed daemon is replaced; one with a live server is not.
    struct stat st {};
    if (::lstat(path.c_str(), &st) == 0) {
        if (!S_ISSOCK(st.st_mode)) {
            return Error{"control socket path " + path + ": exists and is not a socket"};
        }
        const UniqueFd probe(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
        if (!probe.valid()) {
            return Error{sysError("socket", path)};
        }
        const bool live = ::connect(probe.get(), reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0;
        if (live) {
            return Error{"bind(" + path + "): Address in use (another server is listening)"};
        }
        if (::unlink(path.c_str()) != 0) {
            return Error{sysError("unlink", path)};
        }
    }
    // The file bind() creates is never wider than the mode; the exact mode and the group are set
    // before listen(), and nobody can connect before listen(): no moment with wider access. The
    // file appears at `path` only once the socket listens.
    if (auto access = restrictSocketBeforeBind(s->m_listen_fd.get(), s->m_config.socket_mode, path); !access) {
        return Error{access.message()};
    }
    if (auto bound =
            bindAndListenUnix(s->m_listen_fd.get(), path, s->m_config.socket_mode, s->m_config.socket_group, 16);
        !bound) {
        return Error{bound.message()};
    }
    if (::lstat(path.c_str(), &st) == 0) {
        s->m_socket_inode = st.st_ino;
    }
    if (auto opened = s->m_loop.open(); !opened) {
        return Error{opened.message()};
    }
    // Only noted here: new connections are accepted after the clients' input and the idle
    // closes of the round (pollOnce()).
    ControlServer* self = s.get();
    s->m_loop.add(
        s->m_listen_fd.get(), [] { return static_cast<short>(POLLIN); },
        [self](short revents) { self->m_accept_ready = self->m_accept_ready || (revents & POLLIN) != 0; });
    return s;
}

ControlServer::~ControlServer() {
    stop();
    m_loop.close();
    m_clients.clear();  // closes their sockets
    if (m_listen_fd.valid()) {
        m_listen_fd.reset();
        // Remove the socket file only if it is still ours.
        struct stat st {};
        if (m_socket_inode != 0 && ::lstat(m_config.socket_path.c_str(), &st) == 0 && st.st_ino == m_socket_inode) {
            ::unlink(m_config.socket_path.c_str());
        }
    }
}

Status ControlServer::start() {
    if (m_thread.joinable()) {
        return Error{"control server " + m_config.socket_path + ": already running"};
    }
    m_stop = false;
    m_thread = std::thread([this] {
        while (!m_stop.load()) {
            if (!pollOnce(std::chrono::milliseconds(500)).ok()) {
                std::this_thread::sleep_for(std::chrono::milliseconds(10));
            }
        }
    });
    return {};
}

void ControlServer::stop() noexcept {
    m_stop = true;
    wake();
    if (m_thread.joinable()) {
        m_thread.join();
    }
}

void ControlServer::wake() noexcept { m_loop.wake(); }

void ControlServer::publish(const ControlEvent& event) {
    {
        std::lock_guard lock(m_event_mutex);
        if (m_pending_events.size() >= kMaxPendingEvents) {
            m_pending_events.pop_front();
        }
        m_pending_events.push_back(event);
    }
    wake();
}

ControlServerStats ControlServer::stats() const {
    ControlServerStats s;
    s.connections = m_counters.connections;
    s.refused_peer = m_counters.refused_peer;
    s.refused_full = m_counters.refused_full;
    s.refused_uid_full = m_counters.refused_uid_full;
    s.refused_subscribers = m_counters.refused_subscribers;
    s.evictions = m_counters.evictions;
    s.lines = m_counters.lines;
    s.commands = m_counters.commands;
    s.errors = m_counters.errors;
    s.overlong_disconnects = m_counters.overlong;
    s.slow_disconnects = m_counters.slow;
    s.idle_disconnects = m_counters.idle;
    s.events = m_counters.events;
    s.clients = m_counters.clients;
    return s;
}

Status ControlServer::pollOnce(std::chrono::milliseconds timeout) {
    // Wake up in time to close the first connection that turns idle.
    auto wait = std::max(std::chrono::milliseconds(0), timeout);
    if (m_config.idle_timeout.count() > 0) {
        const auto now = SteadyClock::now();
        for (const auto& c : m_clients) {
            const auto deadline = idleDeadline(*c);
            if (deadline != SteadyClock::time_point::max()) {
                const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - now);
                wait = std::clamp(left, std::chrono::milliseconds(0), wait);
            }
        }
    }
    m_accept_ready = false;
    // Clients with input are read in the loop's callbacks (watch()), the listening socket only noted.
    if (auto st = m_loop.runOnce(std::min(wait, std::chrono::milliseconds(1 << 30))); !st) {
        return st;
    }
    for (auto& c : m_clients) {
        if (!c->dead && !c->out.empty()) {
            flush(*c);
        }
        if (!c->dead && c->close_after_flush && c->out.empty()) {
            c->dead = true;
        }
    }
    // Idle connections go before new ones are accepted, so a waiting client gets a free slot.
    closeIdle(SteadyClock::now());
    removeDead();
    if (m_accept_ready) {
        acceptClients();
    }
    deliverEvents();
    removeDead();
    return {};
}

void ControlServer::watch(Client& c) {
    Client* client = &c;
    m_loop.add(
        c.fd.get(),
        [client] {
            short ev = client->close_after_flush ? 0 : POLLIN;
            if (!client->out.empty()) {
                ev = static_cast<short>(ev | POLLOUT);
            }
            return ev;
        },
        [this, client](short revents) {
            // A hang-up or an error without POLLIN is read too, to see the end of the stream;
            // POLLOUT alone is for flush() after the round.
            if ((revents & (POLLIN | POLLHUP | POLLERR)) != 0 &&
                ((revents & POLLIN) != 0 || (revents & POLLOUT) == 0)) {
                readClient(*client);
            }
        });
}

void ControlServer::removeDead() {
    const auto before = m_clients.size();
    for (const auto& c : m_clients) {
        if (c->dead) {
            m_loop.remove(c->fd.get());  // before its socket closes and the number is reused
        }
    }
    std::erase_if(m_clients, [](const std::unique_ptr<Client>& c) { return c->dead; });  // closes their sockets
    if (before != m_clients.size()) {
        m_counters.clients = m_clients.size();
    }
}

SteadyClock::time_point ControlServer::idleDeadline(const Client& c) const {
    auto deadline = SteadyClock::time_point::max();
    if (m_config.idle_timeout.count() <= 0 || c.dead) {
        return deadline;
    }
    // A subscriber at rest waits for events by design (position_lost may come hours later): only
    // bytes it leaves unread can make it idle.
    if (c.events == 0 || !c.out.empty() || c.close_after_flush) {
        deadline = c.last_activity + m_config.idle_timeout;
    }
    if (c.unread_since) {
        deadline = std::min(deadline, *c.unread_since + m_config.idle_timeout);
    }
    return deadline;
}

bool ControlServer::idle(Client& c, SteadyClock::time_point now) const {
    if (m_config.idle_timeout.count() <= 0 || c.dead) {
        return false;
    }
    // Stalled: what it was sent has waited unread for the timeout, whatever it sends meanwhile
    // (a subscriber that never reads would otherwise hold its slot for ever while no event
    // comes). One that has read everything by now is not stalled.
    if (c.unread_since && now - *c.unread_since >= m_config.idle_timeout) {
        if (!c.out.empty() || unreadBytes(c.fd.get()) > 0) {
            return true;
        }
        c.unread_since.reset();
    }
    if (now - c.last_activity < m_config.idle_timeout) {
        return false;
    }
    return c.events == 0 || !c.out.empty() || c.close_after_flush;
}

void ControlServer::closeIdle(SteadyClock::time_point now) {
    for (auto& c : m_clients) {
        if (!idle(*c, now)) {
            continue;
        }
        ++m_counters.idle;
        if (c->out.empty() && !c->close_after_flush) {
            // Best effort: the reason goes out if the socket takes it now; the slot is freed anyway.
            const bool stalled = c->unread_since.has_value();
            queue(*c, controlErrorReply("", std::nullopt,
                                        stalled ? "left its replies and events unread for " +
                                                      seconds(m_config.idle_timeout) + "; disconnecting"
                                                : "idle for " + seconds(m_config.idle_timeout) +
                                                      " without a request; disconnecting"));
            flush(*c);
        }
        c->dead = true;
    }
}

void ControlServer::acceptClients() {
    for (;;) {
        UniqueFd fd(::accept4(m_listen_fd.get(), nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC));
        if (!fd.valid()) {
            return;  // EAGAIN, or a transient error (EMFILE, ECONNABORTED): try again next poll
        }
        auto c = std::make_unique<Client>();
        c->last_activity = c->last_received = SteadyClock::now();
        std::string refusal;
        auto cred = peerCredentials(fd.get(), m_config.socket_path);
        if (!cred) {
            refusal = cred.error().message;
        } else {
            c->uid = cred.value().uid;
            c->pid = cred.value().pid;
            PeerAllowList allow{m_config.allowed_uids, m_config.allowed_gids, m_config.allow_root};
            if (m_config.socket_group) {
                allow.gids.push_back(*m_config.socket_group);
            }
            if (!peerAllowed(allow, cred.value())) {
                refusal = peerRefusal(cred.value(), m_config.socket_path);
                ++m_counters.refused_peer;
            }
        }
        if (refusal.empty()) {
            refusal = admit(*c);
        }
        if (!refusal.empty()) {
            const std::string line = controlErrorReply("", std::nullopt, refusal) + "\n";
            [[maybe_unused]] const auto w = ::send(fd.get(), line.data(), line.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
            continue;  // `fd` closes
        }
        c->fd = std::move(fd);
        ++m_counters.connections;
        watch(*c);
        m_clients.push_back(std::move(c));
        m_counters.clients = m_clients.size();
    }
}

bool ControlServer::privileged(uid_t uid) const {
    return uid == 0 || uid == ::geteuid() ||
           std::find(m_config.privileged_uids.begin(), m_config.privileged_uids.end(), uid) !=
               m_config.privileged_uids.end();
}

std::size_t ControlServer::countUid(uid_t uid, bool subscribers_only) const {
    return static_cast<std::size_t>(std::count_if(m_clients.begin(), m_clients.end(), [&](const auto& o) {
        return !o->dead && o->uid == uid && (!subscribers_only || o->events != 0);
    }));
}

std::string ControlServer::admit(Client& c) {
    c.privileged = privileged(c.uid);
    // Unprivileged uids are capped each, so one of them cannot take every slot; privileged peers
    // are bounded by max_clients alone (they are who the slots are kept for).
    if (!c.privileged && countUid(c.uid, false) >= m_config.max_clients_per_uid) {
        ++m_counters.refused_uid_full;
        return "too many connections from uid " + std::to_string(c.uid) + " (limit " +
               std::to_string(m_config.max_clients_per_uid) + ")";
    }
    const auto live = static_cast<std::size_t>(
        std::count_if(m_clients.begin(), m_clients.end(), [](const auto& o) { return !o->dead; }));
    if (live < m_config.max_clients) {
        return {};
    }
    // Full. A privileged peer takes the slot of the unprivileged connection that has been silent
    // longest; an unprivileged one, or a privileged one when privileged peers hold every slot, is
    // refused.
    Client* victim = nullptr;
    if (c.privileged) {
        for (const auto& o : m_clients) {
            if (!o->dead && !o->privileged && (victim == nullptr || o->last_received < victim->last_received)) {
                victim = o.get();
            }
        }
    }
    if (victim == nullptr) {
        ++m_counters.refused_full;
        return "too many clients (limit " + std::to_string(m_config.max_clients) + ")";
    }
    ++m_counters.evictions;
    if (!victim->close_after_flush && victim->out.empty()) {
        // Best effort, like the idle reason: the slot is freed whether or not the socket takes it.
        queue(*victim, controlErrorReply("", std::nullopt,
                                         "slot taken by privileged uid " + std::to_string(c.uid) + " (all " +
                                             std::to_string(m_config.max_clients) + " in use); disconnecting"));
        flush(*victim);
    }
    victim->dead = true;
    return {};
}

void ControlServer::readClient(Client& c) {
    char buf[kReadChunk];
    bool eof = false;
    for (std::size_t k = 0; k < kMaxReadsPerPoll; ++k) {
        const ssize_t n = ::recv(c.fd.get(), buf, sizeof buf, MSG_DONTWAIT);
        if (n > 0) {
            c.last_activity = c.last_received = SteadyClock::now();
            c.in.append(buf, static_cast<std::size_t>(n));
            // Lines complete so far are handled before reading more, so a client cannot make
            // the buffer grow past one maximum line plus one chunk.
            std::size_t start = 0;
            for (;;) {
                const auto nl = c.in.find('\n', std::max(start, c.scanned));
                if (nl == std::string::npos) {
                    break;
                }
                std::string_view line(c.in.data() + start, nl - start);
                if (!line.empty() && line.back() == '\r') {
                    line.remove_suffix(1);
                }
                if (line.size() > m_config.limits.max_line_bytes) {
                    break;  // handled below as over-long
                }
                handleLine(c, line);
                start = nl + 1;
                c.scanned = start;
                if (c.dead || c.close_after_flush) {
                    return;
                }
            }
            c.in.erase(0, start);
            c.scanned = c.in.size();
            if (c.in.size() > m_config.limits.max_line_bytes) {
                ++m_counters.overlong;
                ++m_counters.errors;
                queue(c, controlErrorReply("", std::nullopt,
                                           "line longer than " + std::to_string(m_config.limits.max_line_bytes) +
                                               " bytes; disconnecting"));
                c.in.clear();
                c.close_after_flush = true;
                return;
            }
            continue;
        }
        if (n == 0) {
            eof = true;
        } else if (errno == EINTR) {
            continue;
        } else if (errno != EAGAIN && errno != EWOULDBLOCK) {
            c.dead = true;
            return;
        }
        break;
    }
    if (eof) {
        // The peer is done sending; answer what it sent (best effort) and close.
        c.close_after_flush = true;
    }
}

void ControlServer::handleLine(Client& c, std::string_view line) {
    if (line.find_first_not_of(" \t") == std::string_view::npos) {
        return;  // blank lines are keep-alives
    }
    ++m_counters.lines;
    ControlParse p = parseControlLine(line, m_config.limits);
    if (!p.command) {
        ++m_counters.errors;
        queue(c, controlErrorReply(p.cmd, p.id, p.error));
        return;
    }
    const ControlCommand& cmd = *p.command;
    Status st;
    nlohmann::json extra = nullptr;
    std::visit(
        [&](const auto& body) {
            using T = std::decay_t<decltype(body)>;
            if constexpr (std::is_same_v<T, SetRouteCommand>) {
                st = m_handler.setRoute(body);
                if (st.ok()) {
                    extra = {{"points", body.points.size()}, {"maneuvers", body.maneuvers.size()}};
                }
            } else if constexpr (std::is_same_v<T, ClearRouteCommand>) {
                st = m_handler.clearRoute();
            } else if constexpr (std::is_same_v<T, SetViewCommand>) {
                st = m_handler.setView(body);
            } else if constexpr (std::is_same_v<T, SetStyleCommand>) {
                st = m_handler.setStyle(body);
            } else if constexpr (std::is_same_v<T, GetStatusCommand>) {
                nlohmann::json status = m_handler.status();
                if (!status.is_object()) {
                    st = Error{"internal: the daemon's status is not a JSON object"};
                } else {
                    nlohmann::json server = {{"clients", m_clients.size()},
                                             {"lines", m_counters.lines.load()},
                                             {"errors", m_counters.errors.load()},
                                             {"refused_peer", m_counters.refused_peer.load()},
                                             {"refused_full", m_counters.refused_full.load()},
                                             {"refused_uid_full", m_counters.refused_uid_full.load()},
                                             {"refused_subscribers", m_counters.refused_subscribers.load()},
                                             {"evictions", m_counters.evictions.load()},
                                             {"idle_disconnects", m_counters.idle.load()}};
                    if (!status.contains("control")) {
                        status["control"] = std::move(server);
                    }
                    extra = {{"status", std::move(status)}};
                }
            } else if constexpr (std::is_same_v<T, SubscribeCommand>) {
                if (c.events == 0 && body.events != 0 && !c.privileged &&
                    countUid(c.uid, true) >= m_config.max_subscribers_per_uid) {
                    ++m_counters.refused_subscribers;
                    st = Error{"too many subscribers from uid " + std::to_string(c.uid) + " (limit " +
                               std::to_string(m_config.max_subscribers_per_uid) + ")"};
                    return;
                }
                c.events = body.events;
                nlohmann::json names = nlohmann::json::array();
                for (const auto k : {ControlEventKind::RouteProgress, ControlEventKind::PositionLost,
                                     ControlEventKind::PositionRegained, ControlEventKind::OffRoute,
                                     ControlEventKind::BackOnRoute, ControlEventKind::GpuReset}) {
                    if (body.events & static_cast<std::uint8_t>(k)) {
                        names.push_back(controlEventName(k));
                    }
                }
                extra = {{"events", std::move(names)}};
            }
        },
        cmd.body);
    if (!st.ok()) {
        ++m_counters.errors;
        queue(c, controlErrorReply(cmd.cmd, cmd.request_id, st.message()));
        return;
    }
    ++m_counters.commands;
    queue(c, controlOkReply(cmd.cmd, cmd.request_id, extra));
}

void ControlServer::queue(Client& c, const std::string& line) {
    if (c.dead) {
        return;
    }
    c.out += line;
    c.out.push_back('\n');
    if (c.out.size() > m_config.max_output_bytes) {
        ++m_counters.slow;
        c.dead = true;  // not reading its replies/events: drop it rather than buffer forever
    }
}

void ControlServer::flush(Client& c) {
    if (c.unread_since && !c.out.empty() && unreadBytes(c.fd.get()) == 0) {
        c.unread_since.reset();  // it has read everything sent before: what goes now starts a new wait
    }
    while (!c.out.empty()) {
        const ssize_t n = ::send(c.fd.get(), c.out.data(), c.out.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n > 0) {
            c.out.erase(0, static_cast<std::size_t>(n));
            c.last_activity = SteadyClock::now();
            if (!c.unread_since) {
                c.unread_since = c.last_activity;
            }
            continue;
        }
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
            return;
        }
        c.dead = true;  // EPIPE, ECONNRESET: the client is gone
        return;
    }
}

void ControlServer::deliverEvents() {
    std::deque<ControlEvent> events;
    {
        std::lock_guard lock(m_event_mutex);
        events.swap(m_pending_events);
    }
    for (const auto& e : events) {
        std::string line;
        for (auto& c : m_clients) {
            if (c->dead || c->close_after_flush || !(c->events & static_cast<std::uint8_t>(e.kind))) {
                continue;
            }
            if (line.empty()) {
                line = controlEventLine(e);
            }
            queue(*c, line);
            ++m_counters.events;
            flush(*c);
        }
    }
}

}  // namespace navmap::ipc
