// SPDX-License-Identifier: Apache-2.0
#pragma once
// DbcMessage: one `BO_` entry of a DBC file with its signals; decodes and encodes whole frames.
// Hand-written (no Debian package provides a C++ DBC codec).

#include <cstdint>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "navmap/ipc/can/can_frame.h"
#include "navmap/ipc/can/dbc_signal.h"
#include "navmap/ipc/net/result.h"

namespace navmap::ipc {

struct DbcMessage {
    std::uint32_t id = 0;  ///< 11 or 29 bit identifier, without the DBC's bit 31
    bool extended = false;
    std::string name;
    std::uint8_t size = 8;  ///< payload bytes declared by the DBC (0..64)
    std::string transmitter;
    std::vector<DbcSignal> signals;
    int multiplexor = -1;  ///< index into signals of the `M` signal, -1 when none
    std::size_t line = 0;  ///< DBC line of the BO_ entry

    /// Lookup key matching CanFrame::key(): id with bit 31 set for extended frames.
    std::uint32_t key() const noexcept { return extended ? (id | 0x80000000U) : id; }

    const DbcSignal* findSignal(std::string_view signal_name) const noexcept;

    /// True when `signal` is present in this payload (always, unless it is multiplexed and the
    /// multiplexor selects another value or the payload is too short to read the multiplexor).
    bool isPresent(const DbcSignal& signal, std::span<const std::uint8_t> data) const noexcept;

    /// Decodes every present signal that fits the payload; calls `visit(signal, physical)` for each.
    /// Returns the number of signals decoded.
    std::size_t decodeAll(std::span<const std::uint8_t> data,
                          const std::function<void(const DbcSignal&, double)>& visit) const;

    /// Builds a frame from physical values (signal name -> value). Signals not named are raw 0.
    /// Fails on an unknown signal, a value that does not fit, or a multiplexed signal whose
    /// multiplexor value was not given or differs.
    Result<CanFrame> encode(const std::map<std::string, double, std::less<>>& values) const;
};

}  // namespace navmap::ipc
