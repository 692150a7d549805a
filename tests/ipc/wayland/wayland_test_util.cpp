// SPDX-License-Identifier: Apache-2.0
#include "wayland_test_util.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>

extern char** environ;
#include <fstream>
#include <sstream>

namespace navmap::wayland_test {

Child::Child(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env,
             const std::string& log, const std::string& cwd) {
    // Everything is prepared before fork(): the child of a threaded process only calls
    // async-signal-safe functions (dup2, chdir, execve).
    const std::string program = argv[0].find('/') != std::string::npos ? argv[0] : findOnPath(argv[0]);
    std::map<std::string, std::string> vars;
    for (char** e = environ; *e != nullptr; ++e) {
        const std::string kv = *e;
        const auto eq = kv.find('=');
        if (eq != std::string::npos) vars[kv.substr(0, eq)] = kv.substr(eq + 1);
    }
    for (const auto& [k, v] : env) {
        if (v.empty()) {
            vars.erase(k);
        } else {
            vars[k] = v;
        }
    }
    std::vector<std::string> env_strings;
    env_strings.reserve(vars.size());
    for (const auto& [k, v] : vars) env_strings.push_back(k + "=" + v);
    std::vector<char*> envp;
    envp.reserve(env_strings.size() + 1);
    for (auto& e : env_strings) envp.push_back(e.data());
    envp.push_back(nullptr);
    std::vector<std::string> arg_strings = argv;
    std::vector<char*> args;
    args.reserve(arg_strings.size() + 1);
    for (auto& a : arg_strings) args.push_back(a.data());
    args.push_back(nullptr);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    m_pid = ::fork();
    if (m_pid == 0) {
        ::setpgid(0, 0);  // a group of its own: stop() ends the program and whatever it started
        if (fd >= 0) {
            ::dup2(fd, 1);
            ::dup2(fd, 2);
        }
        if (!cwd.empty() && ::chdir(cwd.c_str()) != 0) ::_exit(126);
        ::execve(program.c_str(), args.data(), envp.data());
        ::_exit(127);
    }
    if (fd >= 0) ::close(fd);
}

Child::~Child() {
    if (m_pid > 0 && m_status == -1) stop(std::chrono::seconds(2));
}

int Child::wait(std::chrono::milliseconds timeout) {
    if (m_pid <= 0 || m_status != -1) return m_status;
    const auto end = std::chrono::steady_clock::now() + timeout;
    for (;;) {
        int st = 0;
        if (::waitpid(m_pid, &st, WNOHANG) == m_pid) {
            m_status = st;
            return m_status;
        }
        if (std::chrono::steady_clock::now() >= end) return -1;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
}

int Child::stop(std::chrono::milliseconds grace) {
    if (m_pid <= 0 || m_status != -1) return m_status;
    ::kill(-m_pid, SIGTERM);
    if (wait(grace) == -1) {
        ::kill(-m_pid, SIGKILL);
        ::waitpid(m_pid, &m_status, 0);
    }
    ::kill(-m_pid, SIGKILL);  // anything of the group left behind
    return m_status;
}

void Child::kill() {
    if (m_pid <= 0 || m_status != -1) return;
    ::kill(-m_pid, SIGKILL);
    ::waitpid(m_pid, &m_status, 0);
}

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string findOnPath(const std::string& name) {
    const char* path = std::getenv("PATH");
    std::stringstream dirs(path != nullptr ? path : "/usr/bin:/bin");
    std::string dir;
    while (std::getline(dirs, dir, ':')) {
        std::string p = dir + "/" + name;
        if (::access(p.c_str(), X_OK) == 0) return p;
    }
    return "";
}

void patternPixel(int x, int y, int tag, std::uint8_t rgb[3]) {
    rgb[0] = static_cast<std::uint8_t>(x);
    rgb[1] = static_cast<std::uint8_t>(y);
    rgb[2] = static_cast<std::uint8_t>(tag * 64 + ((x >> 8) & 7) * 8 + ((y >> 8) & 7));
}

std::vector<std::uint8_t> patternFrame(int width, int height, int tag) {
    std::vector<std::uint8_t> px(static_cast<std::size_t>(width) * height * 4);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            std::uint8_t* p = &px[(static_cast<std::size_t>(y) * width + x) * 4];
            patternPixel(x, y, tag, p);
            p[3] = 255;
        }
    }
    return px;
}

PatternServer::PatternServer(const std::string& socket_path, int tag, std::vector<ipc::RenderedProfile> rendered) {
    ipc::FrameServerOptions o;
    o.unix_path = socket_path;
    o.rendered_profiles = std::move(rendered);
    m_server = std::make_unique<ipc::FrameServer>(o);
    if (auto s = m_server->start(); !s) {
        m_error = s.message();
        return;
    }
    m_started = true;
    m_thread = std::thread([this, tag] {
        std::map<std::string, std::vector<std::uint8_t>> frames;  // by profile and size
        while (m_run) {
            for (const auto& a : m_server->activeProfiles()) {
                auto& px = frames[a.profile + "/" + std::to_string(a.width) + "x" + std::to_string(a.height)];
                if (px.empty()) px = patternFrame(a.width, a.height, tag);
                ipc::FrameView f;
                f.pixels = px.data();
                f.width = a.width;
                f.height = a.height;
                m_server->publish(a.profile, f);
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(33));
        }
    });
}

PatternServer::~PatternServer() {
    m_run = false;
    if (m_thread.joinable()) m_thread.join();
    m_server.reset();
}

}  // namespace navmap::wayland_test
