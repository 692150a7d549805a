// SPDX-License-Identifier: Apache-2.0
#pragma once
// EvilStreamServer: a frame server that lies, for the client side of docs/frame-protocol.md. It
// listens on a Unix socket, reads each client's handshake line, and answers with what an honest
// server would send (the reply line, the ring's descriptor, a notification of frame 1), edited the
// way a test asks: another JSON (a merge patch or a whole line), a regular file or a memfd that
// can shrink instead of the sealed ring, and that file truncated once the client has mapped it.
// No client may die of a signal against it. Test-only; one connection at a time on its own thread.

#include <sys/types.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "navmap/ipc/client/frame_meta.h"

namespace navmap::stream_test {

enum class EvilRing {
    Sealed,         ///< honest: a memfd sealed as FrameRing seals it
    RegularFile,    ///< the ring's bytes in a regular file, truncated to 0 once the client mapped it
    UnsealedMemfd,  ///< the ring's bytes in a memfd without seals, truncated to 0 once the client mapped it
    WritableMemfd,  ///< sealed against shrinking and growing, but not against writes
    ShortMemfd,     ///< sealed, one page shorter than the reply's total_bytes
    None,           ///< no descriptor with the reply
};

const char* evilRingName(EvilRing ring);

struct EvilBehaviour {
    EvilRing ring = EvilRing::Sealed;
    /// RFC 7386 merge patch applied to the honest reply: {"profile":{"width":"x"}}, {"ring":null}.
    std::string patch;
    /// When not empty: sent as the reply line instead (a '\n' is added).
    std::string line;
    /// Frame 1's metadata block, sent after its header when not empty; the header gives its size,
    /// or `meta_bytes` when that is not negative.
    std::vector<std::uint8_t> meta = {};
    int meta_bytes = -1;
    /// Frame 1's validity, in the ring's slot and in its notification.
    ipc::FrameValidity validity = {};
    /// Edits frame 1's 80 encoded header bytes before they are sent (validity lies).
    std::function<void(std::uint8_t*)> edit_header = {};
};

class EvilStreamServer {
public:
    explicit EvilStreamServer(EvilBehaviour behaviour);
    ~EvilStreamServer();
    EvilStreamServer(const EvilStreamServer&) = delete;
    EvilStreamServer& operator=(const EvilStreamServer&) = delete;

    const std::string& path() const { return m_path; }
    /// Handshake lines read so far.
    int handshakes() const { return m_handshakes.load(); }
    /// Rings truncated under a client's mapping (RegularFile, UnsealedMemfd).
    int truncations() const { return m_truncations.load(); }

private:
    void serve();
    void serveOne(int fd);

    EvilBehaviour m_behaviour;
    std::string m_path;
    int m_listen = -1;
    std::atomic<bool> m_run{true};
    std::atomic<int> m_handshakes{0};
    std::atomic<int> m_truncations{0};
    std::thread m_thread;
};

/// How a child process ended, as a test reports it: "exit 0", "killed by signal 7 (Bus error)".
struct ChildOutcome {
    int wait_status = 0;
    std::string how;
    std::string result;  ///< what `work` returned (empty when the child died first)
    bool signalled() const;
};

/// Runs `work` in a forked child (so that a signal kills the child, not the test) and returns
/// how it ended and what it returned. The child exits with 0 after `work`.
ChildOutcome runInChild(const std::function<std::string()>& work);

/// The same for a command line (run by sh, which execs it), its stdout and stderr together as `result`.
ChildOutcome runCommand(const std::string& command);

}  // namespace navmap::stream_test
