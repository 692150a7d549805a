// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the control-protocol parser (one JSON line -> typed command or error) and
// the reply writer on whatever it parsed. Built with -DNAVMAP_WITH_FUZZ=ON (clang);
// ipc_control_tests also compiles it (NAVMAP_FUZZ_NO_MAIN) and runs navmapFuzzControl() on a
// corpus of broken lines.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "navmap/ipc/control/control_protocol.h"

int navmapFuzzControl(const std::uint8_t* data, std::size_t size) {
    const std::string_view line(reinterpret_cast<const char*>(data), size);
    navmap::ipc::ControlLimits limits;
    limits.max_route_points = 64;
    const auto r = navmap::ipc::parseControlLine(line, limits);
    // Exactly one of command / error, and a reply can always be written.
    if (r.command.has_value() == !r.error.empty()) {
        std::abort();
    }
    const std::string reply = r.command ? navmap::ipc::controlOkReply(r.command->cmd, r.command->request_id)
                                        : navmap::ipc::controlErrorReply(r.cmd, r.id, r.error);
    if (reply.empty() || reply.find('\n') != std::string::npos) {
        std::abort();
    }
    return 0;
}

#ifndef NAVMAP_FUZZ_NO_MAIN
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return navmapFuzzControl(data, size);
}
#endif
