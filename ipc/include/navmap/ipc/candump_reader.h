#pragma once
// CandumpReader: parser for can-utils candump log lines, "(sec.frac) iface FRAME".
// Hand-written (can-utils ships the C tools, not a library). Accepted FRAME forms, as in
// can-utils lib.c: classic "123#11223344" (3 hex digits: 11-bit, 8: 29-bit, '.' between bytes
// allowed, optional "_<dlc>" len8_dlc suffix), remote "123#R" / "123#R4", CAN FD "123##<flags><data>",
// error frames (8-digit id with CAN_ERR_FLAG 0x20000000). Any number of fraction digits in the
// timestamp, upper or lower case hex, any interface names, an optional trailing direction "R"/"T".

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <istream>
#include <string>
#include <string_view>
#include <vector>

#include "navmap/ipc/can_frame.h"
#include "navmap/ipc/result.h"

namespace navmap::ipc {

/// One parsed log line: the frame (timestamp = the log time) and the interface index into
/// CandumpReader::interfaces().
struct CandumpRecord {
    CanFrame frame;
    std::uint16_t interfaceIndex = 0;
};

/// One rejected line.
struct CandumpLineError {
    std::size_t line = 0;
    std::string message;  ///< "<source>:<line>: <reason>"
};

struct CandumpCounters {
    std::size_t lines = 0;        ///< lines seen, including blank ones
    std::size_t frames = 0;       ///< accepted frames (all kinds)
    std::size_t fdFrames = 0;
    std::size_t remoteFrames = 0;
    std::size_t errorFrames = 0;
    std::size_t malformed = 0;    ///< rejected lines
    std::size_t skipped = 0;      ///< blank and comment ('#' or ';') lines
};

/// Line-by-line parser with per-line errors and counters. Not thread-safe; one per log.
class CandumpReader {
public:
    explicit CandumpReader(std::string sourceName = "<candump>");

    /// The pure parser: one line (without newline) -> frame + interface name, or the reason it is
    /// malformed (no line number). The returned view points into `line`.
    struct Parsed {
        CanFrame frame;
        std::string_view interfaceName;
    };
    static Result<Parsed> parseLine(std::string_view line);

    /// Parses one line, counts it and records the error (with line number) if it is malformed.
    /// Returns true and fills `out` for a frame; false for blank, comment or malformed lines.
    bool feedLine(std::string_view line, CandumpRecord& out);

    /// Reads every line of a stream; returns the frames in log order.
    std::vector<CandumpRecord> readAll(std::istream& in);

    const CandumpCounters& counters() const noexcept { return m_counters; }
    /// First kMaxErrors errors; counters().malformed counts all.
    const std::vector<CandumpLineError>& errors() const noexcept { return m_errors; }
    const std::vector<std::string>& interfaces() const noexcept { return m_interfaces; }
    const std::string& sourceName() const noexcept { return m_sourceName; }

    static constexpr std::size_t kMaxErrors = 100;
    static constexpr std::size_t kMaxLineLength = 512;

private:
    std::string m_sourceName;
    CandumpCounters m_counters;
    std::vector<CandumpLineError> m_errors;
    std::vector<std::string> m_interfaces;
};

/// A whole log file loaded into memory (what the Replayer plays).
struct CandumpLog {
    std::vector<CandumpRecord> records;
    std::vector<std::string> interfaces;
    CandumpCounters counters;
    std::vector<CandumpLineError> errors;

    /// Frames only (optionally only those of one interface; empty = all).
    std::vector<CanFrame> frames(std::string_view interfaceName = {}) const;
};

/// Loads a candump file; fails only when the file cannot be read (bad lines are in .errors).
Result<CandumpLog> loadCandumpFile(const std::filesystem::path& path);

}  // namespace navmap::ipc
