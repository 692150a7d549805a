// SPDX-License-Identifier: Apache-2.0
#pragma once
// Writes CAN frames as a candump log, exactly `candump -l`'s form: "(sec.usec) iface ID#DATA"
// (6 fraction digits, upper-case hex, 3-digit 11-bit ids, 8-digit 29-bit ids, "##" for CAN FD),
// readable by ipc::CandumpReader and by can-utils canplayer. The file is written to
// "<path>.tmp" and renamed by close(), so a failed run never leaves a half-written log.

#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

#include "navmap/ipc/can/can_frame.h"
#include "navmap/ipc/net/result.h"

namespace navmap::sim {

/// One log line without the newline: "(1618394400.000000) can0 6A0#...".
std::string formatCandumpLine(const ipc::CanFrame& frame, std::string_view iface);

class CandumpWriter {
public:
    /// Opens "<path>.tmp" for writing; fails with "fopen(<path>.tmp): <reason>".
    static ipc::Result<CandumpWriter> open(const std::filesystem::path& path, std::string iface);
    CandumpWriter(CandumpWriter&& other) noexcept;
    CandumpWriter& operator=(CandumpWriter&& other) noexcept;
    CandumpWriter(const CandumpWriter&) = delete;
    CandumpWriter& operator=(const CandumpWriter&) = delete;
    /// Without close() the temporary file is removed (the log is not published).
    ~CandumpWriter();

    ipc::Status write(const ipc::CanFrame& frame);
    /// Flushes, closes and renames to the final path.
    ipc::Status close();
    [[nodiscard]] std::size_t lines() const { return m_lines; }
    [[nodiscard]] const std::filesystem::path& path() const { return m_path; }

private:
    CandumpWriter() = default;
    void discard() noexcept;

    std::FILE* m_file = nullptr;
    std::filesystem::path m_path;
    std::filesystem::path m_tmp;
    std::string m_iface;
    std::size_t m_lines = 0;
};

}  // namespace navmap::sim
