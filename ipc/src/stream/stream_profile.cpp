// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/stream_profile.h"

#include <nlohmann/json.hpp>

namespace navmap::ipc {
namespace {

bool knownView(std::string_view v) { return v == "bird" || v == "snail" || v == "hud"; }

// Reads an integer member in [lo, hi]; absent keeps *out.
Status readInt(const nlohmann::json& j, const char* key, int lo, int hi, int* out) {
    const auto it = j.find(key);
    if (it == j.end()) {
        return {};
    }
    if (!it->is_number_integer()) {
        return Error{std::string("handshake: \"") + key + "\" must be an integer"};
    }
    const auto v = it->get<std::int64_t>();
    if (v < lo || v > hi) {
        return Error{std::string("handshake: \"") + key + "\" = " + std::to_string(v) + " outside [" +
                     std::to_string(lo) + ", " + std::to_string(hi) + "]"};
    }
    *out = static_cast<int>(v);
    return {};
}

Result<std::string> readString(const nlohmann::json& j, const char* key, std::size_t max_len) {
    const auto it = j.find(key);
    if (it == j.end()) {
        return std::string();
    }
    if (!it->is_string()) {
        return Error{std::string("handshake: \"") + key + "\" must be a string"};
    }
    std::string s = it->get<std::string>();
    if (s.empty() || s.size() > max_len) {
        return Error{std::string("handshake: \"") + key + "\" must have 1.." + std::to_string(max_len) + " characters"};
    }
    return s;
}

}  // namespace

std::optional<StreamProfile> defaultStreamProfile(std::string_view name) {
    StreamProfile p;
    p.name = std::string(name);
    if (name == "cluster") {
        p.width = 1280, p.height = 480, p.view = "snail";
    } else if (name == "hud") {
        p.width = 800, p.height = 240, p.view = "hud";
    } else if (name == "center") {
        p.width = 1280, p.height = 720, p.view = "bird";
    } else {
        return std::nullopt;
    }
    return p;
}

const char* streamPayloadName(StreamPayload payload) noexcept {
    switch (payload) {
        case StreamPayload::Shm: return "shm";
        case StreamPayload::Raw: return "raw";
        case StreamPayload::Zlib: return "zlib";
    }
    return "unknown";
}

Result<StreamRequest> parseStreamRequest(std::string_view line) {
    if (line.size() > kMaxHandshakeBytes) {
        return Error{"handshake: longer than " + std::to_string(kMaxHandshakeBytes) + " bytes"};
    }
    if (!line.empty() && line.back() == '\n') {
        line.remove_suffix(1);
    }
    if (!line.empty() && line.back() == '\r') {
        line.remove_suffix(1);
    }
    const auto j = nlohmann::json::parse(line.begin(), line.end(), nullptr, false);
    if (j.is_discarded()) {
        return Error{"handshake: not a JSON line"};
    }
    if (!j.is_object()) {
        return Error{"handshake: expected a JSON object"};
    }
    static const char* const kKeys[] = {"version", "profile", "width",   "height", "fps",
                                        "view",    "format",  "payload", "hold"};
    for (const auto& item : j.items()) {
        bool known = false;
        for (const char* k : kKeys) {
            known = known || item.key() == k;
        }
        if (!known) {
            std::string key = item.key().substr(0, 64);
            for (char& c : key) {
                if (static_cast<unsigned char>(c) < 0x20 || c == '"' || c == '\\' ||
                    static_cast<unsigned char>(c) >= 0x7F) {
                    c = '?';
                }
            }
            return Error{"handshake: unknown key \"" + key + "\""};
        }
    }
    int version = 0;
    if (auto s = readInt(j, "version", 1, 1000, &version); !s) {
        return Error{s.message()};
    }
    if (version == 0) {
        return Error{"handshake: \"version\" missing"};
    }
    if (version != 1) {
        return Error{"handshake: unsupported version " + std::to_string(version) + " (server speaks 1)"};
    }
    StreamRequest req;
    auto name = readString(j, "profile", 64);
    if (!name) {
        return name.error();
    }
    const bool named = !name.value().empty();
    if (named) {
        if (auto d = defaultStreamProfile(name.value())) {
            req.profile = *d;
        } else {
            req.profile.name = name.value();
            if (!j.contains("width") || !j.contains("height") || !j.contains("view")) {
                return Error{"handshake: profile \"" + std::string(name.value().substr(0, 64)) +
                             "\" is not a default (cluster, hud, center); give width, height and view"};
            }
        }
    } else if (!j.contains("width") || !j.contains("height") || !j.contains("view")) {
        return Error{"handshake: give \"profile\" or width, height and view"};
    }
    for (const char c : req.profile.name) {
        if (static_cast<unsigned char>(c) < 0x20 || c == '"' || c == '\\' || static_cast<unsigned char>(c) >= 0x7F) {
            return Error{"handshake: \"profile\" must be printable ASCII"};
        }
    }
    if (auto s = readInt(j, "width", kMinStreamDimension, kMaxStreamDimension, &req.profile.width); !s) {
        return Error{s.message()};
    }
    if (auto s = readInt(j, "height", kMinStreamDimension, kMaxStreamDimension, &req.profile.height); !s) {
        return Error{s.message()};
    }
    if (auto s = readInt(j, "fps", 0, kMaxStreamFps, &req.profile.fps); !s) {
        return Error{s.message()};
    }
    auto view = readString(j, "view", 16);
    if (!view) {
        return view.error();
    }
    if (!view.value().empty()) {
        if (!knownView(view.value())) {
            return Error{"handshake: unknown view (bird, snail, hud)"};
        }
        req.profile.view = view.value();
    }
    auto format = readString(j, "format", 16);
    if (!format) {
        return format.error();
    }
    if (!format.value().empty()) {
        const auto f = parsePixelFormat(format.value());
        if (!f) {
            return Error{"handshake: unknown format (rgba8, rgb565)"};
        }
        req.profile.format = *f;
    }
    auto payload = readString(j, "payload", 16);
    if (!payload) {
        return payload.error();
    }
    if (payload.value().empty() || payload.value() == "shm") {
        req.payload = StreamPayload::Shm;
    } else if (payload.value() == "raw") {
        req.payload = StreamPayload::Raw;
    } else if (payload.value() == "zlib") {
        req.payload = StreamPayload::Zlib;
    } else {
        return Error{"handshake: unknown payload (shm, raw, zlib)"};
    }
    if (const auto it = j.find("hold"); it != j.end()) {
        if (!it->is_boolean()) {
            return Error{"handshake: \"hold\" must be true or false"};
        }
        req.hold = it->get<bool>();
        if (req.hold && req.payload != StreamPayload::Shm) {
            return Error{"handshake: \"hold\" needs payload shm (frames are held in the shared-memory ring)"};
        }
    }
    return req;
}

std::string formatStreamRequest(const StreamRequest& request) {
    nlohmann::json j;
    j["version"] = 1;
    j["profile"] = request.profile.name;
    j["width"] = request.profile.width;
    j["height"] = request.profile.height;
    j["fps"] = request.profile.fps;
    j["view"] = request.profile.view;
    j["format"] = pixelFormatName(request.profile.format);
    j["payload"] = streamPayloadName(request.payload);
    if (request.hold) {
        j["hold"] = true;
    }
    return j.dump(-1, ' ', true, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace navmap::ipc
