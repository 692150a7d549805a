// SPDX-License-Identifier: Apache-2.0
#pragma once
// DbcDatabase: reader for the subset of the Vector DBC format that vehicle databases use.
//
// Hand-written: no Debian package provides a C++ DBC parser (cantools is Python, and the C++
// projects on GitHub are not packaged). Supported: BO_ messages (11/29-bit ids, up to 64 bytes),
// SG_ signals (start bit, length, Intel `@1` and Motorola `@0` byte order, sign, factor, offset,
// [min|max], unit, receivers), simple multiplexing (`M` / `mN`), VAL_ value names and
// SIG_VALTYPE_ (IEEE float/double). Everything else (VERSION, NS_, BS_, BU_, CM_, BA_*, VAL_TABLE_,
// BO_TX_BU_, SG_MUL_VAL_, EV_, ...) is skipped, including quoted strings that span several lines.
//
// Thread safety: immutable after parsing; share it as std::shared_ptr<const DbcDatabase>.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "navmap/ipc/can/dbc_message.h"
#include "navmap/ipc/net/result.h"

namespace navmap::ipc {

/// Thrown only by the setup helper DbcDatabase::loadOrThrow().
class DbcError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// One problem found while parsing: line number (1-based) and a message that names it.
struct DbcDiagnostic {
    std::size_t line = 0;
    std::string message;  ///< "<source>:<line>: <what>"
};

class DbcDatabase {
public:
    enum class Mode {
        Lenient,  ///< broken entries are skipped and recorded in diagnostics()
        Strict,   ///< the first broken entry fails the parse
    };

    /// Parses DBC text. `sourceName` is used in messages (a file name).
    static Result<DbcDatabase> parse(std::string_view text, std::string_view source_name, Mode mode = Mode::Lenient);
    /// Reads and parses a file; fails when it cannot be read, is no regular file (a FIFO, a device:
    /// refused without waiting) or is over 32 MiB (docs/architecture.md "Untrusted files").
    static Result<DbcDatabase> load(const std::filesystem::path& path, Mode mode = Mode::Lenient);
    /// Setup helper: load() that throws DbcError (with the message) on failure.
    static DbcDatabase loadOrThrow(const std::filesystem::path& path, Mode mode = Mode::Lenient);

    const std::string& sourceName() const noexcept { return m_source_name; }
    const std::vector<DbcMessage>& messages() const noexcept { return m_messages; }
    /// Problems found (lenient mode); at most kMaxDiagnostics kept, diagnosticCount() counts all.
    const std::vector<DbcDiagnostic>& diagnostics() const noexcept { return m_diagnostics; }
    std::size_t diagnosticCount() const noexcept { return m_diagnostic_count; }

    /// Message by frame key (CanFrame::key(): id, bit 31 set for extended), or nullptr.
    const DbcMessage* findMessage(std::uint32_t key) const noexcept;
    /// Message by name, or nullptr.
    const DbcMessage* findMessage(std::string_view name) const noexcept;

    static constexpr std::size_t kMaxDiagnostics = 200;

private:
    friend class DbcParser;
    std::string m_source_name;
    std::vector<DbcMessage> m_messages;
    std::unordered_map<std::uint32_t, std::size_t> m_by_key;
    std::unordered_map<std::string, std::size_t> m_by_name;
    std::vector<DbcDiagnostic> m_diagnostics;
    std::size_t m_diagnostic_count = 0;
};

}  // namespace navmap::ipc
