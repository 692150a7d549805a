// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: navmapd's configuration text through the limits pass (daemon/toml_limits.h)
// and, when it passes, toml++ and the key reader. Whatever the text, the pass answers, and text it
// lets through never takes toml++ down (its recursion is bounded by the depth limit). Built with
// -DNAVMAP_WITH_FUZZ=ON (clang); daemon_unit_tests also compiles it (NAVMAP_FUZZ_NO_MAIN) and
// runs navmapFuzzConfig() on broken and hostile files.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "config.h"
#include "toml_limits.h"

int navmapFuzzConfig(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const std::string limit = navmap::daemon::checkTomlLimits(text, "fuzz.toml");
    navmap::daemon::ConfigError error;
    const auto config = navmap::daemon::parseConfig(text, "fuzz.toml", &error);
    // A refused text is refused with the pass's own message; every refusal names the file.
    if (!limit.empty() && (config || error.message != limit)) std::abort();
    if (!config && error.message.rfind("fuzz.toml", 0) != 0) std::abort();
    return 0;
}

#ifndef NAVMAP_FUZZ_NO_MAIN
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return navmapFuzzConfig(data, size);
}
#endif
