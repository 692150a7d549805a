// SPDX-License-Identifier: Apache-2.0
#pragma once
// The HTTP/1.x request head FrameServer accepts (GET only, no body). Never throws.

#include <cstddef>
#include <map>
#include <string>
#include <string_view>

#include "navmap/ipc/net/result.h"

namespace navmap::ipc {

inline constexpr std::size_t kMaxHttpRequestBytes = 8192;

struct StreamHttpRequest {
    std::string method;
    std::string path;                          ///< without the query, percent-decoding not applied
    std::map<std::string, std::string> query;  ///< "a=1&b=2"
    std::string version;                       ///< "HTTP/1.0" or "HTTP/1.1"
    /// Header fields by lower-case name, values without surrounding blanks. A repeated Host or
    /// Authorization is an error (a proxy and the server must not read different ones); other
    /// repeats keep the last.
    std::map<std::string, std::string> headers;
};

/// Parses a request head ending in "\r\n\r\n" (or "\n\n"). Errors name the problem
/// ("bad request line", "unsupported version 'HTTP/9'", ...).
Result<StreamHttpRequest> parseStreamHttpRequest(std::string_view head);

}  // namespace navmap::ipc
