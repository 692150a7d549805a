// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: DBC parser and the signal codec on whatever it parsed.
// Built with -DNAVMAP_WITH_FUZZ=ON (clang); ipc_unit_tests also compiles it (NAVMAP_FUZZ_NO_MAIN)
// and runs navmapFuzzDbc() on a corpus of broken inputs.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "navmap/ipc/can/dbc_database.h"

int navmapFuzzDbc(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    for (const auto mode : {navmap::ipc::DbcDatabase::Mode::Lenient, navmap::ipc::DbcDatabase::Mode::Strict}) {
        auto r = navmap::ipc::DbcDatabase::parse(text, "fuzz.dbc", mode);
        if (!r.ok()) {
            continue;
        }
        std::array<std::uint8_t, 64> payload{};
        for (std::size_t i = 0; i < payload.size(); ++i) {
            payload[i] = static_cast<std::uint8_t>(i * 37U + size);
        }
        for (const auto& m : r.value().messages()) {
            m.decodeAll(std::span(payload.data(), m.size), [](const navmap::ipc::DbcSignal&, double) {});
            std::map<std::string, double, std::less<>> values;
            for (const auto& s : m.signals) {
                values[s.name] = s.minimum;
            }
            (void)m.encode(values);
        }
    }
    return 0;
}

#ifndef NAVMAP_FUZZ_NO_MAIN
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) { return navmapFuzzDbc(data, size); }
#endif
