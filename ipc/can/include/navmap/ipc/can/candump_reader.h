// SPDX-License-Identifier: Apache-2.0
#pragma once
// CandumpReader: parser for can-utils candump log lines, "(sec.frac) iface FRAME".
// Hand-written (can-utils ships the C tools, not a library). Accepted FRAME forms, as in
// can-utils lib.c: classic "123#11223344" (3 hex digits: 11-bit, 8: 29-bit, '.' between bytes
// allowed, optional "_<dlc>" len8_dlc suffix), remote "123#R" / "123#R4", CAN FD "123##<flags><data>",
// error frames (8-digit id with CAN_ERR_FLAG 0x20000000). Any number of fraction digits in the
// timestamp, upper or lower case hex, any interface names, an optional trailing direction "R"/"T".
// Input of any size is read in chunks with a bounded line buffer (feedBytes); binary data is
// refused at its first control byte instead of being read as one endless line.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <istream>
#include <string>
#include <string_view>
#include <vector>

#include "navmap/ipc/can/can_frame.h"
#include "navmap/ipc/net/result.h"

namespace navmap::ipc {

/// One parsed log line: the frame (timestamp = the log time) and the interface index into
/// CandumpReader::interfaces().
struct CandumpRecord {
    CanFrame frame;
    std::uint16_t interface_index = 0;
};

/// One rejected line.
struct CandumpLineError {
    std::size_t line = 0;
    std::string message;  ///< "<source>:<line>: <reason>"
};

struct CandumpCounters {
    std::size_t lines = 0;   ///< lines seen, including blank ones
    std::size_t frames = 0;  ///< accepted frames (all kinds)
    std::size_t fd_frames = 0;
    std::size_t remote_frames = 0;
    std::size_t error_frames = 0;
    std::size_t malformed = 0;  ///< rejected lines (over-long and out-of-range timestamps included)
    std::size_t skipped = 0;    ///< blank and comment ('#' or ';') lines
};

/// Line-by-line parser with per-line errors and counters. Not thread-safe; one per log.
class CandumpReader {
public:
    explicit CandumpReader(std::string source_name = "<candump>");

    /// The pure parser: one line (without newline) -> frame + interface name, or the reason it is
    /// malformed (no line number). The returned view points into `line`.
    struct Parsed {
        CanFrame frame;
        std::string_view interface_name;
    };
    static Result<Parsed> parseLine(std::string_view line);

    /// Parses one line, counts it and records the error (with line number) if it is malformed.
    /// Returns true and fills `out` for a frame; false for blank, comment or malformed lines.
    bool feedLine(std::string_view line, CandumpRecord& out);

    using RecordSink = std::function<void(const CandumpRecord&)>;
    /// Splits bytes (in any chunks) into lines for feedLine() and hands each frame to `sink`. At
    /// most kMaxLineLength + 1 bytes of a line are kept: a longer line is malformed (counted) and
    /// skipped up to its newline. Fails, and stays failed (failure()), on data that is no text
    /// log: a control byte other than tab, CR and LF, or a line still going after kMaxSkipBytes.
    Status feedBytes(std::string_view bytes, const RecordSink& sink);
    /// The input ended: feeds a last line that had no newline.
    void finishBytes(const RecordSink& sink);
    /// The input starts again from its first byte (a looping replay): drops the partial line and
    /// restarts line numbers and offsets; counters and errors keep counting.
    void restartInput();

    /// Reads a whole stream through feedBytes(); returns the frames in log order. Stops at a
    /// failure (failure() says why; the frames before it are returned).
    std::vector<CandumpRecord> readAll(std::istream& in);

    /// Why the input was refused ("<source>: byte 0x00 at offset 0 (line 1): binary data, not a
    /// candump log"); empty while it is accepted.
    const std::string& failure() const noexcept { return m_failure; }
    /// Bytes held for the line being read (at most kMaxLineLength + 1).
    std::size_t bufferedBytes() const noexcept { return m_partial.size(); }

    const CandumpCounters& counters() const noexcept { return m_counters; }
    /// First kMaxErrors errors; counters().malformed counts all.
    const std::vector<CandumpLineError>& errors() const noexcept { return m_errors; }
    const std::vector<std::string>& interfaces() const noexcept { return m_interfaces; }
    const std::string& sourceName() const noexcept { return m_source_name; }

    static constexpr std::size_t kMaxErrors = 100;
    static constexpr std::size_t kMaxLineLength = 512;
    static constexpr std::size_t kMaxSkipBytes = 64 * 1024;
    /// Seconds since the epoch that a timestamp may have: the nanoseconds of CanTime (int64) hold
    /// up to 9223372036.854775807 s; later ones are malformed lines, never an overflow.
    static constexpr std::uint64_t kMaxTimestampSeconds = 9223372035;

private:
    void reject(const std::string& message);

    std::string m_source_name;
    CandumpCounters m_counters;
    std::vector<CandumpLineError> m_errors;
    std::vector<std::string> m_interfaces;
    // feedBytes() state
    std::size_t m_line = 0;      // number of the current line in this pass over the input
    std::uint64_t m_offset = 0;  // bytes fed in this pass
    std::string m_partial;       // the line read so far (bounded)
    bool m_skipping = false;     // inside an over-long line
    std::size_t m_skipped = 0;   // bytes of the over-long line so far
    std::string m_failure;
};

/// A whole log file loaded into memory (what the Replayer plays).
struct CandumpLog {
    std::vector<CandumpRecord> records;
    std::vector<std::string> interfaces;
    CandumpCounters counters;
    std::vector<CandumpLineError> errors;

    /// Frames only (optionally only those of one interface; empty = all).
    std::vector<CanFrame> frames(std::string_view interface_name = {}) const;
};

/// Loads a candump file (tests and tools; navmapd streams with CandumpFileSource); fails when the
/// file cannot be read or is refused (CandumpReader::failure()); bad lines are in .errors.
Result<CandumpLog> loadCandumpFile(const std::filesystem::path& path);

}  // namespace navmap::ipc
