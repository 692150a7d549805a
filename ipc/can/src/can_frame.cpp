// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/can/can_frame.h"

#include <cstdio>

namespace navmap::ipc {

bool isValidFdLength(unsigned len) noexcept {
    if (len <= 8) {
        return true;
    }
    switch (len) {
        case 12:
        case 16:
        case 20:
        case 24:
        case 32:
        case 48:
        case 64: return true;
        default: return false;
    }
}

std::string formatCandumpPayload(const CanFrame& frame) {
    static constexpr char kHex[] = "0123456789ABCDEF";
    char id_text[16];
    if (frame.error()) {
        std::snprintf(id_text, sizeof id_text, "%08X", static_cast<unsigned>(frame.id | 0x20000000U));
    } else if (frame.extended()) {
        std::snprintf(id_text, sizeof id_text, "%08X", static_cast<unsigned>(frame.id));
    } else {
        std::snprintf(id_text, sizeof id_text, "%03X", static_cast<unsigned>(frame.id));
    }
    std::string out(id_text);
    if (frame.fd()) {
        out += "##";
        unsigned fd_flags = 0;
        if ((frame.flags & kCanBrs) != 0) {
            fd_flags |= 1U;
        }
        if ((frame.flags & kCanEsi) != 0) {
            fd_flags |= 2U;
        }
        out.push_back(kHex[fd_flags]);
    } else {
        out.push_back('#');
        if (frame.rtr()) {
            out.push_back('R');
            if (frame.len > 0) {
                out.push_back(kHex[frame.len & 0xFU]);
            }
            return out;
        }
    }
    for (unsigned i = 0; i < frame.len && i < kCanMaxFdLen; ++i) {
        out.push_back(kHex[frame.data[i] >> 4U]);
        out.push_back(kHex[frame.data[i] & 0xFU]);
    }
    return out;
}

}  // namespace navmap::ipc
