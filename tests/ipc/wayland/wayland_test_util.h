// SPDX-License-Identifier: Apache-2.0
#pragma once
// Helpers of the navmap-wayland tests: child processes with their environment and a log file,
// the test frames (a pattern every pixel of which says where it is), and a frame server that
// publishes that pattern at whatever size its clients ask for.

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "navmap/ipc/stream/frame_server.h"

namespace navmap::wayland_test {

/// A child process: argv[0] found on PATH, the environment plus `env`, stdout and stderr into `log`.
class Child {
public:
    Child(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env, const std::string& log,
          const std::string& cwd = "");
    ~Child();  ///< stop() when still running
    pid_t pid() const { return m_pid; }
    /// Waits up to `timeout` for the exit; the wait status, or -1 while it runs.
    int wait(std::chrono::milliseconds timeout);
    /// SIGTERM to its process group, SIGKILL after `grace`; the wait status.
    int stop(std::chrono::milliseconds grace = std::chrono::seconds(5));
    /// SIGKILL to its process group at once (a crash).
    void kill();

private:
    pid_t m_pid = -1;
    int m_status = -1;
};

/// The whole file ("" when there is none).
std::string readFile(const std::string& path);
/// An executable on PATH, or "".
std::string findOnPath(const std::string& name);

/// RGB of pixel (x, y) of the test frames of generation `tag`: R = x, G = y (low bytes),
/// B = tag and the high bits of x and y; alpha 255.
void patternPixel(int x, int y, int tag, std::uint8_t rgb[3]);
std::vector<std::uint8_t> patternFrame(int width, int height, int tag);

/// A FrameServer on `socket_path` whose thread publishes patternFrame(tag) at 30 fps to every
/// active profile at the size it was asked for. `rendered`: the profiles served (empty: any size).
class PatternServer {
public:
    PatternServer(const std::string& socket_path, int tag, std::vector<ipc::RenderedProfile> rendered = {});
    ~PatternServer();
    bool started() const { return m_started; }
    const std::string& error() const { return m_error; }

private:
    std::unique_ptr<ipc::FrameServer> m_server;
    std::atomic<bool> m_run{true};
    std::thread m_thread;
    bool m_started = false;
    std::string m_error;
};

}  // namespace navmap::wayland_test
