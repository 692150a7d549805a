// SPDX-License-Identifier: Apache-2.0
#include "frame_feed.h"

namespace navmap::ipc::wayland {

namespace {

// StreamClient's words for a refusal in the handshake (docs/frame-protocol.md "Handshake").
bool isRefusal(const std::string& error) { return error.rfind("handshake refused by ", 0) == 0; }

}  // namespace

FrameFeed::FrameFeed(ReconnectOptions options, bool negotiate, std::FILE* log)
    : m_base(std::move(options)), m_negotiate(negotiate), m_log(log) {
    // In place in the ring where the pixels are in shared memory, or in the read-only mapping of an
    // exported buffer (payload dmabuf, or shm after its fallback): the window's copy is the only one.
    m_base.request.hold =
        m_base.request.payload == StreamPayload::Shm || m_base.request.payload == StreamPayload::Dmabuf;
    m_client = std::make_unique<ReconnectingClient>(m_base);
}

std::pair<int, int> FrameFeed::requestedSize() const noexcept {
    const StreamProfile& p = m_client->options().request.profile;
    return {p.width, p.height};
}

void FrameFeed::request(int width, int height) {
    if (requestedSize() == std::pair{width, height}) return;
    release();
    ReconnectOptions o = m_base;
    o.request.profile.width = width;
    o.request.profile.height = height;
    m_client = std::make_unique<ReconnectingClient>(std::move(o));
    m_was_connected = false;
}

void FrameFeed::wantSize(int width, int height) {
    if (!m_negotiate || width <= 0 || height <= 0) return;
    const StreamProfile& base = m_base.request.profile;
    const bool in_range = width >= kMinStreamDimension && width <= kMaxStreamDimension &&
                          height >= kMinStreamDimension && height <= kMaxStreamDimension;
    if (!in_range || m_refused.count({width, height}) != 0) {
        request(base.width, base.height);  // the profile's own size, scaled to fit
        return;
    }
    request(width, height);
}

void FrameFeed::noteConnection() {
    const bool now = m_client->connected();
    if (now && !m_was_connected) {
        const StreamProfile& p = m_client->client()->profile();
        const ReconnectOptions& o = m_client->options();
        std::fprintf(
            m_log, "navmap-wayland: streaming %s %dx%d %s %s (payload %s) from %s\n", p.name.c_str(), p.width, p.height,
            p.view.c_str(), pixelFormatName(p.format), streamPayloadName(m_client->client()->payload()),
            o.unix_path.empty() ? (o.tcp_host + ":" + std::to_string(o.tcp_port)).c_str() : o.unix_path.c_str());
        m_logged_error.clear();
        const std::string& why = m_client->client()->fallbackReason();
        if (!why.empty() && !m_dmabuf_fallback_logged) {
            std::fprintf(m_log, "navmap-wayland: no dma-buf frames (%s); using wl_shm buffers\n", why.c_str());
            m_dmabuf_fallback_logged = true;  // once: every reconnect asks again and gets the same answer
        }
    }
    if (!now && !m_client->lastError().empty() && m_client->lastError() != m_logged_error) {
        m_logged_error = m_client->lastError();
        std::fprintf(
            m_log, "navmap-wayland: navmapd: %s; %s\n", m_logged_error.c_str(),
            m_was_connected ? "showing the last frame, reconnecting with backoff" : "trying again with backoff");
    }
    m_was_connected = now;
    std::fflush(m_log);
}

bool FrameFeed::next(FeedFrame& out, std::chrono::milliseconds timeout) {
    release();
    HeldFrame held;
    const bool got = m_base.request.hold ? m_client->nextHeld(held, timeout) : m_client->next(m_copy, timeout);
    const StreamProfile& base = m_base.request.profile;
    if (!got && !m_client->connected() && isRefusal(m_client->lastError()) &&
        requestedSize() != std::pair{base.width, base.height}) {
        const auto [w, h] = requestedSize();
        m_refused.insert({w, h});
        std::fprintf(m_log,
                     "navmap-wayland: navmapd does not render %s at %dx%d (%s); showing its %dx%d frames "
                     "scaled to fit the window\n",
                     base.name.c_str(), w, h, m_client->lastError().c_str(), base.width, base.height);
        request(base.width, base.height);
        return false;
    }
    noteConnection();
    if (!got) return false;
    if (m_base.request.hold) {
        out.header = held.header;
        out.pixels = held.pixels;
        m_holding = true;
    } else {
        out.header = m_copy.header;
        out.pixels = m_copy.pixels.data();
    }
    return true;
}

void FrameFeed::release() {
    if (m_holding) {
        m_client->release();
        m_holding = false;
    }
}

}  // namespace navmap::ipc::wayland
