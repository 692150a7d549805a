// SPDX-License-Identifier: Apache-2.0
#pragma once
// Where tests find data: everything is in the repository. The repo's data/ (the embedded default
// data), tests/ipc/data (real CAN logs and DBC files, see its SOURCES.md) and the checked-in fuzz
// corpora under tests/fuzz/corpus/.

#include <filesystem>
#include <string_view>

namespace navmap::test {

std::filesystem::path sourceDir();
std::filesystem::path binaryDir();
std::filesystem::path dataDir();     ///< the repo's data/
std::filesystem::path ipcDataDir();  ///< tests/ipc/data: can/*.candump, dbc/*.dbc, signal maps
/// tests/fuzz/corpus/<target>: the minimized corpus of one libFuzzer target.
std::filesystem::path fuzzCorpusDir(std::string_view target);

}  // namespace navmap::test
