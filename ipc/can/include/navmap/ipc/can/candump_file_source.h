// SPDX-License-Identifier: Apache-2.0
#pragma once
// CandumpFileSource: a candump log file streamed into a Replayer. The file is read in chunks of
// kChunkBytes through a CandumpReader (bounded line buffer), so memory stays the same whatever
// the file's size; looping seeks back to the start. A file that is no candump log is refused
// within its first chunk or lines: binary data (/dev/zero) at its first control byte, text whose
// first kMaxLeadingMalformed lines are all malformed, a line without an end.

#include <cstddef>
#include <deque>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "navmap/ipc/can/candump_reader.h"
#include "navmap/ipc/can/replay_source.h"
#include "navmap/ipc/net/result.h"
#include "navmap/ipc/net/unique_fd.h"

namespace navmap::ipc {

class CandumpFileSource final : public ReplaySource {
public:
    /// Opens the file for reading, without blocking and only a regular file (docs/architecture.md
    /// "Untrusted files"): `open(PATH): No such file or directory (candump log)`,
    /// `PATH: is a FIFO, not a regular file (candump log)`.
    static Result<std::unique_ptr<CandumpFileSource>> open(const std::filesystem::path& path);
    ~CandumpFileSource() override;
    CandumpFileSource(const CandumpFileSource&) = delete;
    CandumpFileSource& operator=(const CandumpFileSource&) = delete;

    bool next(CanFrame& out) override;
    /// Seeks back to the first byte: `lseek(PATH): Illegal seek` for a pipe.
    bool rewind() override;
    [[nodiscard]] const std::string& failure() const override { return m_failure; }

    /// Counters (frames, malformed lines, ...), the first errors and the interface names.
    [[nodiscard]] const CandumpReader& reader() const { return m_reader; }
    /// Memory held for reading now: the chunk, the partial line and the parsed frames not yet
    /// taken. Bounded by kChunkBytes + CandumpReader::kMaxLineLength + the frames of one chunk.
    [[nodiscard]] std::size_t bufferedBytes() const;
    /// Bytes read from the file in this pass.
    [[nodiscard]] std::uint64_t bytesRead() const { return m_bytes_read; }

    static constexpr std::size_t kChunkBytes = 16 * 1024;
    static constexpr std::size_t kMaxLeadingMalformed = 1000;

private:
    CandumpFileSource(int fd, std::filesystem::path path);
    bool fill();

    net::UniqueFd m_fd;
    std::filesystem::path m_path;
    CandumpReader m_reader;
    std::vector<char> m_chunk;
    std::deque<CandumpRecord> m_ready;
    bool m_eof = false;
    std::uint64_t m_bytes_read = 0;
    std::string m_failure;
};

}  // namespace navmap::ipc
