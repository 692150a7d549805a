// SPDX-License-Identifier: Apache-2.0
// navmap-ctl: sends one command to navmapd's control socket and prints the reply; `subscribe`
// prints events until interrupted (or --count events). Protocol: docs/ipc.md.
// Exit status: 0 ok, 1 an error reply or no connection, 2 usage (docs/tools.md).

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "navmap/cli/cli.h"
#include "navmap/ipc/control/control_client.h"

namespace {

int usage(const std::string& why) {
    std::cerr << "navmap-ctl: " << why << "\nRun with --help for more information.\n";
    return navmap::cli::kExitUsage;
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
    CLI::App app{"navmap-ctl: send one command to navmapd's control socket and print the reply (docs/ipc.md)"};
    navmap::cli::setUp(app, "navmap-ctl");
    const char* env = std::getenv("NAVMAP_CONTROL_SOCKET");
    std::string socket = env != nullptr && *env != '\0' ? env : "/run/navmap/control.sock";
    double timeout_s = 5.0;
    app.add_option("-s,--socket", socket,
                   "control socket (default: $NAVMAP_CONTROL_SOCKET, else /run/navmap/control.sock)");
    app.add_option("--timeout", timeout_s, "seconds to wait for the reply")
        ->capture_default_str()
        ->check(navmap::cli::finiteIn(0.1, 3600.0));
    app.require_subcommand(0, 1);
    app.fallthrough();  // --socket and --timeout may follow the command too

    app.add_subcommand("get_status", "the daemon's status (input, position, profiles, stream, memory, version)");
    app.add_subcommand("clear_route", "drop the route");
    std::vector<std::string> style_words;
    app.add_subcommand("set_style", "day, night or auto map style, land cover or orthoimage ground")
        ->add_option("STYLE", style_words, "day | night | auto and/or landcover | orthoimage")
        ->required();
    auto* set_view = app.add_subcommand("set_view", "view mode and orientation of one display");
    std::string display;
    std::vector<std::string> view_words;
    set_view->add_option("DISPLAY", display, "a profile name")->required();
    set_view->add_option("MODE", view_words, "bird | snail | auto, and/or heading-up | north-up");
    auto* set_route = app.add_subcommand("set_route", "a route as ID LAT,LON LAT,LON [...]");
    std::string route_id;
    std::vector<std::string> points;
    set_route->add_option("ID", route_id, "route id")->required();
    set_route->add_option("POINTS", points, "LAT,LON, at least two");
    auto* subscribe = app.add_subcommand(
        "subscribe",
        "print events (route_progress, position_lost, position_regained, off_route, back_on_route, gpu_reset)");
    std::optional<long long> count;
    std::vector<std::string> events;
    subscribe->add_option("--count", count, "stop after N events")->check(navmap::cli::integerIn(1, 1000000000));
    subscribe->add_option("EVENTS", events, "only these events (default: all)");
    std::string raw;
    app.add_subcommand("send", "send one raw JSON line")->add_option("JSON", raw, "the request")->required();
    if (const auto exit_status = navmap::cli::parse(app, argc, argv)) {
        return *exit_status;
    }

    if (app.get_subcommands().empty()) {
        return usage("missing COMMAND (get_status, clear_route, set_style, set_view, set_route, subscribe, send)");
    }
    const std::string cmd = app.get_subcommands().front()->get_name();
    nlohmann::ordered_json req;
    req["cmd"] = cmd;
    if (cmd == "set_style") {
        if (style_words.size() > 2) {
            return usage("set_style takes a style and/or a ground");
        }
        // The daemon checks the values and answers with the allowed ones.
        for (const auto& w : style_words) {
            req[w == "landcover" || w == "orthoimage" ? "ground" : "style"] = w;
        }
    } else if (cmd == "set_view") {
        if (view_words.empty() || view_words.size() > 2) {
            return usage("set_view needs DISPLAY and a mode and/or orientation");
        }
        req["display"] = display;
        for (const auto& w : view_words) {
            req[w.find("-up") != std::string::npos ? "orientation" : "mode"] = w;
        }
    } else if (cmd == "set_route") {
        if (points.size() < 2) {
            return usage("set_route needs ID and at least two LAT,LON points");
        }
        req["id"] = route_id;
        req["points"] = nlohmann::ordered_json::array();
        for (const auto& text : points) {
            nlohmann::ordered_json p;
            if (!parsePoint(text, p)) {
                return usage("bad point \"" + text + "\" (expected LAT,LON)");
            }
            req["points"].push_back(p);
        }
    } else if (cmd == "subscribe" && !events.empty()) {
        req["events"] = events;
    }
    const std::string line = cmd == "send" ? raw : req.dump();

    auto client = navmap::ipc::ControlClient::connect(socket);
    if (!client.ok()) {
        std::cerr << "navmap-ctl: " << client.error().message << "\n";
        return navmap::cli::kExitFailure;
    }
    const auto timeout = std::chrono::milliseconds(static_cast<long>(timeout_s * 1000.0));
    auto reply = client.value().request(line, timeout);
    if (!reply.ok()) {
        std::cerr << "navmap-ctl: " << reply.error().message << "\n";
        return navmap::cli::kExitFailure;
    }
    std::cout << reply.value() << std::endl;
    const auto j = nlohmann::json::parse(reply.value(), nullptr, false);
    const bool ok = j.is_object() && j.value("ok", false);
    if (!ok || cmd != "subscribe") {
        return ok ? navmap::cli::kExitOk : navmap::cli::kExitFailure;
    }
    for (long long n = 0; !count || n < *count; ++n) {
        auto ev = client.value().nextEvent(std::chrono::hours(24));
        if (!ev.ok()) {
            std::cerr << "navmap-ctl: " << ev.error().message << "\n";
            return navmap::cli::kExitFailure;
        }
        std::cout << ev.value() << std::endl;
    }
    return 0;
}
