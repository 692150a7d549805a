// SPDX-License-Identifier: Apache-2.0
#pragma once
// Setup failure of the drive simulator (a store that cannot be used, an unknown place, no route).
// Thrown only while setting up (DriveSimulator::create, the navmap-sim tool); expected failures
// during a run are ipc::Result / ipc::Status values.

#include <stdexcept>

namespace navmap::sim {

class SimError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace navmap::sim
