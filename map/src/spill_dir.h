// SPDX-License-Identifier: Apache-2.0
#pragma once
// The scratch folder of one bounded-memory compile: created fresh (mkdtemp) in a given folder,
// removed with everything in it when the compile ends, on success and on error. Private to
// navmap_map.

#include <filesystem>
#include <functional>
#include <string>

namespace navmap::map::detail {

class SpillDir {
public:
    /// Creates `<parent>/navmap-spill-XXXXXX`; throws SpillError ("mkdtemp(<path>): Permission
    /// denied", ...) when it cannot.
    SpillDir(const std::filesystem::path& parent, std::function<void(const std::string&)> log);
    /// Removes the folder; a failure is logged, never thrown.
    ~SpillDir();
    SpillDir(const SpillDir&) = delete;
    SpillDir& operator=(const SpillDir&) = delete;

    [[nodiscard]] const std::filesystem::path& path() const { return m_path; }
    [[nodiscard]] std::filesystem::path operator/(const std::string& name) const { return m_path / name; }

private:
    std::filesystem::path m_path;
    std::function<void(const std::string&)> m_log;
};

}  // namespace navmap::map::detail
