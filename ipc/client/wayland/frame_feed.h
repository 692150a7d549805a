// SPDX-License-Identifier: Apache-2.0
#pragma once
// FrameFeed: navmap-wayland's side of navmapd's frame stream (docs/wayland.md "Size"). A
// ReconnectingClient (libnavmap-client: reconnects with backoff) for one profile, asking for the
// window's size: when the compositor configures a size other than the stream's, the feed
// reconnects asking for that width and height; when navmapd refuses it (a profile it renders at
// one size only), the feed goes back to the profile's own size, says so once in the log, and
// remembers the refusal (the window then scales the frames to fit). Frames of payload shm are
// held in place in the ring until release(): the window copies them once, into its buffer.
// Connection changes and navmapd's errors are logged once each, not per attempt. A request for
// payload dmabuf (--dmabuf) falls back to shm; the refusal is logged once.

#include <chrono>
#include <cstdio>
#include <memory>
#include <set>
#include <string>
#include <utility>

#include "navmap/ipc/client/reconnecting_client.h"

namespace navmap::ipc::wayland {

/// A frame as the window needs it: header and pixels (in the ring, or the feed's copy).
struct FeedFrame {
    FrameHeader header;
    const std::uint8_t* pixels = nullptr;
};

class FrameFeed {
public:
    /// `options.request` is the profile's own request (its size is the fallback); `negotiate`:
    /// ask navmapd for the window's size. Log lines go to `log` with the prefix "navmap-wayland: ".
    FrameFeed(ReconnectOptions options, bool negotiate, std::FILE* log);

    /// The window's size (from the compositor's configure); 0 keeps the current request.
    void wantSize(int width, int height);
    /// Waits up to `timeout` for a frame, connecting as needed. true: `out` holds one until
    /// release() (or the next call).
    bool next(FeedFrame& out, std::chrono::milliseconds timeout);
    /// Gives a held frame back (payload shm); harmless without one.
    void release();

    bool connected() const noexcept { return m_client->connected(); }
    /// The stream socket while connected (poll it for the next frame), else -1.
    int fd() const noexcept { return m_client->client() != nullptr ? m_client->client()->fd() : -1; }
    /// The size asked for now.
    std::pair<int, int> requestedSize() const noexcept;
    /// Sizes navmapd refused (width, height).
    const std::set<std::pair<int, int>>& refusedSizes() const noexcept { return m_refused; }
    const ReconnectingClient& client() const noexcept { return *m_client; }

private:
    void request(int width, int height);
    void noteConnection();

    ReconnectOptions m_base;
    bool m_negotiate;
    std::FILE* m_log;
    std::unique_ptr<ReconnectingClient> m_client;
    std::set<std::pair<int, int>> m_refused;
    bool m_was_connected = false;
    std::string m_logged_error;  ///< the last navmapd error logged (each new one is logged once)
    ReceivedFrame m_copy;        ///< payloads raw/zlib: the frame as read from the socket
    bool m_holding = false;
    bool m_dmabuf_fallback_logged = false;  ///< the dma-buf refusal is logged once
};

}  // namespace navmap::ipc::wayland
