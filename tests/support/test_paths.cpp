#include "test_paths.h"

namespace navmap::test {

std::filesystem::path sourceDir() { return NAVMAP_SOURCE_DIR; }
std::filesystem::path binaryDir() { return NAVMAP_BINARY_DIR; }
std::filesystem::path dataDir() { return sourceDir() / "data"; }

std::optional<std::filesystem::path> sharedDataDir() {
    const auto dir = (sourceDir() / ".." / "shared" / "data").lexically_normal();
    if (std::filesystem::is_directory(dir)) return dir;
    return std::nullopt;
}

}  // namespace navmap::test
