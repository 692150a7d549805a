// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: everything a stream client can send or a server can answer before pixels:
// the JSON handshake line, the HTTP request head, and the 80-byte frame header with the error or
// status text after it.
// Built with -DNAVMAP_WITH_FUZZ=ON (clang); stream_unit_tests compiles it too (NAVMAP_FUZZ_NO_MAIN)
// and runs navmapFuzzStreamHandshake() on a corpus of broken inputs.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "navmap/ipc/frame_header.h"
#include "navmap/ipc/stream_http_request.h"
#include "navmap/ipc/stream_profile.h"

int navmapFuzzStreamHandshake(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    auto req = navmap::ipc::parseStreamRequest(text);
    if (req.ok()) {
        // Whatever was accepted must format and parse back to the same request.
        auto again = navmap::ipc::parseStreamRequest(navmap::ipc::formatStreamRequest(req.value()));
        const auto& a = req.value().profile;
        if (!again.ok() || again.value().profile.width != a.width || again.value().profile.height != a.height ||
            again.value().profile.fps != a.fps || again.value().profile.view != a.view ||
            again.value().profile.format != a.format || again.value().profile.name != a.name ||
            again.value().payload != req.value().payload) {
            __builtin_trap();
        }
    }
    (void)navmap::ipc::parseStreamHttpRequest(text);
    auto header = navmap::ipc::decodeFrameHeader(data, size);
    if (header.ok()) {
        const auto bytes = navmap::ipc::encodeFrameHeader(header.value());
        auto again = navmap::ipc::decodeFrameHeader(bytes.data(), bytes.size());
        if (!again.ok() || again.value().sequence != header.value().sequence ||
            again.value().payload_bytes != header.value().payload_bytes) {
            __builtin_trap();
        }
        const auto kind = header.value().kind;
        if (kind == navmap::ipc::FrameKind::Error || kind == navmap::ipc::FrameKind::Status) {
            const std::size_t have = size - navmap::ipc::kFrameHeaderBytes;
            const std::size_t n = have < header.value().payload_bytes ? have : header.value().payload_bytes;
            (void)navmap::ipc::validateTextPayload(kind, data + navmap::ipc::kFrameHeaderBytes, n);
        }
    }
    return 0;
}

#ifndef NAVMAP_FUZZ_NO_MAIN
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return navmapFuzzStreamHandshake(data, size);
}
#endif
