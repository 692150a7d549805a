// SPDX-License-Identifier: Apache-2.0
#pragma once
// Helpers shared by the map tests: scratch directories and a small hand-made tile.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "navmap/map/tile.h"

namespace navmap::map::test {

/// A fresh empty directory under the system temp dir, removed by the destructor.
class ScratchDir {
public:
    explicit ScratchDir(const std::string& name);
    ~ScratchDir();
    [[nodiscard]] const std::filesystem::path& path() const { return m_path; }
    [[nodiscard]] std::filesystem::path operator/(const std::string& f) const { return m_path / f; }

private:
    std::filesystem::path m_path;
};

/// A tile with one feature of each kind and a 5x5 DEM (values chosen to exercise the codec).
Tile sampleTile(TileId id, double origin_x, double origin_y, double size_m);

std::filesystem::path repoData(const std::string& file);

/// Runs `f` with RLIMIT_FSIZE at `bytes` and SIGXFSZ ignored (as navmap-compile's caller may),
/// restoring both after: write() and fallocate() past the limit fail with EFBIG, as they fail
/// with ENOSPC on a full disk. False, and `f` not run, when they cannot be set.
bool withFileSizeLimit(std::uint64_t bytes, const std::function<void()>& f);

}  // namespace navmap::map::test
