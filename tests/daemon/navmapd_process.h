// SPDX-License-Identifier: Apache-2.0
#pragma once
// Helpers for whole-program tests of navmapd: a replayable drive and a daemon child process.
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <utility>
#include <vector>

extern char** environ;

namespace navmap::test {

/// A scratch folder `<tmp>/<name>-<pid>`, empty at the start and removed at the end.
struct ScratchDir {
    std::filesystem::path dir;
    explicit ScratchDir(const std::string& name)
        : dir(std::filesystem::temp_directory_path() / (name + "-" + std::to_string(::getpid()))) {
        std::filesystem::remove_all(dir);
        std::filesystem::create_directories(dir);
    }
    ~ScratchDir() { std::filesystem::remove_all(dir); }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
};

/// A vehicle standing at each of `stops` (lat, lon) in turn, `ms_per_stop` at each: NAV_Position
/// at 10 Hz and NAV_Motion at 50 Hz (data/navmap.dbc, Intel byte order). The daemon loops it.
inline void writeStandingLog(const std::filesystem::path& path, const std::vector<std::pair<double, double>>& stops,
                             int ms_per_stop) {
    std::ofstream out(path);
    char line[128];
    int counter = 0;
    for (std::size_t stop = 0; stop < stops.size(); ++stop) {
        const std::int32_t lat = static_cast<std::int32_t>(std::lround(stops[stop].first * 1e7));
        const std::int32_t lon = static_cast<std::int32_t>(std::lround(stops[stop].second * 1e7));
        for (int ms = 0; ms < ms_per_stop; ms += 20) {
            const double t = 1618394400.0 + (static_cast<double>(stop) * ms_per_stop + ms) / 1000.0;
            if (ms % 100 == 0) {
                std::uint8_t b[8];
                for (int i = 0; i < 4; ++i)
                    b[i] = static_cast<std::uint8_t>((static_cast<std::uint32_t>(lat) >> (8 * i)) & 0xff);
                for (int i = 0; i < 4; ++i)
                    b[4 + i] = static_cast<std::uint8_t>((static_cast<std::uint32_t>(lon) >> (8 * i)) & 0xff);
                std::snprintf(line, sizeof line, "(%.6f) vcan0 6A0#%02X%02X%02X%02X%02X%02X%02X%02X\n", t, b[0], b[1],
                              b[2], b[3], b[4], b[5], b[6], b[7]);
                out << line;
            }
            const std::uint16_t heading = 4500;  // 45.00 deg
            const std::uint8_t fix_counter = static_cast<std::uint8_t>(3 | ((counter++ & 15) << 4));
            std::snprintf(line, sizeof line, "(%.6f) vcan0 6A1#%02X%02X%02X%02X%02X%02X%02X%02X\n", t + 0.001,
                          heading & 0xff, heading >> 8, 0, 0, 0, 0, fix_counter, 9);
            out << line;
        }
    }
}

/// A vehicle standing at a fixed point in Andorra la Vella for 20 s.
inline void writeStandingLog(const std::filesystem::path& path) {
    writeStandingLog(path, {{42.50770, 1.52190}}, 20000);
}

/// navmapd as a child process (exec'd, so signals reach it), stderr and stdout in `log`.
class NavmapdProcess {
public:
    /// Starts `navmapd <args>` and waits (up to 10 s) until `wait_for` exists.
    NavmapdProcess(const std::string& navmapd, const std::string& args, const std::filesystem::path& log,
                   const std::filesystem::path& wait_for)
        : m_log(log) {
        const std::string cmd = "exec " + navmapd + " " + args + " > " + log.string() + " 2>&1";
        const char* argv[] = {"/bin/sh", "-c", cmd.c_str(), nullptr};
        if (posix_spawn(&m_pid, "/bin/sh", nullptr, nullptr, const_cast<char**>(argv), environ) != 0) m_pid = -1;
        for (int i = 0; i < 200 && !std::filesystem::exists(wait_for); ++i) {
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
    }
    ~NavmapdProcess() { stop(); }
    NavmapdProcess(const NavmapdProcess&) = delete;
    NavmapdProcess& operator=(const NavmapdProcess&) = delete;

    bool signal(int sig) const { return m_pid > 0 && ::kill(m_pid, sig) == 0; }
    /// SIGTERM, then the exit status (-2 when it had to be killed).
    int stop() {
        if (m_pid <= 0) return -1;
        ::kill(m_pid, SIGTERM);
        int status = 0;
        for (int i = 0; i < 100; ++i) {
            if (::waitpid(m_pid, &status, WNOHANG) == m_pid) {
                m_pid = -1;
                return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        ::kill(m_pid, SIGKILL);
        ::waitpid(m_pid, &status, 0);
        m_pid = -1;
        return -2;
    }
    [[nodiscard]] std::string output() const {
        std::ifstream in(m_log);
        return {std::istreambuf_iterator<char>(in), {}};
    }

private:
    pid_t m_pid = -1;
    std::filesystem::path m_log;
};

}  // namespace navmap::test
