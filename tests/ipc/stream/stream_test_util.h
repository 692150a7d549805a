// SPDX-License-Identifier: Apache-2.0
#pragma once
// Helpers for the frame-stream tests and benchmarks: raw sockets, a frame publisher thread,
// an MJPEG-over-HTTP reader, fd and memory counters.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "navmap/ipc/stream/frame_server.h"

#include "foreign_user.h"
#include "open_fds.h"

namespace navmap::stream_test {

using navmap::test::countOpenFds;

long rssKb();
std::string uniqueSocketPath(const std::string& tag);

/// RGBA frame whose every pixel encodes `seq` (R,G,B = seq bytes 0..2, A = 255).
std::vector<std::uint8_t> sequencePattern(int width, int height, std::uint64_t seq);
/// Whether `pixels` are one whole frame of a Publisher's: `bytes` long, every pixel the same
/// (a torn frame mixes two).
bool wholePublisherFrame(const std::vector<std::uint8_t>& pixels, std::size_t bytes);

/// Publishes frames of `view` at `fps` (0 = as fast as possible) on its own thread, like a render loop.
class Publisher {
public:
    Publisher(ipc::FrameServer& server, std::string view, int width, int height, int fps);
    ~Publisher();
    void stop();
    std::uint64_t published() const { return m_count.load(); }

private:
    std::atomic<bool> m_run{true};
    std::atomic<std::uint64_t> m_count{0};
    std::thread m_thread;
};

int connectUnixRaw(const std::string& path);
int connectTcpRaw(int port);
bool sendAllRaw(int fd, const std::string& data);
/// Reads until the peer closes or `timeout` passes.
std::string readUntilClose(int fd, std::chrono::milliseconds timeout);
/// One HTTP request over a fresh connection; returns the whole response.
std::string httpExchange(int port, const std::string& request,
                         std::chrono::milliseconds timeout = std::chrono::seconds(5));
/// A TCP port on 127.0.0.1 nobody listens on now (bound and released; a daemon binds it next).
int freeTcpPort();
/// "GET <target> HTTP/1.1" with the Host header this server accepts (127.0.0.1:<port>) and
/// `headers` ("Name: value\r\n" lines), over a fresh connection.
std::string httpGet(int port, const std::string& target, const std::string& headers = "");

/// A shm handshake done by hand, keeping the ring's descriptor as received (SCM_RIGHTS).
struct RawShmClient {
    int fd = -1;        ///< the socket
    int ring_fd = -1;   ///< the memfd from the reply, -1 when none came
    std::string reply;  ///< the reply line without '\n'
    ~RawShmClient();
};
std::unique_ptr<RawShmClient> rawShmHandshake(const std::string& path, const std::string& line);

/// Opens `count` connections to the Unix socket at `path`, sends `line` on each, and returns each
/// one's first reply line (or "connect: <error>"), one per line. The connections stay open until
/// the process ends: for a child process standing in for a hostile client (ForeignProcess).
std::string holdConnections(const std::string& path, const std::string& line, int count);

/// Reads multipart/x-mixed-replace JPEG parts from /stream.mjpg.
class MjpegReader {
public:
    MjpegReader(int port, const std::string& target);
    ~MjpegReader();
    bool ok() const { return m_fd >= 0 && m_head_ok; }
    /// Next JPEG (empty on timeout/close). `sequence` from X-Navmap-Sequence.
    std::vector<std::uint8_t> next(std::chrono::milliseconds timeout, std::uint64_t* sequence = nullptr);
    const std::string& responseHead() const { return m_head; }

private:
    bool fill(std::chrono::steady_clock::time_point deadline);
    int m_fd = -1;
    bool m_head_ok = false;
    std::string m_head;
    std::string m_buf;
};

/// Decodes a JPEG to RGBA with libturbojpeg; false on error.
bool decodeJpeg(const std::vector<std::uint8_t>& jpeg, int* width, int* height, std::vector<std::uint8_t>* rgba);

}  // namespace navmap::stream_test
