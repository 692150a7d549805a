// SPDX-License-Identifier: Apache-2.0
#pragma once
// ReplaySource: where a Replayer takes its frames from, one at a time in log order, so that a
// log of any length plays in bounded memory (CandumpFileSource streams a candump file; the
// Replayer wraps a frame vector in one for the simulator and the tests).

#include <string>

#include "navmap/ipc/can/can_frame.h"

namespace navmap::ipc {

class ReplaySource {
public:
    virtual ~ReplaySource() = default;
    /// The next frame of the log: true with `out` set; false at the end of the log, or when the
    /// source failed (failure() then says why).
    virtual bool next(CanFrame& out) = 0;
    /// Starts again at the first frame (looping); false when it cannot (failure() says why).
    virtual bool rewind() = 0;
    /// Why the source stopped before the end of its log; empty while it works.
    [[nodiscard]] virtual const std::string& failure() const = 0;
};

}  // namespace navmap::ipc
