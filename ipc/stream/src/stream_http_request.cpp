// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/stream/stream_http_request.h"

#include <cctype>

namespace navmap::ipc {
namespace {

bool isToken(std::string_view s) {
    if (s.empty()) {
        return false;
    }
    for (const char c : s) {
        if (c < 'A' || c > 'Z') {
            return false;
        }
    }
    return true;
}

}  // namespace

Result<StreamHttpRequest> parseStreamHttpRequest(std::string_view head) {
    if (head.size() > kMaxHttpRequestBytes) {
        return Error{"request head longer than " + std::to_string(kMaxHttpRequestBytes) + " bytes"};
    }
    const auto eol = head.find('\n');
    if (eol == std::string_view::npos) {
        return Error{"bad request line"};
    }
    std::string_view line = head.substr(0, eol);
    if (!line.empty() && line.back() == '\r') {
        line.remove_suffix(1);
    }
    for (const char c : line) {
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7F) {
            return Error{"bad request line"};
        }
    }
    const auto sp1 = line.find(' ');
    const auto sp2 = sp1 == std::string_view::npos ? sp1 : line.find(' ', sp1 + 1);
    if (sp1 == std::string_view::npos || sp2 == std::string_view::npos ||
        line.find(' ', sp2 + 1) != std::string_view::npos) {
        return Error{"bad request line"};
    }
    StreamHttpRequest req;
    const std::string_view method = line.substr(0, sp1);
    const std::string_view target = line.substr(sp1 + 1, sp2 - sp1 - 1);
    const std::string_view version = line.substr(sp2 + 1);
    if (!isToken(method)) {
        return Error{"bad method"};
    }
    if (target.empty() || target.front() != '/') {
        return Error{"bad request target"};
    }
    if (version != "HTTP/1.0" && version != "HTTP/1.1") {
        return Error{"unsupported version '" + std::string(version.substr(0, 16)) + "'"};
    }
    req.method = std::string(method);
    req.version = std::string(version);
    const auto q = target.find('?');
    req.path = std::string(target.substr(0, q));
    if (q != std::string_view::npos) {
        std::string_view rest = target.substr(q + 1);
        while (!rest.empty()) {
            const auto amp = rest.find('&');
            const std::string_view kv = rest.substr(0, amp);
            const auto eq = kv.find('=');
            if (!kv.empty()) {
                req.query[std::string(kv.substr(0, eq))] =
                    eq == std::string_view::npos ? "" : std::string(kv.substr(eq + 1));
            }
            if (amp == std::string_view::npos) {
                break;
            }
            rest.remove_prefix(amp + 1);
        }
    }
    // Header lines: "Name: value"; the server reads Host and Authorization.
    std::string_view rest = head.substr(eol + 1);
    while (!rest.empty()) {
        const auto e = rest.find('\n');
        std::string_view h = rest.substr(0, e);
        if (!h.empty() && h.back() == '\r') {
            h.remove_suffix(1);
        }
        if (h.empty()) {
            break;
        }
        const auto colon = h.find(':');
        if (colon == std::string_view::npos || colon == 0) {
            return Error{"bad header line"};
        }
        std::string name(h.substr(0, colon));
        for (char& c : name) {
            if (c == ' ' || c == '\t') {
                return Error{"bad header line"};  // no blank before the colon (RFC 9112 5.1)
            }
            c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        }
        std::string_view value = h.substr(colon + 1);
        while (!value.empty() && (value.front() == ' ' || value.front() == '\t')) {
            value.remove_prefix(1);
        }
        while (!value.empty() && (value.back() == ' ' || value.back() == '\t')) {
            value.remove_suffix(1);
        }
        if ((name == "host" || name == "authorization") && req.headers.count(name) != 0) {
            return Error{"repeated " + name + " header"};
        }
        req.headers[name] = std::string(value);
        if (e == std::string_view::npos) {
            break;
        }
        rest.remove_prefix(e + 1);
    }
    return req;
}

}  // namespace navmap::ipc
