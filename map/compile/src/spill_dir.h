// SPDX-License-Identifier: Apache-2.0
#pragma once
// The scratch folder of one bounded-memory compile: created fresh (mkdtemp) in a given folder,
// removed with everything in it when the compile ends, on success and on error. A compile that is
// killed cannot remove its folder, so each folder names its owner in a file `owner`: "<pid>
// <start time in clock ticks after boot> <boot id>", held locked (flock) while the owner runs.
// Before it makes its own folder a compile removes the folders in the same place whose owner is
// gone: another boot, no such process, a process of another start time (the pid was reused), and
// the lock free. A folder without an owner file (being made, or from an older version) is left.
// Private to navmap_map.

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

namespace navmap::map::detail {

/// The owner of a spill folder, as its `owner` file records it.
struct SpillOwner {
    pid_t pid = 0;
    std::uint64_t start_ticks = 0;  ///< field 22 of /proc/<pid>/stat
    std::string boot_id;            ///< /proc/sys/kernel/random/boot_id
    /// This process.
    static SpillOwner self();
    /// Parses the owner file's text; nullopt when it is not one.
    static std::optional<SpillOwner> parse(const std::string& text);
    [[nodiscard]] std::string text() const;
    /// Whether the recorded process may still run (true when that cannot be ruled out).
    [[nodiscard]] bool mayBeAlive() const;
};

class SpillDir {
public:
    /// Removes the stale spill folders in `parent` (removeStale), then creates
    /// `<parent>/navmap-spill-XXXXXX` with its owner file; throws SpillError ("mkdtemp(<path>):
    /// Permission denied", ...) when it cannot.
    SpillDir(const std::filesystem::path& parent, std::function<void(const std::string&)> log);
    /// Removes the folder; a failure is logged, never thrown.
    ~SpillDir();
    SpillDir(const SpillDir&) = delete;
    SpillDir& operator=(const SpillDir&) = delete;

    [[nodiscard]] const std::filesystem::path& path() const { return m_path; }
    [[nodiscard]] std::filesystem::path operator/(const std::string& name) const { return m_path / name; }

    /// Removes every `navmap-spill-*` folder in `parent` whose owner is gone, logging one line
    /// for each ("removed the spill folder <path> of process <pid>, which is gone (<bytes>
    /// bytes)"); returns how many. Errors are logged, never thrown.
    static std::size_t removeStale(const std::filesystem::path& parent,
                                   const std::function<void(const std::string&)>& log);

private:
    std::filesystem::path m_path;
    std::function<void(const std::string&)> m_log;
    int m_owner_fd = -1;  // the owner file, locked while the folder is ours
};

}  // namespace navmap::map::detail
