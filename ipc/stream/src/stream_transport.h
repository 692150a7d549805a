// SPDX-License-Identifier: Apache-2.0
#pragma once
// StreamTransport: one listening socket of the frame server and the protocol its connections
// speak. The base accepts (non-blocking, CLOEXEC), counts, asks the subclass and the ClientHub
// whether the peer may take a slot, answers refusals at once and hands admitted connections to
// the hub. Subclasses say what goes on the wire: ShmTransport (Unix socket: shared-memory rings
// and socket payloads), TcpTransport (frame stream over TCP), HttpTransport (viewer, status,
// metrics, MJPEG). Server thread. Private to ipc/stream.

#include <sys/socket.h>
#include <sys/types.h>

#include <optional>
#include <string>

#include "client_hub.h"
#include "navmap/ipc/net/result.h"
#include "navmap/ipc/net/unique_fd.h"
#include "stream_conn.h"

namespace navmap::ipc::net {
class PollLoop;
}  // namespace navmap::ipc::net

namespace navmap::ipc::stream_detail {

using net::PollLoop;

class StreamTransport {
public:
    StreamTransport(Via via, ClientHub& hub);
    virtual ~StreamTransport();
    StreamTransport(const StreamTransport&) = delete;
    StreamTransport& operator=(const StreamTransport&) = delete;

    Via via() const { return m_via; }
    /// Binds and listens when the options ask for this transport (otherwise nothing), and
    /// registers the socket with `loop`. Errors name the call and the object.
    Status listen(PollLoop& loop);
    /// Closes the listening socket (the Unix transport also removes its file).
    virtual void close();

    /// Input arrived for `c` (in c.in) while it is in one of this transport's reading phases.
    virtual void onInput(StreamConn& c) = 0;
    /// Queues the newest frame for `c` (c.pending was set); nothing when there is none yet.
    virtual void sendFrame(StreamConn& c) = 0;
    /// The last words to a connection that did not finish its handshake or request head in time.
    virtual std::string handshakeTimeoutReply(const std::string& why) const;
    /// The last words to a streaming client that got no first frame in time ("" for none).
    virtual std::string firstFrameTimeoutReply(const StreamConn& c, const std::string& text) const;

protected:
    /// Opens the listening socket; an invalid fd when this transport is not configured.
    virtual Result<int> openListener() = 0;
    /// The peer check of this transport (Unix: SO_PEERCRED against the allow list): a refusal,
    /// or nothing with `*uid` set when the peer has one.
    virtual std::optional<Refusal> checkPeer(int fd, std::optional<uid_t>* uid);
    /// The reply a refused connection gets before it is closed.
    virtual std::string refusalReply(const std::string& message) const;
    virtual Phase firstPhase() const { return Phase::Handshake; }
    /// Object named by accept() errors.
    virtual std::string acceptObject() const { return "tcp"; }

    int listenFd() const { return m_listen_fd.get(); }
    ClientHub& m_hub;

private:
    void acceptAll();
    void admit(net::UniqueFd fd, const std::string& address);
    void refuse(net::UniqueFd& fd, const std::string& peer, const Refusal& refusal);
    std::unique_ptr<StreamConn> makeConn(net::UniqueFd fd, const std::string& peer, std::optional<uid_t> uid,
                                         const std::string& address) const;

    Via m_via;
    net::UniqueFd m_listen_fd;
};

/// JSON error line of the frame-stream protocol: {"ok":false,"error":"..."}.
std::string jsonErrorLine(const std::string& message);
/// Control bytes other than tab, CR and LF: no JSON line or HTTP head contains them.
bool hasControlBytes(const std::string& s);
/// What a TCP or HTTP peer is counted by: its IPv4 address ("127.0.0.2", also for an IPv4 peer
/// on an IPv6 socket), or its IPv6 /64 prefix ("2001:db8:1:2::/64"); "" for other families.
std::string peerAddressKey(const sockaddr_storage& ss);

}  // namespace navmap::ipc::stream_detail
