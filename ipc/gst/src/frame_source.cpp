// SPDX-License-Identifier: Apache-2.0
#include "frame_source.h"

#include <zlib.h>

#include <string_view>
#include <utility>

#include "frame_buffer.h"

namespace navmap::ipc::gst {

namespace {

/// Whether a StreamClient error says the server closed the connection without an error header:
/// what navmapd's clients see when it stops (FrameServer::stop closes every connection). On the
/// Unix socket a close with our ack still unread arrives as a reset.
bool closedByServer(std::string_view message) {
    return message.ends_with("connection closed by the server") || message.ends_with("Connection reset by peer");
}

}  // namespace

Result<StreamRequest> makeStreamRequest(const std::string& name, int width, int height, int fps,
                                        const std::string& view, StreamPayload payload) {
    StreamRequest request;
    request.payload = payload;
    request.hold = payload == StreamPayload::Shm;  // copied into the GstBuffer in place
    if (name.empty()) {
        return Error{"property profile: empty"};
    }
    if (auto known = defaultStreamProfile(name)) {
        request.profile = *known;
    } else if (width == 0 || height == 0 || view.empty()) {
        return Error{"profile " + name +
                     " is not cluster, hud or center: it needs the properties width, height and view"};
    }
    request.profile.name = name;
    if (width != 0) request.profile.width = width;
    if (height != 0) request.profile.height = height;
    if (fps >= 0) request.profile.fps = fps;
    if (!view.empty()) request.profile.view = view;
    request.profile.format = PixelFormat::Rgba8;
    // The handshake's own check (names, ranges) on the line the library will send.
    auto checked = parseStreamRequest(formatStreamRequest(request));
    if (!checked) {
        return Error{"profile " + name + ": " + checked.error().message};
    }
    return request;
}

FrameInflater zlibFrameInflater() {
    return [](const std::uint8_t* in, std::size_t in_bytes, std::uint8_t* out, std::size_t out_bytes) {
        uLongf have = out_bytes;
        return uncompress(out, &have, in, in_bytes) == Z_OK && have == out_bytes;
    };
}

FrameSource::FrameSource(SourceSettings settings) : m_settings(std::move(settings)) {}

FrameSource::~FrameSource() = default;

Status FrameSource::open() {
    const auto inflate = m_settings.request.payload == StreamPayload::Zlib ? zlibFrameInflater() : FrameInflater{};
    if (m_settings.reconnect) {
        ReconnectOptions o;
        if (m_settings.port >= 0) {
            o.tcp_host = m_settings.host;
            o.tcp_port = m_settings.port;
        } else {
            o.unix_path = m_settings.socket_path;
        }
        o.request = m_settings.request;
        o.inflate = inflate;
        m_reconnecting = std::make_unique<ReconnectingClient>(std::move(o));
        return {};
    }
    auto c = m_settings.port >= 0 ? StreamClient::connectTcp(m_settings.host, m_settings.port, m_settings.request,
                                                             std::chrono::seconds(5), inflate)
                                  : StreamClient::connectUnix(m_settings.socket_path, m_settings.request,
                                                              std::chrono::seconds(5), inflate);
    if (!c) {
        return Error{c.error().message};
    }
    m_client = std::move(c).value();
    ++m_connects;
    return {};
}

const StreamProfile& FrameSource::profile() const noexcept {
    if (m_client) {
        return m_client->profile();
    }
    if (m_reconnecting && m_reconnecting->client() != nullptr) {
        return m_reconnecting->client()->profile();
    }
    return m_settings.request.profile;
}

std::uint64_t FrameSource::connects() const noexcept {
    return m_reconnecting ? m_reconnecting->reconnectStats().connects : m_connects;
}

std::string FrameSource::lastError() const { return m_reconnecting ? m_reconnecting->lastError() : std::string{}; }

Result<NextFrame> FrameSource::next(std::chrono::milliseconds timeout, GstBuffer** buffer, FrameHeader* header) {
    *buffer = nullptr;
    if (m_reconnecting) {
        return nextReconnecting(timeout, buffer, header);
    }
    if (!m_client || m_ended) {
        return NextFrame::Ended;
    }
    return nextOnce(timeout, buffer, header);
}

Result<NextFrame> FrameSource::nextOnce(std::chrono::milliseconds timeout, GstBuffer** buffer, FrameHeader* header) {
    HeldFrame held;
    const bool hold = m_settings.request.hold;
    auto r = hold ? m_client->nextHeld(held, timeout) : m_client->next(m_copy, timeout);
    if (!r) {
        if (closedByServer(r.error().message)) {
            m_ended = true;
            return NextFrame::Ended;
        }
        return Error{r.error().message};
    }
    if (!r.value()) {
        return NextFrame::Timeout;
    }
    *header = hold ? held.header : m_copy.header;
    const auto& meta = hold ? held.meta : m_copy.meta;
    *buffer = makeFrameBuffer(*header, hold ? held.pixels : m_copy.pixels.data(), meta ? &*meta : nullptr);
    if (hold) {
        auto released = m_client->release();
        if (!released) {
            // The server is gone after we were told of the frame: nobody writes the ring any more,
            // so the copy is whole; the next call reports the end.
            m_ended = true;
        } else if (!released.value()) {
            gst_buffer_unref(*buffer);  // overwritten while we copied: not a frame the server made
            *buffer = nullptr;
            return NextFrame::Timeout;
        }
    }
    if (*buffer == nullptr) {
        return Error{"frame " + std::to_string(header->sequence) + " is not RGBA8"};
    }
    return NextFrame::Frame;
}

Result<NextFrame> FrameSource::nextReconnecting(std::chrono::milliseconds timeout, GstBuffer** buffer,
                                                FrameHeader* header) {
    HeldFrame held;
    const bool hold = m_settings.request.hold;
    const bool got = hold ? m_reconnecting->nextHeld(held, timeout) : m_reconnecting->next(m_copy, timeout);
    if (!got) {
        return NextFrame::Timeout;
    }
    *header = hold ? held.header : m_copy.header;
    const auto& meta = hold ? held.meta : m_copy.meta;
    *buffer = makeFrameBuffer(*header, hold ? held.pixels : m_copy.pixels.data(), meta ? &*meta : nullptr);
    // A held frame comes back false when the server overwrote it (drop the copy) or when the
    // connection ended meanwhile (nobody wrote it: keep it).
    if (hold && !m_reconnecting->release() && m_reconnecting->connected() && *buffer != nullptr) {
        gst_buffer_unref(*buffer);
        *buffer = nullptr;
        return NextFrame::Timeout;
    }
    if (*buffer == nullptr) {
        return Error{"frame " + std::to_string(header->sequence) + " is not RGBA8"};
    }
    return NextFrame::Frame;
}

}  // namespace navmap::ipc::gst
