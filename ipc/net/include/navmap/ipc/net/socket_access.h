// SPDX-License-Identifier: Apache-2.0
#pragma once
// Who may use a local Unix socket of the daemon (control socket, frame socket): the socket file's
// mode and group, applied before listen() so no peer can connect under wider permissions, and
// the peer's credentials (SO_PEERCRED, SO_PEERGROUPS) checked against an allow list on accept.

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

#include "navmap/ipc/net/result.h"

namespace navmap::ipc {

/// Who may connect. A peer is allowed when its uid is listed (an empty list means the server's
/// own effective uid), when it is root and `allow_root` is set, or when its primary gid or one of
/// its supplementary groups is listed in `gids`.
struct PeerAllowList {
    std::vector<uid_t> uids;
    std::vector<gid_t> gids;
    bool allow_root = true;
};

/// The credentials of a connected Unix-socket peer, as the kernel recorded them at connect().
struct PeerCredentials {
    uid_t uid = 0;
    gid_t gid = 0;
    pid_t pid = 0;
    std::vector<gid_t> groups;  ///< supplementary groups (SO_PEERGROUPS)
};

/// Reads SO_PEERCRED and SO_PEERGROUPS of `fd`. `object` names the socket in errors:
/// "getsockopt(/run/navmap/frames.sock, SO_PEERCRED): Bad file descriptor".
Result<PeerCredentials> peerCredentials(int fd, const std::string& object);

/// True when `peer` may connect under `allow`.
bool peerAllowed(const PeerAllowList& allow, const PeerCredentials& peer);

/// The refusal every server sends: "peer uid 65534 (pid 4711) is not allowed on /run/navmap/frames.sock".
std::string peerRefusal(const PeerCredentials& peer, const std::string& path);

/// Before bind(): makes the socket's inode `mode`, so the file bind() creates is never wider than
/// `mode` whatever the umask (Linux creates it with the socket inode's mode minus the umask).
Status restrictSocketBeforeBind(int fd, mode_t mode, const std::string& path);

/// After bind(), before listen() (no peer can connect yet): sets the file's mode exactly (a
/// restrictive umask may have narrowed it) and its group when one is given. Errors name the
/// call, the path and the group: "chown(/run/navmap/frames.sock, group 107): Operation not permitted".
Status applySocketFileAccess(const std::string& path, mode_t mode, std::optional<gid_t> group);

/// bind(), applySocketFileAccess() and listen(`backlog`) for the Unix socket `fd` (after
/// restrictSocketBeforeBind), so that the file at `path` appears only once it listens: bound under
/// a staging name beside it (`path` + ".bind") and renamed into place. A client that waits for the
/// file to appear (a display process at start-up) never meets one that refuses connections. Where
/// the staging name would not fit a socket address, binds at `path` itself. The caller has removed
/// a stale file at `path`; nothing is left behind on an error.
Status bindAndListenUnix(int fd, const std::string& path, mode_t mode, std::optional<gid_t> group, int backlog);

/// A group by name or number ("navmap", "107"): its gid, or an Error naming `what` and the group.
Result<gid_t> resolveGroup(const std::string& group, const std::string& what);

}  // namespace navmap::ipc
