// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/net/socket_access.h"

#include <grp.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "navmap/ipc/net/sys_error.h"

namespace navmap::ipc {

using net::sysError;

Result<PeerCredentials> peerCredentials(int fd, const std::string& object) {
    ucred cred{};
    socklen_t len = sizeof cred;
    if (::getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &cred, &len) != 0) {
        return Error{sysError("getsockopt", object + ", SO_PEERCRED")};
    }
    PeerCredentials p;
    p.uid = cred.uid;
    p.gid = cred.gid;
    p.pid = cred.pid;
    // Supplementary groups as they were at connect() (Linux >= 4.13); a peer with more than fit
    // in the first buffer gets a second try at the size the kernel asks for.
    std::vector<gid_t> groups(64);
    for (int attempt = 0; attempt < 2; ++attempt) {
        socklen_t bytes = static_cast<socklen_t>(groups.size() * sizeof(gid_t));
        if (::getsockopt(fd, SOL_SOCKET, SO_PEERGROUPS, groups.data(), &bytes) == 0) {
            groups.resize(bytes / sizeof(gid_t));
            p.groups = std::move(groups);
            return p;
        }
        if (errno != ERANGE) {
            return Error{sysError("getsockopt", object + ", SO_PEERGROUPS")};
        }
        groups.resize(bytes / sizeof(gid_t) + 1);
    }
    return Error{sysError("getsockopt", object + ", SO_PEERGROUPS")};
}

bool peerAllowed(const PeerAllowList& allow, const PeerCredentials& peer) {
    if (allow.allow_root && peer.uid == 0) {
        return true;
    }
    const bool uid_ok = allow.uids.empty()
                            ? peer.uid == ::geteuid()
                            : std::find(allow.uids.begin(), allow.uids.end(), peer.uid) != allow.uids.end();
    if (uid_ok) {
        return true;
    }
    const auto listed = [&](gid_t g) { return std::find(allow.gids.begin(), allow.gids.end(), g) != allow.gids.end(); };
    return listed(peer.gid) || std::any_of(peer.groups.begin(), peer.groups.end(), listed);
}

std::string peerRefusal(const PeerCredentials& peer, const std::string& path) {
    return "peer uid " + std::to_string(peer.uid) + " (pid " + std::to_string(peer.pid) + ") is not allowed on " + path;
}

Status restrictSocketBeforeBind(int fd, mode_t mode, const std::string& path) {
    if (::fchmod(fd, mode) != 0) {
        return Error{sysError("fchmod", path)};
    }
    return {};
}

Status applySocketFileAccess(const std::string& path, mode_t mode, std::optional<gid_t> group) {
    if (::chmod(path.c_str(), mode) != 0) {
        return Error{sysError("chmod", path)};
    }
    if (group && ::lchown(path.c_str(), static_cast<uid_t>(-1), *group) != 0) {
        return Error{sysError("chown", path + ", group " + std::to_string(*group))};
    }
    return {};
}

Status bindAndListenUnix(int fd, const std::string& path, mode_t mode, std::optional<gid_t> group, int backlog) {
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::string bound = path + ".bind";
    if (bound.size() >= sizeof(addr.sun_path)) bound = path;
    if (bound.size() >= sizeof(addr.sun_path)) {
        return Error{"bind(" + path + "): path too long for a Unix socket"};
    }
    std::memcpy(addr.sun_path, bound.c_str(), bound.size() + 1);
    if (bound != path) ::unlink(bound.c_str());  // a staging file left by a killed server
    if (::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
        return Error{sysError("bind", path)};
    }
    if (auto access = applySocketFileAccess(bound, mode, group); !access) {
        ::unlink(bound.c_str());
        return access;
    }
    if (::listen(fd, backlog) != 0) {
        const std::string err = sysError("listen", path);
        ::unlink(bound.c_str());
        return Error{err};
    }
    if (bound != path && ::rename(bound.c_str(), path.c_str()) != 0) {
        const std::string err = sysError("rename", bound + " -> " + path);
        ::unlink(bound.c_str());
        return Error{err};
    }
    return {};
}

Result<gid_t> resolveGroup(const std::string& name, const std::string& what) {
    if (name.empty()) {
        return Error{what + ": empty group name"};
    }
    if (std::all_of(name.begin(), name.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        if (name.size() > 9) {
            return Error{what + " = \"" + name + "\": gid out of range"};
        }
        return static_cast<gid_t>(std::stoul(name));
    }
    std::vector<char> buf(4096);
    for (;;) {
        struct group g {};
        struct group* found = nullptr;
        const int rc = ::getgrnam_r(name.c_str(), &g, buf.data(), buf.size(), &found);
        if (rc == ERANGE && buf.size() < (std::size_t{1} << 20)) {
            buf.resize(buf.size() * 2);
            continue;
        }
        if (rc != 0) {
            errno = rc;
            return Error{sysError("getgrnam", name) + " (" + what + ")"};
        }
        if (found == nullptr) {
            return Error{what + " = \"" + name + "\": no such group"};
        }
        return found->gr_gid;
    }
}

}  // namespace navmap::ipc
