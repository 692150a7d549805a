// SPDX-License-Identifier: Apache-2.0
#pragma once
// ClientHub: the bookkeeping every transport shares. It owns the connections (registered with the
// poll loop as they are accepted), admits them against the per-transport, per-uid and per-address caps,
// queues and flushes their bytes, offers each streaming client the newest frame within its frame
// rate (a busy client skips frames, counted as dropped), hands statuses to clients still waiting
// for a first frame, closes the dead and keeps the rings, the publish set and the counters in
// step. What goes on the wire is the transports' business (StreamTransport). Server thread.
// Private to ipc/stream.

#include <sys/types.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "frame_encoder.h"
#include "navmap/ipc/stream/frame_server.h"
#include "stream_conn.h"
#include "stream_stats.h"
#include "stream_timeouts.h"

namespace navmap::ipc::net {
class PollLoop;
}  // namespace navmap::ipc::net

namespace navmap::ipc::stream_detail {

using net::PollLoop;
class RingSet;
class StreamTransport;

/// Why a connection is refused at accept: the counter it goes to and the text the peer gets.
struct Refusal {
    StatsCounter counter = nullptr;
    std::string message;
};

/// A status from the render thread on its way to the server thread: header and text, ready to queue.
struct PendingStatus {
    std::string key;  // what publish() names: the profile
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    std::shared_ptr<const std::string> bytes;
};

class ClientHub {
public:
    ClientHub(const FrameServerOptions& options, StreamStats& stats, RingSet& rings, PollLoop& loop,
              FrameEncoder& encoder);

    void setTransport(StreamTransport& transport);
    const FrameServerOptions& options() const { return m_options; }
    StreamStats& stats() { return m_stats; }
    RingSet& rings() { return m_rings; }
    const FrameEncoder& encoder() const { return m_encoder; }

    /// The transport, uid and address caps: a refusal when `via` (or `uid`, or `address` on
    /// this transport) has no free slot. An empty `address` is not counted.
    std::optional<Refusal> checkCaps(Via via, std::optional<uid_t> uid, const std::string& address) const;
    /// Takes an admitted connection and polls it from the next round on.
    void add(std::unique_ptr<StreamConn> conn);

    void queue(StreamConn& c, const void* data, std::size_t n) { c.queue(data, n); }
    /// Sends what the socket takes; then a half-close when the reply was the last word, or the
    /// frame that waited for the socket.
    void flush(StreamConn& c);
    /// Sends `bytes`, then half-closes and reads until the peer closes (Draining).
    void finishWith(StreamConn& c, const std::string& bytes);

    /// A new frame for `c` (rate cap per client, with 25% slack for render-time jitter).
    void offerIfNew(StreamConn& c, Clock::time_point now);
    /// A transport queued frame `seq` for `c`: counted and flushed.
    void frameSent(StreamConn& c, std::uint64_t seq);

    /// How long the loop may sleep: 20 ms (stall checks), less when a rate-capped frame falls due.
    std::chrono::milliseconds nextWait() const;
    /// After each poll round, in this order:
    void deliverStatuses(const std::vector<PendingStatus>& statuses);
    void deliverNewFrames();
    void checkTimeouts();
    void reap();

    /// The publish set, active profiles and client counters after connections or rings changed.
    void refreshRings();
    /// Closes every connection (stop()).
    void clear();

private:
    StreamTransport& transport(const StreamConn& c) const;
    void onEvents(StreamConn& c, short revents);
    void onReadable(StreamConn& c);
    void offer(StreamConn& c, Clock::time_point now);
    std::uint64_t available(const StreamConn& c) const;
    void requestEncodes();
    void deliverStatus(const PendingStatus& st, Clock::time_point now, std::uint64_t* sent);
    void recountFps();
    void countClients(FrameServerStats& s) const;

    const FrameServerOptions& m_options;
    StreamStats& m_stats;
    RingSet& m_rings;
    PollLoop& m_loop;
    FrameEncoder& m_encoder;
    StreamTimeouts m_timeouts;
    std::array<StreamTransport*, 3> m_transports{};  // by Via
    std::vector<std::unique_ptr<StreamConn>> m_conns;
};

}  // namespace navmap::ipc::stream_detail
