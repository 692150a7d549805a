// SPDX-License-Identifier: Apache-2.0
#pragma once
// DbcSignal: one `SG_` entry of a DBC file and the bit-level codec for it.
// Hand-written: no Debian package provides a C++ DBC parser/codec (see dbc_database.h).

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>

#include "navmap/ipc/net/result.h"

namespace navmap::ipc {

enum class ByteOrder : std::uint8_t {
    Motorola,  ///< `@0`: big endian; start bit is the MSB in DBC "sawtooth" numbering
    Intel,     ///< `@1`: little endian; start bit is the LSB
};

enum class ValueType : std::uint8_t {
    Integer,  ///< raw bits as (un)signed integer, the default
    Float32,  ///< SIG_VALTYPE_ 1: IEEE single (length must be 32)
    Float64,  ///< SIG_VALTYPE_ 2: IEEE double (length must be 64)
};

enum class MuxRole : std::uint8_t {
    None,         ///< always present
    Multiplexor,  ///< `M`: selects which multiplexed signals are present
    Multiplexed,  ///< `mN`: present only when the multiplexor equals N
};

/// One signal. Physical value = raw * factor + offset; [minimum, maximum] is the valid physical range
/// (ignored when minimum >= maximum, as in DBCs that write [0|0]).
struct DbcSignal {
    std::string name;
    std::uint16_t start_bit = 0;  ///< as written in the DBC
    std::uint16_t length = 0;     ///< 1..64 bits
    ByteOrder byte_order = ByteOrder::Intel;
    bool is_signed = false;
    ValueType value_type = ValueType::Integer;
    double factor = 1.0;
    double offset = 0.0;
    double minimum = 0.0;
    double maximum = 0.0;
    std::string unit;
    MuxRole mux_role = MuxRole::None;
    std::uint32_t mux_value = 0;    ///< for Multiplexed signals
    bool also_multiplexor = false;  ///< `mNM` (extended multiplexing): treated as plain multiplexed signal
    std::map<std::int64_t, std::string> value_names;  ///< from VAL_
    std::size_t line = 0;                             ///< DBC line of the SG_ entry (for messages)

    /// Number of payload bytes the signal needs (one past the highest byte it touches).
    unsigned bytesNeeded() const noexcept;
    /// True when min/max form a usable range.
    bool hasRange() const noexcept { return minimum < maximum; }
    /// True when `physical` lies in [minimum, maximum] (with a small tolerance), or no range is set.
    bool inRange(double physical) const noexcept;

    /// Raw bits of the signal (not sign-extended). `data` must hold bytesNeeded() bytes.
    std::uint64_t extractBits(std::span<const std::uint8_t> data) const noexcept;
    /// Writes the low `length` bits of `bits` into `data` (must hold bytesNeeded() bytes).
    void insertBits(std::span<std::uint8_t> data, std::uint64_t bits) const noexcept;

    /// Raw value as signed integer / float (sign-extended or reinterpreted as the type says).
    double rawValue(std::span<const std::uint8_t> data) const noexcept;
    /// Physical value, or nullopt when `data` is too short for this signal.
    std::optional<double> decode(std::span<const std::uint8_t> data) const noexcept;
    /// Encodes a physical value into `data`; fails when NaN or the raw value does not fit the bits.
    Status encode(std::span<std::uint8_t> data, double physical) const;
};

}  // namespace navmap::ipc
