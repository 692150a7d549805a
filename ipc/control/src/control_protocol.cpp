// SPDX-License-Identifier: Apache-2.0
// JSON-lines control protocol: validation of requests and formatting of replies/events.
// Every check names the offending member so a client developer can fix the request from the
// reply alone (docs/ipc.md lists the messages).

#include "navmap/ipc/control/control_protocol.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <unordered_set>
#include <utility>
#include <vector>

namespace navmap::ipc {

namespace {

using nlohmann::json;

constexpr std::size_t kMaxDepth = 32;

// Replies and events keep the member order of docs/ipc.md ("ok"/"event" first).
using Ojson = nlohmann::ordered_json;

template <typename J>
std::string dumpJson(const J& j) {
    return j.dump(-1, ' ', false, J::error_handler_t::replace);
}

// Quoted, shortened copy of client text for error messages.
std::string quote(std::string_view s) {
    constexpr std::size_t kMax = 64;
    std::string out = "\"";
    out.append(s.substr(0, kMax));
    if (s.size() > kMax) {
        out.append("...");
    }
    out.push_back('"');
    return out;
}

std::string typeName(const json& j) { return j.type_name(); }

std::string number(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

// Bracket depth outside strings: the parser below keeps its own stack, but refusing absurd
// nesting first bounds memory and the work of destroying the value.
bool depthWithin(std::string_view s, std::size_t max_depth) {
    std::size_t depth = 0;
    bool in_string = false;
    bool escaped = false;
    for (const char c : s) {
        if (in_string) {
            if (escaped) {
                escaped = false;
            } else if (c == '\\') {
                escaped = true;
            } else if (c == '"') {
                in_string = false;
            }
            continue;
        }
        if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > max_depth) {
                return false;
            }
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return true;
}

// Finds the first object key that appears twice in its object, at any depth, with the path to
// that object (`maneuvers[1]`), through nlohmann's parser callback: the library keeps only the
// last of duplicate keys, so `{"cmd":"get_status","cmd":"clear_route"}` would silently become
// the second command. Keys are compared as parsed (after unescaping).
class DuplicateKeyFinder {
public:
    bool operator()(int /*depth*/, json::parse_event_t event, json& parsed) {
        switch (event) {
            case json::parse_event_t::object_start: m_stack.push_back(Frame{true, {}, 0, {}}); break;
            case json::parse_event_t::array_start: m_stack.push_back(Frame{false, {}, 0, {}}); break;
            case json::parse_event_t::key:
                if (!m_stack.empty() && parsed.is_string()) {
                    Frame& top = m_stack.back();
                    top.key = parsed.get_ref<const std::string&>();
                    if (!top.keys.insert(top.key).second && !m_found) {
                        m_found = true;
                        m_key = top.key;
                        m_at_root = m_stack.size() == 1;
                        m_path = pathToTop();
                    }
                }
                break;
            case json::parse_event_t::object_end:
            case json::parse_event_t::array_end:
                if (!m_stack.empty()) {
                    m_stack.pop_back();
                }
                elementDone();
                break;
            case json::parse_event_t::value: elementDone(); break;
        }
        return true;
    }

    [[nodiscard]] bool found() const { return m_found; }
    [[nodiscard]] const std::string& key() const { return m_key; }
    [[nodiscard]] bool atRoot() const { return m_at_root; }
    [[nodiscard]] std::string message() const {
        return (m_path.empty() ? std::string() : m_path + ": ") + "duplicate key " + quote(m_key);
    }

private:
    struct Frame {
        bool object;
        std::string key;    // object: the member being read
        std::size_t index;  // array: the element being read
        std::unordered_set<std::string> keys;
    };
    void elementDone() {
        if (!m_stack.empty() && !m_stack.back().object) {
            ++m_stack.back().index;
        }
    }
    // Path of the innermost object, as the validation messages write it: points[3], maneuvers[0].text.
    [[nodiscard]] std::string pathToTop() const {
        std::string path;
        for (std::size_t i = 0; i + 1 < m_stack.size(); ++i) {
            const Frame& f = m_stack[i];
            if (f.object) {
                path += (path.empty() ? "" : ".") + f.key;
            } else {
                path += "[" + std::to_string(f.index) + "]";
            }
        }
        return path;
    }

    std::vector<Frame> m_stack;
    bool m_found = false;
    bool m_at_root = false;
    std::string m_key;
    std::string m_path;
};

struct Checker {
    const json& obj;
    std::string error;

    bool allowOnly(std::initializer_list<const char*> names) {
        for (const auto& [key, value] : obj.items()) {
            bool known = false;
            for (const char* n : names) {
                known = known || key == n;
            }
            if (!known) {
                error = "unknown field " + quote(key);
                return false;
            }
        }
        return true;
    }

    // Reads an optional string member; false (with error) when present but wrong.
    bool string(const char* name, std::optional<std::string>& out, std::size_t max_bytes, bool required) {
        const auto it = obj.find(name);
        if (it == obj.end()) {
            if (required) {
                error = std::string("missing \"") + name + "\"";
                return false;
            }
            return true;
        }
        if (!it->is_string()) {
            error = std::string("\"") + name + "\" must be a string, not " + typeName(*it);
            return false;
        }
        const auto& s = it->get_ref<const std::string&>();
        if (s.empty()) {
            error = std::string("\"") + name + "\" must not be empty";
            return false;
        }
        if (s.size() > max_bytes) {
            error = std::string("\"") + name + "\" longer than " + std::to_string(max_bytes) + " bytes";
            return false;
        }
        out = s;
        return true;
    }
};

template <typename T, std::size_t N>
std::optional<T> enumFrom(const json& j, const std::array<std::pair<T, const char*>, N>& names) {
    if (!j.is_string()) {
        return std::nullopt;
    }
    const auto& s = j.get_ref<const std::string&>();
    for (const auto& [value, name] : names) {
        if (s == name) {
            return value;
        }
    }
    return std::nullopt;
}

constexpr std::array<std::pair<ViewMode, const char*>, 3> kModeNames{
    {{ViewMode::Bird, "bird"}, {ViewMode::Snail, "snail"}, {ViewMode::Auto, "auto"}}};
constexpr std::array<std::pair<ViewOrientation, const char*>, 2> kOrientationNames{
    {{ViewOrientation::HeadingUp, "heading-up"}, {ViewOrientation::NorthUp, "north-up"}}};
constexpr std::array<std::pair<MapStyle, const char*>, 3> kStyleNames{
    {{MapStyle::Day, "day"}, {MapStyle::Night, "night"}, {MapStyle::Auto, "auto"}}};
constexpr std::array<std::pair<Ground, const char*>, 2> kGroundNames{
    {{Ground::LandCover, "landcover"}, {Ground::Orthoimage, "orthoimage"}}};
constexpr std::array<std::pair<ControlEventKind, const char*>, 6> kEventNames{
    {{ControlEventKind::RouteProgress, "route_progress"},
     {ControlEventKind::PositionLost, "position_lost"},
     {ControlEventKind::PositionRegained, "position_regained"},
     {ControlEventKind::OffRoute, "off_route"},
     {ControlEventKind::BackOnRoute, "back_on_route"},
     {ControlEventKind::GpuReset, "gpu_reset"}}};

template <typename T, std::size_t N>
std::string choices(const std::array<std::pair<T, const char*>, N>& names) {
    std::string out;
    for (const auto& [value, name] : names) {
        out += out.empty() ? "" : " | ";
        out += name;
    }
    return out;
}

std::string parseRoute(const json& obj, const ControlLimits& limits, SetRouteCommand& out) {
    Checker c{obj, {}};
    if (!c.allowOnly({"cmd", "id", "points", "maneuvers"})) {
        return c.error;
    }
    std::optional<std::string> id;
    if (!c.string("id", id, limits.max_string_bytes, true)) {
        return c.error;
    }
    out.route_id = *id;
    const auto pts = obj.find("points");
    if (pts == obj.end()) {
        return "missing \"points\"";
    }
    if (!pts->is_array()) {
        return "\"points\" must be an array of [lat, lon], not " + typeName(*pts);
    }
    if (pts->size() < 2) {
        return "\"points\" needs at least 2 points, got " + std::to_string(pts->size());
    }
    if (pts->size() > limits.max_route_points) {
        return "\"points\" has " + std::to_string(pts->size()) + " points, more than the limit of " +
               std::to_string(limits.max_route_points);
    }
    out.points.reserve(pts->size());
    for (std::size_t i = 0; i < pts->size(); ++i) {
        const json& p = (*pts)[i];
        const std::string where = "points[" + std::to_string(i) + "]";
        if (!p.is_array() || p.size() != 2) {
            return where + ": must be [lat, lon]";
        }
        if (!p[0].is_number() || !p[1].is_number()) {
            return where + ": latitude and longitude must be numbers";
        }
        const double lat = p[0].get<double>();
        const double lon = p[1].get<double>();
        if (!std::isfinite(lat) || lat < -90.0 || lat > 90.0) {
            return where + ": latitude " + number(lat) + " out of range [-90, 90]";
        }
        if (!std::isfinite(lon) || lon < -180.0 || lon > 180.0) {
            return where + ": longitude " + number(lon) + " out of range [-180, 180]";
        }
        out.points.push_back({lat, lon});
    }
    const auto man = obj.find("maneuvers");
    if (man == obj.end()) {
        return {};
    }
    if (!man->is_array()) {
        return "\"maneuvers\" must be an array, not " + typeName(*man);
    }
    if (man->size() > limits.max_maneuvers) {
        return "\"maneuvers\" has " + std::to_string(man->size()) + " entries, more than the limit of " +
               std::to_string(limits.max_maneuvers);
    }
    for (std::size_t i = 0; i < man->size(); ++i) {
        const json& m = (*man)[i];
        const std::string where = "maneuvers[" + std::to_string(i) + "]";
        if (!m.is_object()) {
            return where + ": must be an object";
        }
        Checker mc{m, {}};
        if (!mc.allowOnly({"index", "end_index", "type", "text", "exit"})) {
            return where + ": " + mc.error;
        }
        Maneuver mv;
        const auto idx = m.find("index");
        if (idx == m.end()) {
            return where + ": missing \"index\"";
        }
        if (!idx->is_number_integer()) {
            return where + ".index: must be an integer";
        }
        if (idx->is_number_unsigned() ? idx->get<std::uint64_t>() >= out.points.size()
                                      : (idx->get<std::int64_t>() < 0 ||
                                         idx->get<std::int64_t>() >= static_cast<std::int64_t>(out.points.size()))) {
            return where + ".index: " + idx->dump() + " out of range [0, " + std::to_string(out.points.size() - 1) +
                   "]";
        }
        mv.index = idx->get<std::size_t>();
        if (!out.maneuvers.empty() && mv.index < out.maneuvers.back().index) {
            return where + ".index: " + std::to_string(mv.index) + " is before the previous maneuver's index " +
                   std::to_string(out.maneuvers.back().index);
        }
        const auto type = m.find("type");
        if (type == m.end()) {
            return where + ": missing \"type\"";
        }
        const auto t = enumFrom(*type, kManeuverTypeNames);
        if (!t) {
            return where + ".type: " +
                   (type->is_string() ? "unknown maneuver " + quote(type->get_ref<const std::string&>())
                                      : "must be a string") +
                   " (expected one of " + choices(kManeuverTypeNames) + ")";
        }
        mv.type = *t;
        const auto text = m.find("text");
        if (text != m.end()) {
            if (!text->is_string()) {
                return where + ".text: must be a string";
            }
            if (text->get_ref<const std::string&>().size() > limits.max_string_bytes) {
                return where + ".text: longer than " + std::to_string(limits.max_string_bytes) + " bytes";
            }
            mv.text = text->get<std::string>();
        }
        const auto exit = m.find("exit");
        if (exit != m.end()) {
            if (mv.type != ManeuverType::Roundabout) {
                return where + ".exit: only a roundabout maneuver has an exit number, not " +
                       quote(maneuverTypeName(mv.type));
            }
            if (!exit->is_number_integer()) {
                return where + ".exit: must be an integer";
            }
            const bool in_range =
                exit->is_number_unsigned()
                    ? exit->get<std::uint64_t>() >= 1 && exit->get<std::uint64_t>() <= kMaxRoundaboutExit
                    : exit->get<std::int64_t>() >= 1 && exit->get<std::int64_t>() <= kMaxRoundaboutExit;
            if (!in_range) {
                return where + ".exit: " + exit->dump() + " out of range [1, " + std::to_string(kMaxRoundaboutExit) +
                       "]";
            }
            mv.exit_number = exit->get<std::uint32_t>();
        }
        const auto end = m.find("end_index");
        if (end != m.end()) {
            if (!end->is_number_integer()) {
                return where + ".end_index: must be an integer";
            }
            const bool in_range =
                end->is_number_unsigned()
                    ? end->get<std::uint64_t>() >= mv.index && end->get<std::uint64_t>() < out.points.size()
                    : end->get<std::int64_t>() >= static_cast<std::int64_t>(mv.index) &&
                          end->get<std::int64_t>() < static_cast<std::int64_t>(out.points.size());
            if (!in_range) {
                return where + ".end_index: " + end->dump() + " out of range [" + std::to_string(mv.index) + ", " +
                       std::to_string(out.points.size() - 1) + "]";
            }
            mv.end_index = end->get<std::size_t>();
        }
        out.maneuvers.push_back(std::move(mv));
    }
    return {};
}

template <typename T, std::size_t N>
std::string readEnum(const json& obj, const char* name, const std::array<std::pair<T, const char*>, N>& names,
                     std::optional<T>& out) {
    const auto it = obj.find(name);
    if (it == obj.end()) {
        return {};
    }
    out = enumFrom(*it, names);
    if (!out) {
        return std::string("\"") + name + "\": " +
               (it->is_string() ? quote(it->get_ref<const std::string&>()) + " is not one of " : "must be one of ") +
               choices(names);
    }
    return {};
}

// set_view's "camera": {zoom, pitch[, bearing]} (MapLibre GL JS convention) or null.
std::string readViewCamera(const json& obj, SetViewCommand& out) {
    const auto it = obj.find("camera");
    if (it == obj.end()) {
        return {};
    }
    if (it->is_null()) {
        out.clear_camera = true;
        return {};
    }
    if (!it->is_object()) {
        return "\"camera\" must be an object {zoom, pitch[, bearing]} or null, not " + typeName(*it);
    }
    Checker c{*it, {}};
    if (!c.allowOnly({"zoom", "pitch", "bearing"})) {
        return "camera: " + c.error;
    }
    ViewCamera camera;
    const auto member = [&](const char* name, double lo, double hi, bool required,
                            std::optional<double>& value) -> std::string {
        const auto m = it->find(name);
        if (m == it->end()) {
            return required ? std::string("camera: missing \"") + name + "\"" : std::string();
        }
        if (!m->is_number()) {
            return std::string("camera.") + name + ": must be a number, not " + typeName(*m);
        }
        const double v = m->get<double>();
        if (!std::isfinite(v) || v < lo || v > hi) {
            return std::string("camera.") + name + ": " + number(v) + " out of range [" + number(lo) + ", " +
                   number(hi) + "]";
        }
        value = v;
        return {};
    };
    std::optional<double> zoom, pitch_deg;
    std::string error = member("zoom", 0.0, kViewCameraMaxZoom, true, zoom);
    if (error.empty()) {
        error = member("pitch", 0.0, kViewCameraMaxPitchDeg, true, pitch_deg);
    }
    if (error.empty()) {
        error = member("bearing", -kViewCameraMaxBearingDeg, kViewCameraMaxBearingDeg, false, camera.bearing_deg);
    }
    if (!error.empty()) {
        return error;
    }
    camera.zoom = *zoom;
    camera.pitch_deg = *pitch_deg;
    out.camera = camera;
    return {};
}

}  // namespace

const char* viewModeName(ViewMode m) noexcept { return kModeNames[static_cast<std::size_t>(m)].second; }
const char* viewOrientationName(ViewOrientation o) noexcept {
    return kOrientationNames[static_cast<std::size_t>(o)].second;
}
const char* mapStyleName(MapStyle s) noexcept { return kStyleNames[static_cast<std::size_t>(s)].second; }
const char* groundName(Ground g) noexcept { return kGroundNames[static_cast<std::size_t>(g)].second; }
const char* controlEventName(ControlEventKind k) noexcept {
    for (const auto& [value, name] : kEventNames) {
        if (value == k) {
            return name;
        }
    }
    return "route_progress";
}

ControlParse parseControlLine(std::string_view line, const ControlLimits& limits) {
    ControlParse r;
    if (line.size() > limits.max_line_bytes) {
        r.error = "line longer than " + std::to_string(limits.max_line_bytes) + " bytes";
        return r;
    }
    if (!depthWithin(line, kMaxDepth)) {
        r.error = "JSON nested deeper than " + std::to_string(kMaxDepth) + " levels";
        return r;
    }
    json obj;
    DuplicateKeyFinder duplicates;
    try {
        obj = json::parse(line.begin(), line.end(), std::ref(duplicates));
    } catch (const json::exception& e) {
        // nlohmann's messages start with "[json.exception.parse_error.101] "; keep the rest.
        std::string what = e.what();
        const auto pos = what.find("] ");
        r.error = "invalid JSON: " + (pos == std::string::npos ? what : what.substr(pos + 2));
        return r;
    }
    if (!obj.is_object()) {
        r.error = "request must be a JSON object, not " + typeName(obj);
        return r;
    }
    const auto cmd = obj.find("cmd");
    if (cmd != obj.end() && cmd->is_string() && cmd->get_ref<const std::string&>().size() <= limits.max_string_bytes) {
        r.cmd = cmd->get<std::string>();
    }
    const auto id = obj.find("id");
    if (id != obj.end() && id->is_string() && !id->get_ref<const std::string&>().empty() &&
        id->get_ref<const std::string&>().size() <= limits.max_string_bytes) {
        r.id = id->get<std::string>();
    }
    if (duplicates.found()) {
        // Which of the two values was meant cannot be known: nothing is applied, and a duplicated
        // "cmd" or "id" is not echoed either.
        if (duplicates.atRoot() && duplicates.key() == "cmd") {
            r.cmd.clear();
        }
        if (duplicates.atRoot() && duplicates.key() == "id") {
            r.id.reset();
        }
        r.error = duplicates.message();
        return r;
    }
    if (cmd == obj.end()) {
        r.error = "missing \"cmd\"";
        return r;
    }
    if (!cmd->is_string()) {
        r.error = "\"cmd\" must be a string, not " + typeName(*cmd);
        return r;
    }
    const std::string& name = cmd->get_ref<const std::string&>();
    ControlCommand command;
    command.cmd = r.cmd;
    Checker c{obj, {}};
    std::optional<std::string> request_id;
    const auto need_id = [&]() { return c.string("id", request_id, limits.max_string_bytes, false); };
    if (name == "set_route") {
        SetRouteCommand route;
        r.error = parseRoute(obj, limits, route);
        command.request_id = route.route_id.empty() ? std::nullopt : std::optional<std::string>(route.route_id);
        command.body = std::move(route);
    } else if (name == "clear_route" || name == "get_status") {
        if (!c.allowOnly({"cmd", "id"}) || !need_id()) {
            r.error = c.error;
        }
        command.body = name == "clear_route" ? ControlCommandBody(ClearRouteCommand{}) : GetStatusCommand{};
    } else if (name == "set_view") {
        SetViewCommand view;
        std::optional<std::string> display;
        if (!c.allowOnly({"cmd", "id", "display", "mode", "orientation", "camera"}) || !need_id() ||
            !c.string("display", display, limits.max_string_bytes, true)) {
            r.error = c.error;
        } else {
            view.display = *display;
            r.error = readEnum(obj, "mode", kModeNames, view.mode);
            if (r.error.empty()) {
                r.error = readEnum(obj, "orientation", kOrientationNames, view.orientation);
            }
            if (r.error.empty()) {
                r.error = readViewCamera(obj, view);
            }
            if (r.error.empty() && !view.mode && !view.orientation && !view.camera && !view.clear_camera) {
                r.error = "set_view needs \"mode\" (" + choices(kModeNames) + "), \"orientation\" (" +
                          choices(kOrientationNames) + ") or \"camera\" ({zoom, pitch[, bearing]} or null)";
            }
        }
        command.body = std::move(view);
    } else if (name == "set_style") {
        SetStyleCommand style;
        if (!c.allowOnly({"cmd", "id", "style", "ground"}) || !need_id()) {
            r.error = c.error;
        } else if (!obj.contains("style") && !obj.contains("ground")) {
            r.error = "set_style needs \"style\" (" + choices(kStyleNames) + ") or \"ground\" (" +
                      choices(kGroundNames) + ")";
        } else {
            r.error = readEnum(obj, "style", kStyleNames, style.style);
            if (r.error.empty()) r.error = readEnum(obj, "ground", kGroundNames, style.ground);
        }
        command.body = style;
    } else if (name == "subscribe") {
        SubscribeCommand sub;
        if (!c.allowOnly({"cmd", "id", "events"}) || !need_id()) {
            r.error = c.error;
        } else if (const auto ev = obj.find("events"); ev != obj.end()) {
            if (!ev->is_array() || ev->empty()) {
                r.error = "\"events\" must be a non-empty array of " + choices(kEventNames);
            } else {
                sub.events = 0;
                for (std::size_t i = 0; i < ev->size() && r.error.empty(); ++i) {
                    const auto k = enumFrom((*ev)[i], kEventNames);
                    if (!k) {
                        r.error = "events[" + std::to_string(i) + "]: not one of " + choices(kEventNames);
                    } else {
                        sub.events = static_cast<std::uint8_t>(sub.events | static_cast<std::uint8_t>(*k));
                    }
                }
            }
        }
        command.body = sub;
    } else {
        r.error = "unknown cmd " + quote(name) +
                  " (expected set_route | clear_route | set_view | set_style | get_status | subscribe)";
        return r;
    }
    if (!r.error.empty()) {
        return r;
    }
    if (!std::holds_alternative<SetRouteCommand>(command.body)) {
        command.request_id = request_id;
    }
    r.command = std::move(command);
    return r;
}

std::string controlOkReply(std::string_view cmd, const std::optional<std::string>& id, const nlohmann::json& extra) {
    Ojson j = Ojson::object();
    j["ok"] = true;
    j["cmd"] = std::string(cmd);
    if (id) {
        j["id"] = *id;
    }
    if (extra.is_object()) {
        for (const auto& [key, value] : extra.items()) {
            j[key] = Ojson(value);
        }
    }
    return dumpJson(j);
}

std::string controlErrorReply(std::string_view cmd, const std::optional<std::string>& id, std::string_view error) {
    Ojson j = Ojson::object();
    j["ok"] = false;
    if (!cmd.empty()) {
        j["cmd"] = std::string(cmd);
    }
    if (id) {
        j["id"] = *id;
    }
    j["error"] = std::string(error);
    return dumpJson(j);
}

std::string controlEventLine(const ControlEvent& event) {
    Ojson j = Ojson::object();
    j["event"] = controlEventName(event.kind);
    switch (event.kind) {
        case ControlEventKind::RouteProgress:
            j["id"] = event.route_id;
            j["driven_m"] = std::round(event.driven_m * 10.0) / 10.0;
            j["remaining_m"] = std::round(event.remaining_m * 10.0) / 10.0;
            break;
        case ControlEventKind::PositionLost: j["since_s"] = std::round(event.since_s * 100.0) / 100.0; break;
        case ControlEventKind::PositionRegained: break;
        case ControlEventKind::OffRoute:
            j["id"] = event.route_id;
            j["offset_m"] = std::round(event.offset_m * 10.0) / 10.0;
            break;
        case ControlEventKind::BackOnRoute: j["id"] = event.route_id; break;
        case ControlEventKind::GpuReset: j["resets"] = event.resets; break;
    }
    return dumpJson(j);
}

}  // namespace navmap::ipc
