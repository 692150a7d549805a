// SPDX-License-Identifier: Apache-2.0
#include "test_paths.h"

namespace navmap::test {

std::filesystem::path sourceDir() { return NAVMAP_SOURCE_DIR; }
std::filesystem::path binaryDir() { return NAVMAP_BINARY_DIR; }
std::filesystem::path dataDir() { return sourceDir() / "data"; }
std::filesystem::path ipcDataDir() { return sourceDir() / "tests" / "ipc" / "data"; }
std::filesystem::path fuzzCorpusDir(std::string_view target) {
    return sourceDir() / "tests" / "fuzz" / "corpus" / target;
}

}  // namespace navmap::test
