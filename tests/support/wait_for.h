// SPDX-License-Identifier: Apache-2.0
// Polling until a condition holds, for tests of threads and sockets.
#pragma once

#include <chrono>
#include <thread>

namespace navmap::test {

/// Calls `pred` every `poll` until it returns true or `limit` has passed; returns its last result.
template <typename Pred>
bool waitFor(Pred pred, std::chrono::milliseconds limit = std::chrono::seconds(3),
             std::chrono::milliseconds poll = std::chrono::milliseconds(5)) {
    const auto until = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < until) {
        if (pred()) return true;
        std::this_thread::sleep_for(poll);
    }
    return pred();
}

}  // namespace navmap::test
