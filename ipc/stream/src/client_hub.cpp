// SPDX-License-Identifier: Apache-2.0
#include "client_hub.h"

#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <utility>

#include "navmap/ipc/net/poll_loop.h"
#include "stream_rings.h"
#include "stream_transport.h"

namespace navmap::ipc::stream_detail {

ClientHub::ClientHub(const FrameServerOptions& options, StreamStats& stats, RingSet& rings, PollLoop& loop,
                     FrameEncoder& encoder)
    : m_options(options), m_stats(stats), m_rings(rings), m_loop(loop), m_encoder(encoder), m_timeouts(options) {}

void ClientHub::setTransport(StreamTransport& transport) {
    m_transports[static_cast<std::size_t>(transport.via())] = &transport;
}

StreamTransport& ClientHub::transport(const StreamConn& c) const {
    return *m_transports[static_cast<std::size_t>(c.via)];
}

std::optional<Refusal> ClientHub::checkCaps(Via via, std::optional<uid_t> uid, const std::string& address) const {
    const auto same_via = static_cast<std::size_t>(
        std::count_if(m_conns.begin(), m_conns.end(), [&](const auto& c) { return c->via == via; }));
    if (same_via >= m_options.max_clients_per_transport) {
        return Refusal{&FrameServerStats::refused_transport_full,
                       std::string("too many ") + viaName(via) + " clients (limit " +
                           std::to_string(m_options.max_clients_per_transport) + ")"};
    }
    if (!address.empty()) {
        const auto same_address = static_cast<std::size_t>(std::count_if(
            m_conns.begin(), m_conns.end(), [&](const auto& c) { return c->via == via && c->address == address; }));
        if (same_address >= m_options.max_clients_per_address) {
            return Refusal{&FrameServerStats::refused_address_full,
                           std::string("too many ") + viaName(via) + " connections from " + address + " (limit " +
                               std::to_string(m_options.max_clients_per_address) + ")"};
        }
    }
    if (!uid) {
        return std::nullopt;
    }
    const auto same_uid = static_cast<std::size_t>(
        std::count_if(m_conns.begin(), m_conns.end(), [&](const auto& c) { return c->uid == uid; }));
    if (same_uid >= m_options.max_clients_per_uid) {
        return Refusal{&FrameServerStats::refused_uid_full, "too many connections from uid " + std::to_string(*uid) +
                                                                " (limit " +
                                                                std::to_string(m_options.max_clients_per_uid) + ")"};
    }
    return std::nullopt;
}

void ClientHub::add(std::unique_ptr<StreamConn> conn) {
    StreamConn* c = conn.get();
    m_loop.add(
        c->fd.get(), [c] { return static_cast<short>(c->outPending() ? POLLIN | POLLOUT : POLLIN); },
        [this, c](short revents) { onEvents(*c, revents); });
    m_conns.push_back(std::move(conn));
    refreshRings();
}

void ClientHub::onEvents(StreamConn& c, short revents) {
    if (c.dead) {
        return;
    }
    if ((revents & (POLLIN | POLLHUP | POLLERR)) != 0) {
        onReadable(c);
    }
    if (!c.dead && (revents & POLLOUT) != 0) {
        flush(c);
    }
}

void ClientHub::onReadable(StreamConn& c) {
    char buf[65536];
    for (int rounds = 0; rounds < 16; ++rounds) {
        const ssize_t n = ::recv(c.fd.get(), buf, sizeof(buf), MSG_DONTWAIT);
        if (n > 0) {
            if (c.phase == Phase::Draining || c.phase == Phase::Mjpeg) {
                continue;  // nothing more is expected from them; discard
            }
            c.in.append(buf, static_cast<std::size_t>(n));
            transport(c).onInput(c);
            continue;
        }
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) {
            return;
        }
        c.dead = true;  // closed by the peer, or broken
        return;
    }
}

void ClientHub::flush(StreamConn& c) {
    if (!c.sendQueued()) {
        return;
    }
    if (c.close_when_flushed) {
        // Half-close and read until the peer closes, so unread input cannot turn into a reset
        // that destroys the reply on its way.
        ::shutdown(c.fd.get(), SHUT_WR);
        c.close_when_flushed = false;
        c.phase = Phase::Draining;
        c.since = Clock::now();
        return;
    }
    if (c.pending && !c.busy() && (c.phase == Phase::Stream || c.phase == Phase::Mjpeg)) {
        transport(c).sendFrame(c);
    }
}

void ClientHub::finishWith(StreamConn& c, const std::string& bytes) {
    c.queue(bytes.data(), bytes.size());
    c.close_when_flushed = true;
    c.phase = Phase::Draining;
    c.since = Clock::now();
    flush(c);
}

void ClientHub::offer(StreamConn& c, Clock::time_point now) {
    // Frame-rate cap per client, with 25% slack for render-time jitter.
    if (c.fps > 0 && c.offered) {
        const auto period = std::chrono::nanoseconds(1000000000LL / c.fps);
        if (now - c.last_offer < period * 3 / 4) {
            // Too early for this client; if no newer frame comes, it still gets this one when due.
            c.deferred_until = c.last_offer + period * 3 / 4;
            c.deferred = true;
            return;
        }
    }
    c.deferred = false;
    c.last_offer = now;
    c.offered = true;
    if (c.busy()) {
        if (c.pending) {
            // The frame waiting for this client is replaced by a newer one: that one is dropped.
            ++c.dropped;
            m_stats.count(&FrameServerStats::frames_dropped);
        }
        c.pending = true;
        return;
    }
    c.pending = true;
    transport(c).sendFrame(c);
}

std::uint64_t ClientHub::available(const StreamConn& c) const {
    const RingEntry& e = *c.ring;
    std::uint64_t seq = 0;
    if (c.phase == Phase::Mjpeg) {
        seq = e.jpeg ? e.jpeg->sequence : 0;
    } else if (c.payload == StreamPayload::Zlib) {
        seq = e.zlib ? e.zlib->sequence : 0;
    } else if (c.payload == StreamPayload::Dmabuf) {
        return e.dmabuf->latestSequence();  // a sequence of its own: no ring frames
    } else {
        seq = e.ring->latestSequence();
    }
    return seq < e.first_seq ? 0 : seq;  // rendered before the ring was idle: not for these clients
}

void ClientHub::offerIfNew(StreamConn& c, Clock::time_point now) {
    const std::uint64_t seq = available(c);
    if (seq > c.seen) {
        c.seen = seq;
        offer(c, now);
    }
}

void ClientHub::frameSent(StreamConn& c, std::uint64_t seq) {
    c.last_sent = seq;
    m_stats.count(&FrameServerStats::frames_sent);
    flush(c);
}

std::chrono::milliseconds ClientHub::nextWait() const {
    // Wake at least every 20 ms (stall checks), earlier when a rate-capped frame falls due.
    auto wait = std::chrono::milliseconds(20);
    const auto now = Clock::now();
    for (const auto& c : m_conns) {
        if (c->deferred) {
            wait = std::min(wait, std::chrono::ceil<std::chrono::milliseconds>(
                                      std::max(c->deferred_until - now, Clock::duration::zero())));
        }
    }
    return wait;
}

void ClientHub::requestEncodes() {
    // Results first: they become the rings' newest encoded frames.
    m_rings.takeEncodes(m_encoder.takeResults());
    // Then one request per ring and format that has clients and a newer frame than last asked.
    for (const auto& e : m_rings.entries()) {
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
        if (zlib && seq > e->zlib_asked) {
            e->zlib_asked = seq;
            m_encoder.request(e->ring, seq, EncodeKind::Zlib);
        }
        if (jpeg && seq > e->jpeg_asked) {
            e->jpeg_asked = seq;
            m_encoder.request(e->ring, seq, EncodeKind::Jpeg);
        }
    }
}

void ClientHub::deliverNewFrames() {
    const auto now = Clock::now();
    const std::uint64_t pinned_overwrites = m_rings.pinnedOverwrites();
    m_stats.update([&](FrameServerStats& s) { s.pinned_overwrites = pinned_overwrites; });
    for (const auto& c : m_conns) {
        if (c->deferred && !c->dead && now >= c->deferred_until) {
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

void ClientHub::deliverStatus(const PendingStatus& st, Clock::time_point now, std::uint64_t* sent) {
    for (const auto& cp : m_conns) {
        StreamConn& c = *cp;
        // Only streaming socket clients that have had no frame yet; MJPEG has no place for it.
        if (c.dead || c.phase != Phase::Stream || !c.ring || c.last_sent != 0 || c.ring->key != st.key) {
            continue;
        }
        const FrameRingLayout& l = c.ring->ring->layout();
        if (l.width != st.width || l.height != st.height) {
            continue;
        }
        if (c.outPending()) {
            continue;  // it has not taken what it got (the handshake reply, the last status): no pile-up
        }
        c.queue(st.bytes->data(), st.bytes->size());
        c.stream_since = now;  // the daemon is working on this client's frame: its first-frame wait restarts
        ++*sent;
        flush(c);
    }
}

void ClientHub::deliverStatuses(const std::vector<PendingStatus>& statuses) {
    const auto now = Clock::now();
    std::uint64_t sent = 0;
    for (const auto& st : statuses) {
        deliverStatus(st, now, &sent);
    }
    if (sent > 0) {
        m_stats.count(&FrameServerStats::statuses_sent, sent);
    }
}

void ClientHub::checkTimeouts() {
    const auto now = Clock::now();
    for (const auto& cp : m_conns) {
        StreamConn& c = *cp;
        if (c.dead) {
            continue;
        }
        const TimeoutVerdict v = m_timeouts.check(c, now);
        const std::string last_error = c.peer + ": disconnected, " + v.why;
        switch (v.kind) {
            case TimeoutVerdict::Kind::None: break;
            case TimeoutVerdict::Kind::Handshake:
                m_stats.countError(&FrameServerStats::handshake_timeouts, last_error);
                c.closeWith(transport(c).handshakeTimeoutReply(v.why));
                break;
            case TimeoutVerdict::Kind::FirstFrame:
                m_stats.countError(&FrameServerStats::first_frame_timeouts, last_error);
                c.closeWith(transport(c).firstFrameTimeoutReply(c, "disconnected, " + v.why));
                break;
            case TimeoutVerdict::Kind::Stall:
                m_stats.countError(&FrameServerStats::stall_disconnects, last_error);
                c.dead = true;
                break;
        }
    }
}

void ClientHub::reap() {
    bool changed = false;
    for (auto it = m_conns.begin(); it != m_conns.end();) {
        if (!(*it)->dead) {
            ++it;
            continue;
        }
        (*it)->unpin();
        if ((*it)->ring) {
            --(*it)->ring->clients;
            if ((*it)->payload == StreamPayload::Dmabuf) {
                --(*it)->ring->dmabuf_clients;
            }
        }
        m_loop.remove((*it)->fd.get());
        it = m_conns.erase(it);  // closes the socket
        changed = true;
        m_stats.count(&FrameServerStats::disconnects);
    }
    if (changed) {
        m_rings.retireUnused();
        recountFps();
        refreshRings();
    }
}

void ClientHub::recountFps() {
    for (const auto& e : m_rings.entries()) {
        int fps = 0;
        for (const auto& c : m_conns) {
            if (c->ring == e) {
                fps = std::max(fps, effectiveFps(c->fps));
            }
        }
        e->max_fps = fps;
    }
}

void ClientHub::countClients(FrameServerStats& s) const {
    s.connections = m_conns.size();
    s.clients = s.shm_clients = s.tcp_clients = s.mjpeg_clients = s.dmabuf_clients = 0;
    for (const auto& c : m_conns) {
        if (c->dead || !c->ring) {
            continue;
        }
        ++s.clients;
        if (c->phase == Phase::Mjpeg) {
            ++s.mjpeg_clients;
        } else if (c->payload == StreamPayload::Shm) {
            ++s.shm_clients;
        } else if (c->payload == StreamPayload::Dmabuf) {
            ++s.dmabuf_clients;
        } else {
            ++s.tcp_clients;
        }
    }
}

void ClientHub::refreshRings() {
    m_rings.updatePublishSet();
    m_stats.setActive(m_rings.activeProfiles());
    const std::size_t rings = m_rings.activeCount();
    const std::size_t rings_idle = m_rings.idleCount();
    const std::size_t ring_bytes = m_rings.totalBytes();
    m_stats.update([&](FrameServerStats& s) {
        s.rings = rings;
        s.rings_idle = rings_idle;
        s.ring_bytes = ring_bytes;
        countClients(s);
    });
}

void ClientHub::clear() {
    for (const auto& c : m_conns) {
        m_loop.remove(c->fd.get());
    }
    m_conns.clear();
}

}  // namespace navmap::ipc::stream_detail
