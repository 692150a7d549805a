// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/can/dbc_message.h"

#include <cmath>

namespace navmap::ipc {

const DbcSignal* DbcMessage::findSignal(std::string_view signal_name) const noexcept {
    for (const auto& s : signals) {
        if (s.name == signal_name) {
            return &s;
        }
    }
    return nullptr;
}

bool DbcMessage::isPresent(const DbcSignal& signal, std::span<const std::uint8_t> data) const noexcept {
    if (signal.mux_role != MuxRole::Multiplexed) {
        return true;
    }
    if (multiplexor < 0) {
        return false;
    }
    const DbcSignal& mux = signals[static_cast<std::size_t>(multiplexor)];
    if (data.size() < mux.bytesNeeded()) {
        return false;
    }
    return mux.extractBits(data) == signal.mux_value;
}

std::size_t DbcMessage::decodeAll(std::span<const std::uint8_t> data,
                                  const std::function<void(const DbcSignal&, double)>& visit) const {
    std::size_t count = 0;
    for (const auto& s : signals) {
        if (!isPresent(s, data)) {
            continue;
        }
        if (const auto v = s.decode(data)) {
            visit(s, *v);
            ++count;
        }
    }
    return count;
}

Result<CanFrame> DbcMessage::encode(const std::map<std::string, double, std::less<>>& values) const {
    CanFrame frame;
    frame.id = id;
    frame.len = size;
    if (extended) {
        frame.flags |= kCanExtended;
    }
    if (size > kCanMaxClassicLen) {
        frame.flags |= kCanFd;
    }
    const std::span<std::uint8_t> data(frame.data.data(), size);
    std::optional<std::uint64_t> mux_selected;
    if (multiplexor >= 0) {
        const DbcSignal& mux = signals[static_cast<std::size_t>(multiplexor)];
        if (const auto it = values.find(mux.name); it != values.end()) {
            if (auto st = mux.encode(data, it->second); !st) {
                return Error{"message " + name + ": " + st.message()};
            }
            mux_selected = mux.extractBits(data);
        }
    }
    for (const auto& [signalName, value] : values) {
        const DbcSignal* s = findSignal(signalName);
        if (s == nullptr) {
            return Error{"message " + name + ": no signal named '" + signalName + "'"};
        }
        if (s->mux_role == MuxRole::Multiplexor) {
            continue;
        }
        if (s->mux_role == MuxRole::Multiplexed && (!mux_selected || *mux_selected != s->mux_value)) {
            return Error{"message " + name + ": signal " + signalName + " needs multiplexor value " +
                         std::to_string(s->mux_value)};
        }
        if (auto st = s->encode(data, value); !st) {
            return Error{"message " + name + ": " + st.message()};
        }
    }
    return frame;
}

}  // namespace navmap::ipc
