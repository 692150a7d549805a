// SPDX-License-Identifier: Apache-2.0
#pragma once
// ControlServer: the daemon's control socket (Unix stream socket, JSON lines, docs/ipc.md).
// Non-blocking, on a net::PollLoop (the frame server's loop too): step it from the daemon loop
// with pollOnce(), or let it run its own thread with start(). Valid commands go to a ControlHandler on that thread;
// malformed lines get an error reply and change nothing; an over-long line or an idle connection is disconnected with a
// reason. Who may connect: the socket file mode and SO_PEERCRED (allowed uids/gids). How many: a cap in all, per peer
// uid and on subscribers per uid; privileged peers (root, the daemon's own uid, `privileged_uids`: the HMI) take the
// slot of an unprivileged one when all are taken, so no other user can lock the HMI out (docs/ipc.md "Slots and
// priority").

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "navmap/ipc/control/control_command.h"
#include "navmap/ipc/control/control_handler.h"
#include "navmap/ipc/net/poll_loop.h"
#include "navmap/ipc/net/result.h"
#include "navmap/ipc/net/unique_fd.h"

namespace navmap::ipc {

struct ControlServerConfig {
    std::string socket_path = "/run/navmap/control.sock";
    mode_t socket_mode = 0660;          ///< the socket file's mode whatever the umask (set before listen())
    std::optional<gid_t> socket_group;  ///< the socket file's group (chown before listen()); its members may connect
    /// Peers whose uid is listed may connect; empty = the daemon's own effective uid. A peer
    /// whose primary gid or a supplementary group (SO_PEERGROUPS) is in allowed_gids is allowed too.
    std::vector<uid_t> allowed_uids;
    std::vector<gid_t> allowed_gids;
    bool allow_root = true;        ///< uid 0 may always connect
    std::size_t max_clients = 16;  ///< further connections get an error line and are closed
    /// Connections of one unprivileged peer uid; one more gets an error line and is closed.
    std::size_t max_clients_per_uid = 8;
    /// Connections of one unprivileged peer uid that hold a subscription; a further `subscribe`
    /// gets an error reply and leaves that connection a plain client (the idle timeout applies).
    std::size_t max_subscribers_per_uid = 4;
    /// Peers with priority besides root and the daemon's own effective uid (the HMI's uid when it
    /// runs as another user). When every slot is taken, a privileged peer takes the slot of the
    /// unprivileged connection that has been silent longest; that one gets an error line and is
    /// closed. Only when privileged peers hold every slot is a privileged peer refused.
    std::vector<uid_t> privileged_uids;
    std::size_t max_output_bytes = std::size_t{4} << 20;  ///< a client not reading past this is dropped
    /// A connection that sends no byte and takes no byte of its output for this long gets an
    /// error line and is closed, so silent peers cannot hold the max_clients slots. A subscriber
    /// that has read everything it was sent is waiting for events, not idle. Any connection that
    /// leaves bytes it was sent unread (in the server's buffer or the socket's) for this long is
    /// stalled and closed the same way. Zero: never.
    std::chrono::milliseconds idle_timeout{std::chrono::seconds(30)};
    ControlLimits limits;
};

/// Counters since start (read from any thread).
struct ControlServerStats {
    std::uint64_t connections = 0;          ///< accepted and allowed
    std::uint64_t refused_peer = 0;         ///< refused by SO_PEERCRED
    std::uint64_t refused_full = 0;         ///< refused because max_clients were connected
    std::uint64_t refused_uid_full = 0;     ///< refused because its uid had max_clients_per_uid
    std::uint64_t refused_subscribers = 0;  ///< subscribe refused: its uid had max_subscribers_per_uid
    std::uint64_t evictions = 0;            ///< unprivileged connections closed to seat a privileged peer
    std::uint64_t lines = 0;                ///< request lines received
    std::uint64_t commands = 0;             ///< lines applied successfully
    std::uint64_t errors = 0;               ///< lines answered with an error
    std::uint64_t overlong_disconnects = 0;
    std::uint64_t slow_disconnects = 0;  ///< output buffer over max_output_bytes
    std::uint64_t idle_disconnects = 0;  ///< closed after idle_timeout without traffic, or stalled
    std::uint64_t events = 0;            ///< event lines queued to subscribers
    std::uint64_t clients = 0;           ///< connected now
};

class ControlServer {
public:
    /// Creates the socket: refuses a path that is in use by a live server, replaces a stale
    /// socket file, binds, applies the mode, listens. Errors name the call and the path:
    /// `bind(/run/navmap/control.sock): Permission denied`.
    static Result<std::unique_ptr<ControlServer>> create(ControlServerConfig config, ControlHandler& handler);
    /// Stops the thread, closes every client and removes the socket file. Never throws.
    ~ControlServer();
    ControlServer(const ControlServer&) = delete;
    ControlServer& operator=(const ControlServer&) = delete;

    /// Waits up to `timeout` for socket activity or published events and handles all of it.
    /// Call from one thread only (and not while start() runs). Fails only if poll() fails.
    Status pollOnce(std::chrono::milliseconds timeout);
    /// Runs pollOnce() on an own thread until stop() or destruction.
    Status start();
    void stop() noexcept;

    /// Queues an event for the subscribers of its kind; any thread, never blocks on a client.
    void publish(const ControlEvent& event);

    [[nodiscard]] ControlServerStats stats() const;
    [[nodiscard]] const std::string& path() const { return m_config.socket_path; }

private:
    struct Client;
    ControlServer(ControlServerConfig config, ControlHandler& handler);
    void acceptClients();
    void watch(Client& c);
    void readClient(Client& c);
    void handleLine(Client& c, std::string_view line);
    void queue(Client& c, const std::string& line);
    void flush(Client& c);
    void deliverEvents();
    void closeIdle(std::chrono::steady_clock::time_point now);
    void removeDead();
    [[nodiscard]] bool idle(Client& c, std::chrono::steady_clock::time_point now) const;
    [[nodiscard]] std::chrono::steady_clock::time_point idleDeadline(const Client& c) const;
    [[nodiscard]] bool privileged(uid_t uid) const;
    [[nodiscard]] std::string admit(Client& c);
    [[nodiscard]] std::size_t countUid(uid_t uid, bool subscribers_only) const;
    void wake() noexcept;

    ControlServerConfig m_config;
    ControlHandler& m_handler;
    net::UniqueFd m_listen_fd;
    net::PollLoop m_loop;         // its eventfd wakes it for publish() and stop()
    bool m_accept_ready = false;  // the listening socket was readable in this round
    ino_t m_socket_inode = 0;
    std::vector<std::unique_ptr<Client>> m_clients;

    std::mutex m_event_mutex;
    std::deque<ControlEvent> m_pending_events;

    std::thread m_thread;
    std::atomic<bool> m_stop{false};

    struct Counters {
        std::atomic<std::uint64_t> connections{0}, refused_peer{0}, refused_full{0}, refused_uid_full{0},
            refused_subscribers{0}, evictions{0}, lines{0}, commands{0}, errors{0}, overlong{0}, slow{0}, idle{0},
            events{0}, clients{0};
    };
    Counters m_counters;
};

}  // namespace navmap::ipc
