// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: candump log lines through the reader and the formatter.
// Built with -DNAVMAP_WITH_FUZZ=ON (clang); ipc_unit_tests also compiles it (NAVMAP_FUZZ_NO_MAIN)
// and runs navmapFuzzCandump() on a corpus of broken inputs.

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "navmap/ipc/can/candump_reader.h"

int navmapFuzzCandump(const std::uint8_t* data, std::size_t size) {
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    navmap::ipc::CandumpReader reader("fuzz.log");
    const auto records = reader.readAll(in);
    for (const auto& r : records) {
        // Whatever parsed must format and parse back to the same frame.
        const std::string line = "(0.0) x " + navmap::ipc::formatCandumpPayload(r.frame);
        auto again = navmap::ipc::CandumpReader::parseLine(line);
        if (!again.ok() || again.value().frame.id != r.frame.id || again.value().frame.len != r.frame.len ||
            again.value().frame.flags != r.frame.flags) {
            __builtin_trap();
        }
    }
    return 0;
}

#ifndef NAVMAP_FUZZ_NO_MAIN
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return navmapFuzzCandump(data, size);
}
#endif
