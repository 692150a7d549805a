// SPDX-License-Identifier: Apache-2.0
// navmap-soak: runs navmapd for a given duration on an accelerated, looping drive with CAN faults
// (the shipped short-faults drive: GNSS dropouts and bursts of bad frames), while display clients
// connect, read, stall and disconnect and the control socket gets valid and malformed commands.
// It samples the daemon's RSS, open fds and threads and its frame-time percentiles, writes a JSON
// report and fails when resources grow beyond the stated tolerances.
// Exit status: 0 passed, 1 failed (or navmapd did not run), 2 usage (docs/tools.md).

#include <nlohmann/json.hpp>

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "navmap/cli/cli.h"
#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/control/control_client.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct Sample {
    double t_s = 0;
    long rss_kb = 0;
    long peak_kb = 0;  // VmHWM: the highest RSS so far
    int fds = 0;
    int threads = 0;
    double frame_p50_ms = 0, frame_p99_ms = 0;
    int clients = 0;
};

long procStatus(pid_t pid, const char* key) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/status");
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind(key, 0) == 0) return std::atol(line.c_str() + std::strlen(key));
    }
    return -1;
}

int countFds(pid_t pid) {
    std::error_code ec;
    int n = 0;
    for (auto it = fs::directory_iterator("/proc/" + std::to_string(pid) + "/fd", ec);
         !ec && it != fs::directory_iterator(); ++it)
        ++n;
    return n;
}

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

struct SoakOptions {
    std::string navmapd, drive, report_path = "soak-report.json", work = "/tmp/navmap-soak";
    double duration = 120, speed = 8, rss_tolerance = 0.25, rss_slack_mb = 24, max_peak_rss_mb = 0;
    int fd_tolerance = 4, thread_tolerance = 2;
    unsigned seed = 1;
};

void addSoakOptions(CLI::App& app, SoakOptions& o) {
    using navmap::cli::finiteIn;
    using navmap::cli::integerIn;
    app.add_option("--navmapd", o.navmapd, "navmapd binary")->required();
    app.add_option("--drive", o.drive, "candump drive to loop (with faults)")->required();
    app.add_option("--duration", o.duration, "seconds to run")->capture_default_str()->check(finiteIn(1.0, 1e7));
    app.add_option("--speed", o.speed, "replay speed factor")->capture_default_str()->check(finiteIn(0.01, 1000.0));
    app.add_option("--report", o.report_path, "JSON report file")->capture_default_str();
    app.add_option("--work-dir", o.work, "directory for sockets and logs")->capture_default_str();
    app.add_option("--rss-tolerance", o.rss_tolerance, "allowed RSS growth (fraction) after warm-up")
        ->capture_default_str()
        ->check(finiteIn(0.0, 100.0));
    app.add_option("--rss-slack-mb", o.rss_slack_mb, "plus this many MiB")
        ->capture_default_str()
        ->check(finiteIn(0.0, 1e6));
    app.add_option("--max-peak-rss-mb", o.max_peak_rss_mb, "peak RSS (VmHWM) limit in MiB, 0 = report only")
        ->capture_default_str()
        ->check(finiteIn(0.0, 1e6));
    app.add_option("--fd-tolerance", o.fd_tolerance, "allowed growth of open fds")
        ->capture_default_str()
        ->check(integerIn(0, 100000));
    app.add_option("--thread-tolerance", o.thread_tolerance, "allowed growth of threads")
        ->capture_default_str()
        ->check(integerIn(0, 100000));
    app.add_option("--seed", o.seed, "random seed for the client schedule")
        ->capture_default_str()
        ->check(integerIn(0, 4294967295LL));
}

// The daemon's sockets in the work directory.
struct SoakPaths {
    std::string control, frames;
};

// Starts navmapd on the looping drive and waits for its frame socket; -1 when it did not come up.
pid_t startDaemon(const SoakOptions& o, const SoakPaths& paths) {
    fs::remove_all(o.work);
    fs::create_directories(o.work);
    const std::string cmd = "exec " + o.navmapd + " --replay " + o.drive + " --speed " + std::to_string(o.speed) +
                            " --control-socket " + paths.control + " --frame-socket " + paths.frames +
                            " --http-port 0 --log-level notice > " + o.work + "/navmapd.log 2>&1";
    const char* args[] = {"/bin/sh", "-c", cmd.c_str(), nullptr};
    pid_t pid = -1;
    if (posix_spawn(&pid, "/bin/sh", nullptr, nullptr, const_cast<char**>(args), environ) != 0) {
        std::fprintf(stderr, "navmap-soak: cannot start %s\n", o.navmapd.c_str());
        return -1;
    }
    for (int i = 0; i < 200 && !fs::exists(paths.frames); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (!fs::exists(paths.frames)) {
        std::fprintf(stderr, "navmap-soak: navmapd did not come up (log: %s/navmapd.log)\n", o.work.c_str());
        ::kill(pid, SIGKILL);
        return -1;
    }
    return pid;
}

struct SoakCounts {
    std::uint64_t connects = 0, disconnects = 0, frames_received = 0, control_errors = 0, stream_errors = 0;
};

// The display clients, the control traffic and the samples of one run.
class SoakRun {
public:
    SoakRun(pid_t pid, const SoakPaths& paths, unsigned seed) : m_pid(pid), m_paths(paths), m_rng(seed) {}

    /// Runs for `duration` seconds; false when the daemon exited meanwhile.
    bool run(double duration);
    [[nodiscard]] const std::vector<Sample>& samples() const { return m_samples; }
    [[nodiscard]] const SoakCounts& counts() const { return m_counts; }

private:
    struct Client {
        std::unique_ptr<navmap::ipc::StreamClient> stream;
        bool stalled = false;
        Clock::time_point until;
    };
    void churnClients();
    void readClients();
    void sendControlTraffic();
    void takeSample(Clock::time_point t0, Clock::time_point now);

    pid_t m_pid;
    const SoakPaths& m_paths;
    std::mt19937 m_rng;
    std::vector<Client> m_clients;
    std::vector<Sample> m_samples;
    SoakCounts m_counts;
};

bool SoakRun::run(double duration) {
    const auto t0 = Clock::now();
    auto last_sample = t0 - std::chrono::seconds(10);
    bool daemon_alive = true;
    while (std::chrono::duration<double>(Clock::now() - t0).count() < duration) {
        int status = 0;
        if (::waitpid(m_pid, &status, WNOHANG) == m_pid) {
            daemon_alive = false;
            std::fprintf(stderr, "navmap-soak: navmapd exited during the run (status %d)\n", status);
            break;
        }
        churnClients();
        readClients();
        sendControlTraffic();
        if (Clock::now() - last_sample >= std::chrono::seconds(2)) {
            last_sample = Clock::now();
            takeSample(t0, last_sample);
        }
    }
    m_clients.clear();
    return daemon_alive;
}

// Client churn: up to 4 clients, some stall (never read) until the server drops them.
void SoakRun::churnClients() {
    static const char* const kProfiles[] = {"cluster", "hud", "center"};
    if (m_clients.size() < 4 && m_rng() % 4 == 0) {
        navmap::ipc::StreamRequest r;
        r.profile = *navmap::ipc::defaultStreamProfile(kProfiles[m_rng() % 3]);
        auto c = navmap::ipc::StreamClient::connectUnix(m_paths.frames, r);
        if (c) {
            ++m_counts.connects;
            m_clients.push_back({std::move(c).value(), m_rng() % 5 == 0,
                                 Clock::now() + std::chrono::milliseconds(500 + m_rng() % 4000)});
        } else {
            ++m_counts.stream_errors;
        }
    }
}

void SoakRun::readClients() {
    for (auto it = m_clients.begin(); it != m_clients.end();) {
        if (Clock::now() > it->until) {
            it = m_clients.erase(it);
            ++m_counts.disconnects;
            continue;
        }
        if (!it->stalled) {
            navmap::ipc::ReceivedFrame f;
            auto got = it->stream->next(f, std::chrono::milliseconds(5));
            if (!got) {
                ++m_counts.stream_errors;
                it = m_clients.erase(it);
                ++m_counts.disconnects;
                continue;
            }
            m_counts.frames_received += got.value() ? 1 : 0;
        }
        ++it;
    }
}

// Control traffic, valid and not.
void SoakRun::sendControlTraffic() {
    if (m_rng() % 20 == 0) {
        if (auto c = navmap::ipc::ControlClient::connect(m_paths.control)) {
            const char* lines[] = {R"({"cmd":"set_style","style":"night"})", R"({"cmd":"set_style","style":"day"})",
                                   R"({"cmd":"set_view","display":"center","mode":"snail"})", "garbage {",
                                   R"({"cmd":"set_route","id":"x","points":[[95,1]]})"};
            auto reply = c.value().request(lines[m_rng() % 5]);
            if (!reply) ++m_counts.control_errors;
        }
    }
}

void SoakRun::takeSample(Clock::time_point t0, Clock::time_point now) {
    Sample s;
    s.t_s = std::chrono::duration<double>(now - t0).count();
    s.rss_kb = procStatus(m_pid, "VmRSS:");
    s.peak_kb = procStatus(m_pid, "VmHWM:");
    s.fds = countFds(m_pid);
    s.threads = static_cast<int>(procStatus(m_pid, "Threads:"));
    s.clients = static_cast<int>(m_clients.size());
    if (auto c = navmap::ipc::ControlClient::connect(m_paths.control)) {
        if (auto reply = c.value().request(R"({"cmd":"get_status"})")) {
            const auto j = nlohmann::json::parse(reply.value(), nullptr, false);
            if (j.is_object() && j.contains("status") && j["status"].contains("profiles")) {
                std::vector<double> p50, p99;
                for (const auto& p : j["status"]["profiles"]) {
                    if (p.value("rendered", 0) > 0) {
                        p50.push_back(p.value("frame_p50_ms", 0.0));
                        p99.push_back(p.value("frame_p99_ms", 0.0));
                    }
                }
                s.frame_p50_ms = p50.empty() ? 0 : *std::max_element(p50.begin(), p50.end());
                s.frame_p99_ms = p99.empty() ? 0 : *std::max_element(p99.begin(), p99.end());
            }
        }
    }
    m_samples.push_back(s);
    std::printf("  t=%5.0fs rss=%6.1f MiB fds=%3d threads=%2d clients=%d frame p50 %.1f p99 %.1f ms\n", s.t_s,
                s.rss_kb / 1024.0, s.fds, s.threads, s.clients, s.frame_p50_ms, s.frame_p99_ms);
    std::fflush(stdout);
}

// How the daemon ended: its peak RSS and its exit status (after SIGTERM when it was still running).
struct DaemonEnd {
    long peak_kb = 0;
    int exit_code = 0;
};

DaemonEnd stopDaemon(pid_t pid, bool daemon_alive, const std::vector<Sample>& samples) {
    DaemonEnd end;
    end.peak_kb = daemon_alive ? procStatus(pid, "VmHWM:") : (samples.empty() ? 0 : samples.back().peak_kb);
    if (daemon_alive) ::kill(pid, SIGTERM);
    int status = 0;
    ::waitpid(pid, &status, 0);
    end.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return end;
}

// Compares the first third after warm-up with the last third.
void compareThirds(const SoakOptions& o, const std::vector<Sample>& samples, nlohmann::json& report,
                   std::vector<std::string>& failures) {
    const std::size_t third = samples.size() / 3;
    std::vector<double> rss_a, rss_b, fd_a, fd_b, th_a, th_b;
    for (std::size_t i = 1; i <= third; ++i) {  // skip the first sample (warm-up)
        rss_a.push_back(samples[i].rss_kb), fd_a.push_back(samples[i].fds), th_a.push_back(samples[i].threads);
    }
    for (std::size_t i = samples.size() - third; i < samples.size(); ++i) {
        rss_b.push_back(samples[i].rss_kb), fd_b.push_back(samples[i].fds), th_b.push_back(samples[i].threads);
    }
    const double rss0 = median(rss_a), rss1 = median(rss_b);
    const double fd0 = median(fd_a), fd1 = median(fd_b), th0 = median(th_a), th1 = median(th_b);
    report["rss_mib"] = {{"early", rss0 / 1024}, {"late", rss1 / 1024}};
    report["fds"] = {{"early", fd0}, {"late", fd1}};
    report["threads"] = {{"early", th0}, {"late", th1}};
    if (rss1 > rss0 * (1 + o.rss_tolerance) + o.rss_slack_mb * 1024) failures.push_back("RSS grew beyond tolerance");
    if (fd1 > fd0 + o.fd_tolerance) failures.push_back("open fds grew beyond tolerance");
    if (th1 > th0 + o.thread_tolerance) failures.push_back("threads grew beyond tolerance");
}

// The JSON report; `failures` gets what failed.
nlohmann::json soakReport(const SoakOptions& o, const SoakRun& run, bool daemon_alive, const DaemonEnd& end,
                          std::vector<std::string>& failures) {
    const std::vector<Sample>& samples = run.samples();
    const SoakCounts& n = run.counts();
    nlohmann::json report;
    if (!daemon_alive) failures.push_back("navmapd exited during the run");
    if (daemon_alive && end.exit_code != 0)
        failures.push_back("navmapd exit status " + std::to_string(end.exit_code) + " after SIGTERM");
    if (samples.size() >= 6) {
        compareThirds(o, samples, report, failures);
    } else {
        failures.push_back("too few samples (run longer than 12 s)");
    }
    report["peak_rss_mib"] = end.peak_kb / 1024.0;
    if (o.max_peak_rss_mb > 0 && end.peak_kb > o.max_peak_rss_mb * 1024) {
        failures.push_back("peak RSS " + std::to_string(end.peak_kb / 1024) + " MiB over " +
                           std::to_string(static_cast<int>(o.max_peak_rss_mb)) + " MiB");
    }
    report["duration_s"] = o.duration;
    report["tolerances"] = {{"rss_fraction", o.rss_tolerance},
                            {"rss_slack_mib", o.rss_slack_mb},
                            {"fds", o.fd_tolerance},
                            {"threads", o.thread_tolerance},
                            {"max_peak_rss_mib", o.max_peak_rss_mb}};
    report["clients"] = {{"connects", n.connects},
                         {"disconnects", n.disconnects},
                         {"frames_received", n.frames_received},
                         {"stream_errors", n.stream_errors},
                         {"control_errors", n.control_errors}};
    nlohmann::json js = nlohmann::json::array();
    for (const auto& s : samples) {
        js.push_back({{"t_s", s.t_s},
                      {"rss_kib", s.rss_kb},
                      {"peak_rss_kib", s.peak_kb},
                      {"fds", s.fds},
                      {"threads", s.threads},
                      {"frame_p50_ms", s.frame_p50_ms},
                      {"frame_p99_ms", s.frame_p99_ms},
                      {"clients", s.clients}});
    }
    report["samples"] = js;
    report["failures"] = failures;
    report["passed"] = failures.empty();
    return report;
}

int runSoak(const SoakOptions& o) {
    if (::access(o.navmapd.c_str(), X_OK) != 0) {
        std::fprintf(stderr, "navmap-soak: --navmapd %s: %s\n", o.navmapd.c_str(), std::strerror(errno));
        return navmap::cli::kExitFailure;
    }
    if (::access(o.drive.c_str(), R_OK) != 0) {
        std::fprintf(stderr, "navmap-soak: --drive %s: %s\n", o.drive.c_str(), std::strerror(errno));
        return navmap::cli::kExitFailure;
    }
    const SoakPaths paths{o.work + "/control.sock", o.work + "/frames.sock"};
    const pid_t pid = startDaemon(o, paths);
    if (pid == -1) return navmap::cli::kExitFailure;
    std::printf("navmap-soak: navmapd pid %d, %.0f s, drive %s x%.0f\n", pid, o.duration, o.drive.c_str(), o.speed);

    SoakRun run(pid, paths, o.seed);
    const bool daemon_alive = run.run(o.duration);
    const DaemonEnd end = stopDaemon(pid, daemon_alive, run.samples());
    std::vector<std::string> failures;
    const nlohmann::json report = soakReport(o, run, daemon_alive, end, failures);
    std::ofstream(o.report_path) << report.dump(2) << "\n";
    std::printf("navmap-soak: %s; %llu connects, %llu frames received; report %s\n",
                failures.empty() ? "PASSED" : "FAILED", static_cast<unsigned long long>(run.counts().connects),
                static_cast<unsigned long long>(run.counts().frames_received), o.report_path.c_str());
    for (const auto& f : failures) std::printf("navmap-soak: failure: %s\n", f.c_str());
    return failures.empty() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"navmap-soak - long-running stability test of navmapd"};
    navmap::cli::setUp(app, "navmap-soak");
    SoakOptions options;
    addSoakOptions(app, options);
    if (const auto exit_status = navmap::cli::parse(app, argc, argv)) return *exit_status;
    return runSoak(options);
}
