// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/can/dbc_signal.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

namespace navmap::ipc {
namespace {

constexpr std::uint64_t lowMask(unsigned n) noexcept {
    return n >= 64 ? ~std::uint64_t{0} : ((std::uint64_t{1} << n) - 1U);
}

}  // namespace

unsigned DbcSignal::bytesNeeded() const noexcept {
    if (length == 0) {
        return 0;
    }
    if (byte_order == ByteOrder::Intel) {
        return (static_cast<unsigned>(start_bit) + length - 1U) / 8U + 1U;
    }
    // Motorola: the MSB is at start_bit; the signal runs towards lower bit numbers inside a byte and
    // continues at bit 7 of the next byte ("sawtooth" numbering).
    const unsigned msb_bit = start_bit % 8U;
    const unsigned first_byte = start_bit / 8U;
    if (length <= msb_bit + 1U) {
        return first_byte + 1U;
    }
    const unsigned rest = length - (msb_bit + 1U);
    return first_byte + 1U + (rest + 7U) / 8U;
}

bool DbcSignal::inRange(double physical) const noexcept {
    if (!std::isfinite(physical)) {
        return false;
    }
    if (!hasRange()) {
        return true;
    }
    // Ranges in DBCs are rounded to a few digits (e.g. [-6.5|6.6066] for 16 bits x 0.0002);
    // allow half a raw step of slack so the end points of the raw range pass.
    const double slack = std::abs(factor) * 0.5 + 1e-9 * std::max(std::abs(minimum), std::abs(maximum));
    return physical >= minimum - slack && physical <= maximum + slack;
}

std::uint64_t DbcSignal::extractBits(std::span<const std::uint8_t> data) const noexcept {
    std::uint64_t value = 0;
    unsigned remaining = length;
    if (byte_order == ByteOrder::Intel) {
        unsigned pos = start_bit;
        unsigned shift = 0;
        while (remaining > 0) {
            const unsigned byte = pos / 8U;
            const unsigned bit = pos % 8U;
            const unsigned n = std::min(8U - bit, remaining);
            const std::uint64_t chunk = (static_cast<std::uint64_t>(data[byte]) >> bit) & lowMask(n);
            value |= chunk << shift;
            shift += n;
            pos += n;
            remaining -= n;
        }
        return value;
    }
    unsigned pos = start_bit;
    while (remaining > 0) {
        const unsigned byte = pos / 8U;
        const unsigned bit = pos % 8U;  // MSB of this chunk inside the byte
        const unsigned n = std::min(bit + 1U, remaining);
        const std::uint64_t chunk = (static_cast<std::uint64_t>(data[byte]) >> (bit + 1U - n)) & lowMask(n);
        value = (n >= 64 ? 0 : (value << n)) | chunk;
        remaining -= n;
        pos = (byte + 1U) * 8U + 7U;
    }
    return value;
}

void DbcSignal::insertBits(std::span<std::uint8_t> data, std::uint64_t bits) const noexcept {
    unsigned remaining = length;
    bits &= lowMask(length);
    if (byte_order == ByteOrder::Intel) {
        unsigned pos = start_bit;
        while (remaining > 0) {
            const unsigned byte = pos / 8U;
            const unsigned bit = pos % 8U;
            const unsigned n = std::min(8U - bit, remaining);
            const auto mask = static_cast<std::uint8_t>(lowMask(n) << bit);
            const auto chunk = static_cast<std::uint8_t>((bits & lowMask(n)) << bit);
            data[byte] = static_cast<std::uint8_t>((data[byte] & ~mask) | chunk);
            bits = n >= 64 ? 0 : (bits >> n);
            pos += n;
            remaining -= n;
        }
        return;
    }
    unsigned pos = start_bit;
    while (remaining > 0) {
        const unsigned byte = pos / 8U;
        const unsigned bit = pos % 8U;
        const unsigned n = std::min(bit + 1U, remaining);
        const unsigned lsb = bit + 1U - n;
        const std::uint64_t chunk_bits = (bits >> (remaining - n)) & lowMask(n);
        const auto mask = static_cast<std::uint8_t>(lowMask(n) << lsb);
        data[byte] = static_cast<std::uint8_t>((data[byte] & ~mask) | static_cast<std::uint8_t>(chunk_bits << lsb));
        remaining -= n;
        pos = (byte + 1U) * 8U + 7U;
    }
}

double DbcSignal::rawValue(std::span<const std::uint8_t> data) const noexcept {
    const std::uint64_t bits = extractBits(data);
    switch (value_type) {
        case ValueType::Float32: {
            const auto u = static_cast<std::uint32_t>(bits);
            return static_cast<double>(std::bit_cast<float>(u));
        }
        case ValueType::Float64: return std::bit_cast<double>(bits);
        case ValueType::Integer: break;
    }
    if (is_signed && length > 0 && length < 64 && ((bits >> (length - 1U)) & 1U) != 0) {
        return static_cast<double>(static_cast<std::int64_t>(bits | ~lowMask(length)));
    }
    if (is_signed) {
        return static_cast<double>(static_cast<std::int64_t>(bits));
    }
    return static_cast<double>(bits);
}

std::optional<double> DbcSignal::decode(std::span<const std::uint8_t> data) const noexcept {
    if (length == 0 || data.size() < bytesNeeded()) {
        return std::nullopt;
    }
    return rawValue(data) * factor + offset;
}

Status DbcSignal::encode(std::span<std::uint8_t> data, double physical) const {
    if (!std::isfinite(physical)) {
        return Error{"signal " + name + ": value is not finite"};
    }
    if (data.size() < bytesNeeded()) {
        return Error{"signal " + name + ": frame has " + std::to_string(data.size()) + " bytes, signal needs " +
                     std::to_string(bytesNeeded())};
    }
    if (factor == 0.0) {
        return Error{"signal " + name + ": factor is 0"};
    }
    const double raw = (physical - offset) / factor;
    if (value_type == ValueType::Float32) {
        insertBits(data, std::bit_cast<std::uint32_t>(static_cast<float>(raw)));
        return {};
    }
    if (value_type == ValueType::Float64) {
        insertBits(data, std::bit_cast<std::uint64_t>(raw));
        return {};
    }
    const double rounded = std::nearbyint(raw);
    // Exclusive upper bound so that 2^63 / 2^64 (not representable in the integer) are rejected.
    const double lo = is_signed ? -std::ldexp(1.0, length - 1) : 0.0;
    const double hi_exclusive = is_signed ? std::ldexp(1.0, length - 1) : std::ldexp(1.0, length);
    if (rounded < lo || rounded >= hi_exclusive) {
        return Error{"signal " + name + ": value " + std::to_string(physical) + " does not fit " +
                     std::to_string(length) + (is_signed ? " signed" : " unsigned") + " bits"};
    }
    const std::uint64_t bits = is_signed ? static_cast<std::uint64_t>(static_cast<std::int64_t>(rounded))
                                         : static_cast<std::uint64_t>(rounded);
    insertBits(data, bits);
    return {};
}

}  // namespace navmap::ipc
