// SPDX-License-Identifier: Apache-2.0
#pragma once
// RingSet: the frame server's shared-memory rings, one per (profile, size, pixel format) with
// clients, shared by all of them and by every transport, and the set publish() writes into.
// A ring whose memfd went to a client is kept when its last client leaves (idle) and reused by
// the next client of that profile, size and format: a client's mapping outlives its connection
// and its descriptor, so the memory of such a ring is only known to be free when the server ends
// (docs/frame-protocol.md "Ring memory"). Idle rings count against the ceiling; rings that only
// TCP and MJPEG clients used are freed with their last client.
// Each RingEntry caches the newest frame in the forms the socket transports need (raw copy, zlib,
// JPEG), so N clients cost one copy/compression/encode; zlib and JPEG come from the encoder
// thread (FrameEncoder), never from the I/O thread. Server thread, but for publish() (render
// thread). Private to ipc/stream.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "dmabuf_frames.h"
#include "frame_encoder.h"
#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/client/frame_ring.h"
#include "navmap/ipc/client/stream_profile.h"
#include "navmap/ipc/net/result.h"
#include "navmap/ipc/stream/frame_server.h"

namespace navmap::ipc::stream_detail {

class StreamStats;

/// The metadata blocks of a ring's newest frames by sequence, so that the server thread sends a
/// frame's own block after its header, whenever (a zlib encode finishes later). The render thread
/// puts a block before it writes its frame; the mutex guards a pointer swap, never I/O.
class FrameMetaHistory {
public:
    using Block = std::shared_ptr<const std::vector<std::uint8_t>>;
    void put(std::uint64_t sequence, Block block);
    /// The block of frame `sequence`; null when it had none or is older than kFrames frames.
    Block get(std::uint64_t sequence) const;

private:
    static constexpr std::size_t kFrames = 16;
    mutable std::mutex m_mutex;
    std::array<std::pair<std::uint64_t, Block>, kFrames> m_blocks{};
};

struct RingEntry {
    std::string key;  // what publish() names
    std::string view;
    std::shared_ptr<FrameRing> ring;
    std::shared_ptr<FrameMetaHistory> meta = std::make_shared<FrameMetaHistory>();
    std::size_t clients = 0;
    std::size_t dmabuf_clients = 0;  // of `clients`: they take dma-buf frames, not the ring's pixels
    /// The dma-buf frames of this profile and size (docs/frame-protocol.md "dma-buf frames").
    std::shared_ptr<DmabufFrames> dmabuf = std::make_shared<DmabufFrames>();
    /// Its memfd went to a client (SCM_RIGHTS): a mapping of it may live on after every
    /// connection is gone, so the ring stays (idle) and counted until the server ends.
    bool handed_out = false;
    /// Frames below this sequence are from before the ring was idle: not offered to new clients.
    std::uint64_t first_seq = 0;
    int max_fps = 0;
    std::uint64_t raw_seq = 0;
    FrameHeader raw_header;
    std::vector<std::uint8_t> raw;
    std::uint64_t zlib_asked = 0;  // newest sequence handed to the encoder
    std::uint64_t jpeg_asked = 0;
    std::shared_ptr<const EncodedFrame> zlib;  // newest finished encodes
    std::shared_ptr<const EncodedFrame> jpeg;

    /// Copies frame `seq` into `raw`/`raw_header` (once per frame); false when it was overwritten.
    bool fillRaw(std::uint64_t seq);
};

/// fps 0 asks for every frame: for scheduling that is the highest rate there is.
int effectiveFps(int fps);

class RingSet {
public:
    RingSet(const FrameServerOptions& options, StreamStats& stats);

    /// The ring key a requested profile maps to (a rendered profile's name, or the view when the
    /// server has no list); an Error naming what is rendered otherwise (counted).
    Result<std::string> resolve(const StreamProfile& profile);
    /// The ring of `key` at the profile's size and format: the one with clients, or the idle one
    /// (reused, counted in rings_reused), or a new one when it fits under ring_memory_bytes next
    /// to every ring kept, idle ones included (refusal counted; its message starts with "ring
    /// memory:"). The entry counts the new client.
    Result<std::shared_ptr<RingEntry>> attach(const std::string& key, const StreamProfile& profile);
    const std::vector<std::shared_ptr<RingEntry>>& entries() const { return m_rings; }
    /// Frees the rings without clients that no client was given (keeping their pinned-overwrite
    /// counts); the others stay idle.
    void retireUnused();
    /// Rings with clients / without (idle, kept for reuse).
    std::size_t activeCount() const;
    std::size_t idleCount() const;
    std::uint64_t pinnedOverwrites() const;
    std::size_t totalBytes() const;
    /// Finished encodes become their rings' newest encoded frames.
    void takeEncodes(std::vector<FrameEncoder::Result> results);
    /// Profiles with rings now, merged by key and size.
    std::vector<ActiveProfile> activeProfiles() const;
    /// Hands the rings with clients to publish() (the render thread sees them from its next call).
    void updatePublishSet();
    /// Render thread: writes the frame into every ring of `profile`; the number written.
    std::size_t publish(const std::string& profile, const FrameView& frame);
    /// Render thread: the dma-buf frame for the dma-buf clients of `profile` at its size; the
    /// number of rings reached.
    std::size_t publishDmabuf(const std::string& profile, const FrameView& info, const DmabufBuffer& buffer);
    /// Render thread: DmabufFrames::busy() of every ring of `profile` with dma-buf clients.
    std::uint32_t dmabufBusy(const std::string& profile) const;
    void clear();

private:
    struct PublishTarget {
        std::string key;
        std::shared_ptr<FrameRing> ring;
        std::shared_ptr<FrameMetaHistory> meta;
        std::shared_ptr<DmabufFrames> dmabuf;  // null: the ring has no dma-buf clients
        std::uint32_t width = 0, height = 0;
    };
    using PublishSet = std::vector<PublishTarget>;

    std::shared_ptr<RingEntry> find(const std::string& key, const StreamProfile& profile) const;
    Result<std::string> refuseNotRendered(std::string message);
    Status checkMemory(const StreamProfile& profile);

    const FrameServerOptions& m_options;
    StreamStats& m_stats;
    std::vector<std::shared_ptr<RingEntry>> m_rings;  // server thread
    std::uint64_t m_ring_counter = 0;
    std::uint64_t m_retired_pinned_overwrites = 0;  // of rings freed since (server thread)
    mutable std::mutex m_publish_mutex;             // guards the pointer swap only, never I/O
    std::shared_ptr<const PublishSet> m_publish_set = std::make_shared<PublishSet>();
};

}  // namespace navmap::ipc::stream_detail
