// SPDX-License-Identifier: Apache-2.0
#include "http_access.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <algorithm>
#include <cctype>
#include <string_view>

#include "stream_stats.h"

namespace navmap::ipc::stream_detail {

namespace {

// Compares a secret in time that depends only on the length of the expected value, not on where
// the first difference is (hand-written: no Debian package in the build has a constant-time
// compare without pulling in a crypto library for these few lines).
bool equalConstantTime(std::string_view given, std::string_view expected) {
    unsigned diff = given.size() == expected.size() ? 0U : 1U;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        const unsigned char g = i < given.size() ? static_cast<unsigned char>(given[i]) : 0;
        diff |= static_cast<unsigned>(g ^ static_cast<unsigned char>(expected[i]));
    }
    return diff == 0;
}

bool isLoopback(const std::string& address) { return address.rfind("127.", 0) == 0 || address == "::1"; }

// "name:port", "[v6]:port" or either without the port; an empty name when malformed.
void splitHost(const std::string& value, std::string* name, std::string* port) {
    if (!value.empty() && value.front() == '[') {
        const auto close = value.find(']');
        if (close != std::string::npos) {
            *name = value.substr(1, close - 1);
            if (close + 1 < value.size() && value[close + 1] == ':') {
                *port = value.substr(close + 2);
            } else if (close + 1 != value.size()) {
                name->clear();
            }
        }
        return;
    }
    const auto colon = value.find(':');
    *name = value.substr(0, colon);
    *port = colon == std::string::npos ? "" : value.substr(colon + 1);
}

}  // namespace

std::string HttpAccess::serverAddress(int fd) const {
    std::string address = m_options.bind_address;
    if (address != "0.0.0.0" && address != "::") {
        return address;
    }
    // Bound to every address: the one this connection came in on.
    sockaddr_storage ss{};
    socklen_t len = sizeof(ss);
    char text[INET6_ADDRSTRLEN] = {};
    if (::getsockname(fd, reinterpret_cast<sockaddr*>(&ss), &len) == 0) {
        if (ss.ss_family == AF_INET) {
            ::inet_ntop(AF_INET, &reinterpret_cast<sockaddr_in*>(&ss)->sin_addr, text, sizeof(text));
        } else if (ss.ss_family == AF_INET6) {
            ::inet_ntop(AF_INET6, &reinterpret_cast<sockaddr_in6*>(&ss)->sin6_addr, text, sizeof(text));
        }
    }
    address = text;
    if (address.rfind("::ffff:", 0) == 0 && address.find('.') != std::string::npos) {
        address.erase(0, 7);  // an IPv4 peer on an IPv6 socket
    }
    return address;
}

std::string HttpAccess::checkHost(int fd, int port, const std::string& value, int* code) const {
    const std::string address = serverAddress(fd);
    std::string name;
    std::string given;
    splitHost(value, &name, &given);
    std::string lower = name;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char ch) { return std::tolower(ch); });
    const bool name_ok = !name.empty() && (name == address || (lower == "localhost" && isLoopback(address)));
    const bool port_ok = given.empty() ? port == 80 : given == std::to_string(port);
    if (name_ok && port_ok) {
        return {};
    }
    m_stats.count(&FrameServerStats::refused_host);
    *code = 421;
    const std::string self =
        (address.find(':') != std::string::npos ? "[" + address + "]" : address) + ":" + std::to_string(port);
    return "Host \"" + value.substr(0, 128) + "\" is not this server (expected " + self +
           (isLoopback(address) ? " or localhost:" + std::to_string(port) : "") + ")\n";
}

std::string HttpAccess::checkToken(const StreamHttpRequest& req, int* code) const {
    std::string_view given;
    bool present = false;
    if (const auto auth = req.headers.find("authorization"); auth != req.headers.end()) {
        std::string_view v = auth->second;
        if (v.size() > 7 && (v.substr(0, 7) == "Bearer " || v.substr(0, 7) == "bearer ")) {
            given = v.substr(7);
            present = true;
        }
    }
    if (const auto q = req.query.find("token"); !present && q != req.query.end()) {
        given = q->second;
        present = true;
    }
    if (present && equalConstantTime(given, m_options.http_token)) {
        return {};
    }
    m_stats.count(&FrameServerStats::refused_token);
    *code = 401;
    return present ? "wrong token\n" : "this server needs a token: Authorization: Bearer <token>, or ?token=<token>\n";
}

std::string HttpAccess::check(int fd, int port, const StreamHttpRequest& req, int* code) const {
    const auto host = req.headers.find("host");
    if (host == req.headers.end() || host->second.empty()) {
        m_stats.count(&FrameServerStats::refused_host);
        *code = 400;
        return "missing Host header\n";
    }
    if (std::string why = checkHost(fd, port, host->second, code); !why.empty()) {
        return why;
    }
    return m_options.http_token.empty() ? std::string() : checkToken(req, code);
}

}  // namespace navmap::ipc::stream_detail
