// SPDX-License-Identifier: Apache-2.0
#pragma once
// Spill files of the bounded-memory compile (docs/tile-store.md "Bounded memory"): a sequence of
// length-prefixed, CRC32-checked records on disk that navmap-compile writes while it reads its
// input and reads back band by band. Records are opaque bytes here; the compiler stages give them
// meaning. Layout, little-endian: "NMSPILL1", then per record u32 length, u32 CRC32 of the
// payload, payload. A reader reports truncation and damage naming the file and the byte offset.

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "navmap/map/compile/compiler.h"

namespace navmap::map {

/// A spill file cannot be written or read back intact: "<file>: <problem>", or
/// "<call>(<file>): <errno text>" for a failed syscall (disk full, permissions, ...).
class SpillError : public CompileError {
public:
    using CompileError::CompileError;
};

inline constexpr char kSpillMagic[8] = {'N', 'M', 'S', 'P', 'I', 'L', 'L', '1'};
inline constexpr std::uint32_t kMaxSpillRecord = 1u << 30;  ///< larger length fields are damage

/// Appends records to a new file (O_EXCL: nothing planted there is reused), buffered. Throws
/// SpillError naming the file on any failed call. Not thread-safe.
class SpillWriter {
public:
    /// Creates `path`; `buffer_bytes` of records are kept before each write().
    explicit SpillWriter(std::filesystem::path path, std::size_t buffer_bytes = std::size_t{1} << 16);
    ~SpillWriter();  ///< closes without checks (call close() to see errors)
    SpillWriter(const SpillWriter&) = delete;
    SpillWriter& operator=(const SpillWriter&) = delete;

    /// Appends one record; returns its offset in the file (for SpillReader::readAt()).
    std::uint64_t append(std::span<const std::uint8_t> payload);
    /// Writes what is buffered and closes; afterwards the file is complete.
    void close();
    /// Writes what is buffered: a reader of the file sees every record appended so far after
    /// its refresh().
    void flush();

    [[nodiscard]] const std::filesystem::path& path() const { return m_path; }
    [[nodiscard]] std::uint64_t bytes() const { return m_offset + m_buffer.size(); }
    [[nodiscard]] std::uint64_t records() const { return m_records; }

private:
    std::filesystem::path m_path;
    int m_fd = -1;
    std::vector<std::uint8_t> m_buffer;
    std::size_t m_buffer_limit;
    std::uint64_t m_offset = 0;
    std::uint64_t m_records = 0;
};

/// Reads a complete spill file: sequentially (next()) or one record at an offset (readAt()).
/// Throws SpillError naming the file: not a spill file, truncated, a length field out of range,
/// a checksum mismatch.
class SpillReader {
public:
    explicit SpillReader(std::filesystem::path path);
    ~SpillReader();
    SpillReader(const SpillReader&) = delete;
    SpillReader& operator=(const SpillReader&) = delete;

    /// The next record into `payload`; false at the end of the file.
    bool next(std::vector<std::uint8_t>& payload);
    /// The record at `offset` (as SpillWriter::append() returned it).
    void readAt(std::uint64_t offset, std::vector<std::uint8_t>& payload) const;
    /// Takes the file's size again: of a file still being written, records its writer
    /// flushed since are read from here on.
    void refresh();

    [[nodiscard]] const std::filesystem::path& path() const { return m_path; }
    [[nodiscard]] std::uint64_t size() const { return m_size; }

private:
    void readExactly(std::uint64_t offset, void* out, std::size_t n, const char* what) const;
    void record(std::uint64_t offset, std::vector<std::uint8_t>& payload, std::uint64_t& end) const;
    std::filesystem::path m_path;
    int m_fd = -1;
    std::uint64_t m_size = 0;
    std::uint64_t m_pos = sizeof(kSpillMagic);
};

}  // namespace navmap::map
