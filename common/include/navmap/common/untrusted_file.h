// SPDX-License-Identifier: Apache-2.0
#pragma once
// UntrustedFile: the one way navmap opens a file that someone else may have written (a config, a
// DBC, network weights, a tile store, a candump log, compiler inputs). It opens without blocking
// (O_NONBLOCK: a FIFO never waits for a writer), accepts regular files only (a FIFO, a device
// such as /dev/zero, a socket or a directory is refused, named), checks the file's size against
// the cap of its kind before anything is allocated, and reads at most that cap even when the file
// grows while it is read. Every error names the file and the kind ("/tmp/x.dbc: is a FIFO, not a
// regular file (DBC file)"). The kinds and their caps are listed in docs/architecture.md
// "Untrusted files". It never throws and never waits for anything but the disk.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace navmap {

/// What a file is for, as errors name it, and the most bytes a file of that kind may have.
struct FileKind {
    const char* name = "file";    ///< "config file", "DBC file", ... (errors say it)
    std::uint64_t max_bytes = 0;  ///< 0: no cap (a reader that streams the file in bounded pieces)
};

class UntrustedFile {
public:
    /// Opens `path` for reading as a file of `kind`: O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY,
    /// then fstat: a regular file of at most kind.max_bytes, else the returned file is not ok()
    /// and error() says why. O_NONBLOCK is cleared again once the file is known to be regular.
    static UntrustedFile open(const std::filesystem::path& path, const FileKind& kind);

    /// open() and readAll() in one: the whole file, or nullopt with `error` set.
    static std::optional<std::string> readText(const std::filesystem::path& path, const FileKind& kind,
                                               std::string& error);
    static std::optional<std::vector<std::uint8_t>> readBytes(const std::filesystem::path& path, const FileKind& kind,
                                                              std::string& error);

    UntrustedFile(UntrustedFile&& other) noexcept;
    UntrustedFile& operator=(UntrustedFile&& other) noexcept;
    UntrustedFile(const UntrustedFile&) = delete;
    UntrustedFile& operator=(const UntrustedFile&) = delete;
    ~UntrustedFile();

    [[nodiscard]] bool ok() const { return m_fd >= 0; }
    /// Why open() or a read failed ("<path>: <problem> (<kind>)"); empty while all is well.
    [[nodiscard]] const std::string& error() const { return m_error; }
    [[nodiscard]] int fd() const { return m_fd; }
    /// The size fstat gave at open (at most kind.max_bytes when the kind has a cap).
    [[nodiscard]] std::uint64_t size() const { return m_size; }
    [[nodiscard]] const std::filesystem::path& path() const { return m_path; }
    /// Hands the descriptor to the caller, who closes it; the file is not ok() after.
    int release();

    /// Reads the rest of the file from the current offset: at most kind.max_bytes in all, one byte
    /// more is an error ("grew past ..."), as is a read error. False with error() set.
    bool readAll(std::string& out);
    bool readAll(std::vector<std::uint8_t>& out);

private:
    UntrustedFile() = default;
    template <typename Buffer>
    bool readInto(Buffer& out);
    std::string fail(const std::string& problem) const;

    int m_fd = -1;
    std::uint64_t m_size = 0;
    std::filesystem::path m_path;
    FileKind m_kind;
    std::string m_error;
};

}  // namespace navmap
