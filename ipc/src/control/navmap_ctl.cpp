// navmap-ctl: sends one command to navmapd's control socket and prints the reply; `subscribe`
// prints events until interrupted (or --count events). Exit status: 0 ok, 1 error reply,
// 2 usage or connection problem. Protocol: docs/ipc.md.

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "navmap/ipc/control_client.h"

namespace {

constexpr const char* kUsage = R"(usage: navmap-ctl [--socket PATH] [--timeout S] COMMAND [ARGS]
  get_status
  clear_route
  set_style day|night
  set_view DISPLAY [bird|snail|auto] [heading-up|north-up]
  set_route ID LAT,LON LAT,LON [...]
  subscribe [--count N] [route_progress|position_lost|position_regained ...]
  send JSON                         send one raw JSON line
The socket defaults to $NAVMAP_CONTROL_SOCKET, else /run/navmap/control.sock.
)";

int usage(const std::string& why) {
    std::cerr << "navmap-ctl: " << why << "\n" << kUsage;
    return 2;
}

bool parsePoint(const std::string& s, nlohmann::ordered_json& out) {
    const auto comma = s.find(',');
    if (comma == std::string::npos) {
        return false;
    }
    char* end = nullptr;
    const double lat = std::strtod(s.c_str(), &end);
    if (end != s.c_str() + comma) {
        return false;
    }
    const char* lon_text = s.c_str() + comma + 1;
    const double lon = std::strtod(lon_text, &end);
    if (end == lon_text || *end != '\0') {
        return false;
    }
    out = nlohmann::ordered_json::array({lat, lon});
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    const char* env = std::getenv("NAVMAP_CONTROL_SOCKET");
    std::string socket = env != nullptr && *env != '\0' ? env : "/run/navmap/control.sock";
    double timeout_s = 5.0;
    std::size_t i = 0;
    for (; i < args.size(); ++i) {
        if (args[i] == "-h" || args[i] == "--help") {
            std::cout << kUsage;
            return 0;
        }
        if ((args[i] == "--socket" || args[i] == "-s") && i + 1 < args.size()) {
            socket = args[++i];
        } else if (args[i] == "--timeout" && i + 1 < args.size()) {
            timeout_s = std::atof(args[++i].c_str());
        } else {
            break;
        }
    }
    if (i >= args.size()) {
        return usage("missing COMMAND");
    }
    const std::string cmd = args[i++];
    const std::vector<std::string> rest(args.begin() + static_cast<std::ptrdiff_t>(i), args.end());
    nlohmann::ordered_json req;
    req["cmd"] = cmd;
    long count = -1;
    if (cmd == "get_status" || cmd == "clear_route") {
        if (!rest.empty()) {
            return usage(cmd + " takes no arguments");
        }
    } else if (cmd == "set_style") {
        if (rest.size() != 1) {
            return usage("set_style needs day or night");
        }
        req["style"] = rest[0];
    } else if (cmd == "set_view") {
        if (rest.empty() || rest.size() > 3) {
            return usage("set_view needs DISPLAY and a mode and/or orientation");
        }
        req["display"] = rest[0];
        for (std::size_t k = 1; k < rest.size(); ++k) {
            req[rest[k].find("-up") != std::string::npos ? "orientation" : "mode"] = rest[k];
        }
    } else if (cmd == "set_route") {
        if (rest.size() < 3) {
            return usage("set_route needs ID and at least two LAT,LON points");
        }
        req["id"] = rest[0];
        req["points"] = nlohmann::ordered_json::array();
        for (std::size_t k = 1; k < rest.size(); ++k) {
            nlohmann::ordered_json p;
            if (!parsePoint(rest[k], p)) {
                return usage("bad point \"" + rest[k] + "\" (expected LAT,LON)");
            }
            req["points"].push_back(p);
        }
    } else if (cmd == "subscribe") {
        nlohmann::ordered_json events = nlohmann::ordered_json::array();
        for (std::size_t k = 0; k < rest.size(); ++k) {
            if (rest[k] == "--count" && k + 1 < rest.size()) {
                count = std::atol(rest[++k].c_str());
            } else {
                events.push_back(rest[k]);
            }
        }
        if (!events.empty()) {
            req["events"] = events;
        }
    } else if (cmd == "send") {
        if (rest.size() != 1) {
            return usage("send needs one JSON argument");
        }
    } else {
        return usage("unknown command \"" + cmd + "\"");
    }
    const std::string line = cmd == "send" ? rest[0] : req.dump();

    auto client = navmap::ipc::ControlClient::connect(socket);
    if (!client.ok()) {
        std::cerr << "navmap-ctl: " << client.error().message << "\n";
        return 2;
    }
    const auto timeout = std::chrono::milliseconds(static_cast<long>(timeout_s * 1000.0));
    auto reply = client.value().request(line, timeout);
    if (!reply.ok()) {
        std::cerr << "navmap-ctl: " << reply.error().message << "\n";
        return 2;
    }
    std::cout << reply.value() << std::endl;
    const auto j = nlohmann::json::parse(reply.value(), nullptr, false);
    const bool ok = j.is_object() && j.value("ok", false);
    if (!ok || cmd != "subscribe") {
        return ok ? 0 : 1;
    }
    for (long n = 0; count < 0 || n < count; ++n) {
        auto ev = client.value().nextEvent(std::chrono::hours(24));
        if (!ev.ok()) {
            std::cerr << "navmap-ctl: " << ev.error().message << "\n";
            return 2;
        }
        std::cout << ev.value() << std::endl;
    }
    return 0;
}
