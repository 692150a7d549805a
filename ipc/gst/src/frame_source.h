// SPDX-License-Identifier: Apache-2.0
#pragma once
// FrameSource: what navmapsrc receives frames with. One connection to navmapd through
// libnavmap-client: a StreamClient (reconnect off: the first failure or the end of the stream
// ends the source) or a ReconnectingClient (reconnect on: the library's backoff, 100 ms doubling to
// 5 s). Payload shm holds each frame in the ring while it is copied into a GstBuffer (one copy);
// raw and zlib receive a copy first. Waits at most the timeout it is given, so the element can
// stop it between two waits. Not thread-safe: the element's streaming thread owns it.

#include <gst/gst.h>

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include "navmap/ipc/client/reconnecting_client.h"
#include "navmap/ipc/client/stream_client.h"

namespace navmap::ipc::gst {

/// Where and what navmapsrc asks for (its properties, docs/gstreamer.md).
struct SourceSettings {
    std::string socket_path;  ///< Unix frame socket (used when port < 0)
    std::string host;         ///< TCP host (with port >= 0; payload raw or zlib)
    int port = -1;
    StreamRequest request;
    bool reconnect = false;
};

/// The request for profile `name`: a default profile (cluster, hud, center) with the given
/// fields overriding it, or another name that then needs width, height and view. width/height 0,
/// fps < 0 and an empty view keep the profile's. Errors name the property.
Result<StreamRequest> makeStreamRequest(const std::string& name, int width, int height, int fps,
                                        const std::string& view, StreamPayload payload);

/// What one FrameSource::next() got.
enum class NextFrame {
    Frame,    ///< *buffer holds a frame (from makeFrameBuffer), *header its header
    Timeout,  ///< nothing within the timeout (also while reconnecting)
    Ended,    ///< the server closed the stream (navmapd stopped); reconnect off only
};

class FrameSource {
public:
    explicit FrameSource(SourceSettings settings);
    ~FrameSource();
    FrameSource(const FrameSource&) = delete;
    FrameSource& operator=(const FrameSource&) = delete;

    /// Reconnect off: connects and does the handshake now; the Error is the library's
    /// ("connect(/run/navmap/frames.sock): No such file or directory", "handshake refused by
    /// ...: ..."). Reconnect on: connects on the first next().
    Status open();
    /// Waits up to `timeout` for a frame. Error: the stream broke (a protocol error, an error
    /// header from the server, a failed read); reconnect off only.
    Result<NextFrame> next(std::chrono::milliseconds timeout, GstBuffer** buffer, FrameHeader* header);

    /// The profile granted by the newest handshake (the request's before the first one).
    const StreamProfile& profile() const noexcept;
    /// Successful handshakes so far; a new one means a new connection (the element marks DISCONT).
    std::uint64_t connects() const noexcept;
    /// Reconnect on: why the last attempt failed or the last stream ended; empty when none did.
    std::string lastError() const;
    const SourceSettings& settings() const noexcept { return m_settings; }

private:
    Result<NextFrame> nextOnce(std::chrono::milliseconds timeout, GstBuffer** buffer, FrameHeader* header);
    Result<NextFrame> nextReconnecting(std::chrono::milliseconds timeout, GstBuffer** buffer, FrameHeader* header);

    SourceSettings m_settings;
    std::unique_ptr<StreamClient> m_client;              // reconnect off
    std::unique_ptr<ReconnectingClient> m_reconnecting;  // reconnect on
    std::uint64_t m_connects = 0;
    bool m_ended = false;
    ReceivedFrame m_copy;  // raw/zlib: the library's copy, reused
};

/// Inflates a zlib payload with zlib's uncompress() (the client library links no zlib).
FrameInflater zlibFrameInflater();

}  // namespace navmap::ipc::gst
