#pragma once
// Where tests find data: everything is in the repository. The repo's data/ (the embedded default
// data) and tests/ipc/data (real CAN logs and DBC files, see its SOURCES.md).

#include <filesystem>

namespace navmap::test {

std::filesystem::path sourceDir();
std::filesystem::path binaryDir();
std::filesystem::path dataDir();     ///< the repo's data/
std::filesystem::path ipcDataDir();  ///< tests/ipc/data: can/*.candump, dbc/*.dbc, signal maps

}  // namespace navmap::test
