// SPDX-License-Identifier: Apache-2.0
// Boot to the first map frame, and the memory budget (docs/navmapd.md "Start-up"), Google
// Benchmark JSON. One repetition is one boot: navmapd is exec'd with the simulated drive and the
// three shipped profiles (cluster, hud, center: the defaults of daemon/navmapd.toml), one
// shared-memory StreamClient per profile connects as soon as the frame socket exists (as
// scripts/demo.sh's navmap-view clients do), and each profile's first frame is timed from the
// exec (posix_spawn) to its arrival in the client. The run goes on along the drive for
// NAVMAP_BOOT_SECONDS (default 20) after the exec, then the daemon's peak RSS (VmHWM from
// /proc/<pid>/status) is read and it is stopped.
//
// BM_Boot/<label>/warm: the page cache holds what the previous boot read (a priming boot runs
// first). BM_Boot/<label>/cold: before the exec, `sync; echo 3 > /proc/sys/vm/drop_caches` (as
// root), else posix_fadvise(POSIX_FADV_DONTNEED) on every file the daemon mapped in its previous
// run, its store and its data files: the label says which ("drop_caches" or "fadvise").
//
// Counters per repetition: cluster_s, hud_s, center_s (exec to first frame), all_s (the last of
// them), socket_s (exec to the frame socket's appearance), peak_rss_mb, and meets_cluster
// (cluster_s <= 1.0), meets_all (all_s <= 2.0), meets_rss (peak_rss_mb <= 160). With
// --benchmark_repetitions the medians and standard deviations follow (the _median, _stddev
// aggregates); --benchmark_enable_random_interleaving=true interleaves the binaries' runs.
//
// Environment: NAVMAP_BOOT_NAVMAPD="label=path,label=path" compares daemons (default this=<the
// build's navmapd>); NAVMAP_BOOT_SPEED (default 4, the demo's), NAVMAP_BOOT_SECONDS,
// NAVMAP_BOOT_COLD=fadvise (evict only navmap's files, not the whole page cache),
// NAVMAP_BOOT_ARGS (more navmapd arguments, split at spaces), NAVMAP_BOOT_KEEP_LOG=1 (keep the
// last boot's folder, with navmapd.log, in the temporary directory).

#include <benchmark/benchmark.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "navmap/ipc/client/stream_client.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

const char* const kProfiles[] = {"cluster", "hud", "center"};

struct Daemon {
    std::string label;
    fs::path path;
    std::set<std::string> mapped;  // regular files the previous run mapped (for fadvise eviction)
    bool primed = false;
};

struct Boot {
    std::string error;
    double socket_s = 0;
    std::map<std::string, double> first_frame_s;
    double peak_rss_mb = 0;
};

double envNumber(const char* name, double fallback) {
    const char* v = std::getenv(name);
    return v && *v ? std::atof(v) : fallback;
}

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string readFile(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

double peakRssMb(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("VmHWM:", 0) == 0) return std::atof(line.c_str() + 6) / 1024.0;
    }
    return 0;
}

std::set<std::string> mappedFiles(pid_t pid) {
    std::set<std::string> files;
    std::ifstream in("/proc/" + std::to_string(pid) + "/maps");
    for (std::string line; std::getline(in, line);) {
        const auto slash = line.find(" /");
        if (slash == std::string::npos) continue;
        std::string f = line.substr(slash + 1);
        if (f.rfind("/dev/", 0) == 0 || f.find(" (deleted)") != std::string::npos) continue;
        files.insert(f);
    }
    return files;
}

void evict(const fs::path& file) {
    const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return;
    ::fdatasync(fd);
    ::posix_fadvise(fd, 0, 0, POSIX_FADV_DONTNEED);
    ::close(fd);
}

// Empties the page cache of what a boot reads; returns how ("drop_caches" or "fadvise").
std::string dropCaches(const Daemon& d) {
    const char* how = std::getenv("NAVMAP_BOOT_COLD");
    if (!how || std::string(how) != "fadvise") {
        ::sync();
        if (std::FILE* f = std::fopen("/proc/sys/vm/drop_caches", "w")) {
            const bool ok = std::fputs("3\n", f) >= 0;
            if (std::fclose(f) == 0 && ok) return "drop_caches";
        }
    }
    for (const auto& f : d.mapped) evict(f);
    evict(d.path);
    const fs::path share = d.path.parent_path().parent_path() / "share" / "navmap";
    std::error_code ec;
    for (const auto& e : fs::recursive_directory_iterator(share, ec)) {
        if (e.is_regular_file(ec)) evict(e.path());
    }
    return "fadvise";
}

Boot boot(Daemon& d, double run_s) {
    Boot r;
    const fs::path dir = fs::temp_directory_path() / ("navmap-boot-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string sock = (dir / "frames.sock").string(), control = (dir / "control.sock").string(),
                      log = (dir / "navmapd.log").string(), speed = std::to_string(envNumber("NAVMAP_BOOT_SPEED", 4));
    std::vector<std::string> args = {d.path.string(), "--input",        "sim", "--speed",     speed, "--control-socket",
                                     control,         "--frame-socket", sock,  "--http-port", "0"};
    bool log_level = false;
    if (const char* extra = std::getenv("NAVMAP_BOOT_ARGS")) {  // e.g. "--shader-cache /var/tmp/x"
        std::stringstream words(extra);
        for (std::string w; words >> w;) {
            log_level = log_level || w == "--log-level";
            args.push_back(w);
        }
    }
    if (!log_level) args.insert(args.end(), {"--log-level", "info"});
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);

    std::atomic<bool> running{true};
    std::map<std::string, double> first;  // written by one thread each, read after the join
    std::map<std::string, std::string> errors;
    for (const char* p : kProfiles) first[p] = -1, errors[p];
    pid_t pid = -1;
    const Clock::time_point t0 = Clock::now();
    if (posix_spawn(&pid, d.path.c_str(), &actions, nullptr, argv.data(), environ) != 0) {
        posix_spawn_file_actions_destroy(&actions);
        r.error = "posix_spawn(" + d.path.string() + ") failed";
        return r;
    }
    posix_spawn_file_actions_destroy(&actions);
    std::atomic<double> socket_s{-1};
    std::vector<std::thread> clients;
    for (const char* name : kProfiles) {
        clients.emplace_back([&, name] {
            // As a display process would: poll for the socket, connect, wait for the first frame.
            std::unique_ptr<navmap::ipc::StreamClient> client;
            while (running && secondsSince(t0) < run_s) {
                struct stat st {};
                if (::stat(sock.c_str(), &st) == 0) {
                    double none = -1;
                    socket_s.compare_exchange_strong(none, secondsSince(t0));
                    navmap::ipc::StreamRequest req;
                    req.profile = *navmap::ipc::defaultStreamProfile(name);
                    auto c = navmap::ipc::StreamClient::connectUnix(sock, req);
                    if (c) {
                        client = std::move(c.value());
                        break;
                    }
                    errors[name] = c.error().message;
                }
                std::this_thread::sleep_for(1ms);
            }
            navmap::ipc::ReceivedFrame f;
            while (client && running) {
                auto got = client->next(f, 50ms);
                if (!got) {
                    errors[name] = got.error().message;
                    return;
                }
                if (got.value() && first[name] < 0) first[name] = secondsSince(t0);
            }
        });
    }
    while (secondsSince(t0) < run_s) {
        if (::waitpid(pid, nullptr, WNOHANG) == pid) {
            pid = -1;
            break;
        }
        std::this_thread::sleep_for(20ms);
    }
    if (pid > 0) {
        r.peak_rss_mb = peakRssMb(pid);
        d.mapped = mappedFiles(pid);
    }
    running = false;
    for (auto& t : clients) t.join();
    if (pid > 0) {
        ::kill(pid, SIGTERM);
        ::waitpid(pid, nullptr, 0);
    } else {
        r.error = "navmapd exited early: " + readFile(log);
    }
    r.socket_s = socket_s;
    for (const char* p : kProfiles) {
        if (first[p] < 0 && r.error.empty())
            r.error = std::string("no frame for ") + p + " within " + std::to_string(run_s) + " s: " + errors[p] +
                      " (log " + log + ")";
    }
    r.first_frame_s = first;
    if (r.error.empty() && !std::getenv("NAVMAP_BOOT_KEEP_LOG")) fs::remove_all(dir);
    return r;
}

void BM_Boot(benchmark::State& state, Daemon* d, bool cold) {
    const double run_s = envNumber("NAVMAP_BOOT_SECONDS", 20);
    if (!d->primed) {
        (void)boot(*d, 6);  // loads what a warm boot finds in the page cache; learns the mapped files
        d->primed = true;
    }
    std::string how = "warm";
    Boot r;
    for (auto _ : state) {
        if (cold) how = "cold (" + dropCaches(*d) + ")";
        r = boot(*d, run_s);
        state.SetIterationTime(r.first_frame_s.empty() ? 0 : r.first_frame_s["cluster"]);
    }
    if (!r.error.empty()) {
        state.SkipWithError(r.error.c_str());
        return;
    }
    double all = 0;
    for (const auto& [name, s] : r.first_frame_s) {
        state.counters[name + "_s"] = s;
        all = std::max(all, s);
    }
    state.counters["all_s"] = all;
    state.counters["socket_s"] = r.socket_s;
    state.counters["peak_rss_mb"] = r.peak_rss_mb;
    state.counters["meets_cluster"] = r.first_frame_s["cluster"] <= 1.0 ? 1 : 0;
    state.counters["meets_all"] = all <= 2.0 ? 1 : 0;
    state.counters["meets_rss"] = r.peak_rss_mb <= 160.0 ? 1 : 0;
    state.SetLabel(d->label + ", " + how + ", 3 profiles, sim drive");
}

std::vector<std::unique_ptr<Daemon>>& daemons() {
    static std::vector<std::unique_ptr<Daemon>> list;
    return list;
}

}  // namespace

int main(int argc, char** argv) {
    const char* env = std::getenv("NAVMAP_BOOT_NAVMAPD");
    std::string spec = env && *env ? env : std::string("this=") + NAVMAPD_PATH;
    std::stringstream in(spec);
    for (std::string item; std::getline(in, item, ',');) {
        const auto eq = item.find('=');
        auto d = std::make_unique<Daemon>();
        d->label = eq == std::string::npos ? item : item.substr(0, eq);
        d->path = eq == std::string::npos ? item : item.substr(eq + 1);
        daemons().push_back(std::move(d));
    }
    for (const auto& d : daemons()) {
        for (const bool cold : {false, true}) {
            benchmark::RegisterBenchmark(("BM_Boot/" + d->label + (cold ? "/cold" : "/warm")).c_str(), BM_Boot, d.get(),
                                         cold)
                ->Iterations(1)
                ->UseManualTime()
                ->Unit(benchmark::kMillisecond);
        }
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
