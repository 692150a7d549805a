// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: navmap-sim's --from/--to parser ("lat,lon" or a place name) and the name
// normalization. Built with -DNAVMAP_WITH_FUZZ=ON (clang); sim_unit_tests also compiles it
// (NAVMAP_FUZZ_NO_MAIN) and runs navmapFuzzSimPlace() on a corpus of broken inputs.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "navmap/sim/place_resolver.h"

int navmapFuzzSimPlace(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    static const navmap::sim::PlaceResolver kResolver;  // built-in table only: no store needed
    (void)navmap::sim::PlaceResolver::normalize(text);
    (void)navmap::sim::PlaceResolver::parseLatLon(text);
    auto r = kResolver.resolve(text);
    if (r.ok() && (r.value().lat_deg < -90.0 || r.value().lat_deg > 90.0 || r.value().lon_deg < -180.0 ||
                   r.value().lon_deg > 180.0)) {
        __builtin_trap();  // resolve() must never return an out-of-range point
    }
    return 0;
}

#ifndef NAVMAP_FUZZ_NO_MAIN
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return navmapFuzzSimPlace(data, size);
}
#endif
