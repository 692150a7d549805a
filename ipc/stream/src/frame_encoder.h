// SPDX-License-Identifier: Apache-2.0
#pragma once
// FrameEncoder: zlib and JPEG encoding of ring frames on a worker thread of its own, so that a
// slow encode (zlib of 1280x720 takes tens of milliseconds on a small core) never delays the frame
// server's I/O thread and with it the shared-memory clients. Private to ipc/stream.
//
// The server thread asks for "the frame `seq` of `ring`, as zlib / as JPEG"; a request that was
// not started yet is replaced by a newer one (the newest frame wins, as for the clients). Each
// frame is encoded once per format and ring, for all clients of that ring. Finished results are
// collected by the server thread with takeResults(); `wake` is called after each one.

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "navmap/ipc/client/frame_format.h"
#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/client/frame_ring.h"
#include "navmap/ipc/net/result.h"

namespace navmap::ipc::stream_detail {

enum class EncodeKind { Zlib, Jpeg };

/// One encoded frame: the header read from the ring and the compressed bytes. Immutable once
/// handed out (shared by every client that sends it).
struct EncodedFrame {
    std::uint64_t sequence = 0;
    FrameHeader header;
    std::vector<std::uint8_t> bytes;
};

struct EncoderStats {
    std::uint64_t encoded = 0;   ///< frames encoded
    std::uint64_t replaced = 0;  ///< requests superseded by a newer frame before they started
    std::uint64_t failed = 0;    ///< frame overwritten before it could be read, or encoder error
    double zlib_ms_last = 0, zlib_ms_max = 0, jpeg_ms_last = 0, jpeg_ms_max = 0;
    std::string last_error;
};

class FrameEncoder {
public:
    FrameEncoder(int jpeg_quality, std::function<void()> wake);
    ~FrameEncoder();  ///< stops the worker
    FrameEncoder(const FrameEncoder&) = delete;
    FrameEncoder& operator=(const FrameEncoder&) = delete;

    /// Starts the worker; fails when libturbojpeg cannot make a compressor.
    Status start();
    void stop();

    /// Server thread: encode frame `sequence` of `ring` as `kind` (replaces a request for the same
    /// ring and kind that has not started). The ring stays alive until the job is done.
    void request(const std::shared_ptr<FrameRing>& ring, std::uint64_t sequence, EncodeKind kind);

    struct Result {
        const FrameRing* ring = nullptr;
        EncodeKind kind = EncodeKind::Zlib;
        std::shared_ptr<const EncodedFrame> frame;
    };
    /// Server thread: the results finished since the last call, oldest first.
    std::vector<Result> takeResults();
    [[nodiscard]] EncoderStats stats() const;

private:
    struct Job {
        std::shared_ptr<FrameRing> ring;
        std::uint64_t sequence = 0;
    };
    using Key = std::pair<const FrameRing*, EncodeKind>;

    void run();
    std::shared_ptr<const EncodedFrame> encode(const FrameRing& ring, std::uint64_t sequence, EncodeKind kind);

    const int m_jpeg_quality;
    std::function<void()> m_wake;
    void* m_tj = nullptr;  // tjhandle (kept out of this header)
    std::thread m_thread;
    mutable std::mutex m_mutex;
    std::condition_variable m_cv;
    bool m_running = false;
    std::map<Key, Job> m_jobs;      // waiting, at most one per ring and kind
    std::optional<Key> m_served;    // the key of the last job started (round robin)
    std::vector<Result> m_results;  // finished, not taken yet
    EncoderStats m_stats;
    // Worker-only scratch buffers (reused: no allocation per frame once warm).
    std::vector<std::uint8_t> m_pixels;
    std::vector<std::uint8_t> m_rgba;
};

}  // namespace navmap::ipc::stream_detail
