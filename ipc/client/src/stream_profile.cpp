// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/client/stream_profile.h"

#include <limits>
#include <nlohmann/json.hpp>
#include <tuple>

#include "navmap/ipc/client/dmabuf_block.h"
#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/client/frame_ring.h"

namespace navmap::ipc {
namespace {

bool knownView(std::string_view v) { return v == "bird" || v == "snail" || v == "hud"; }

// Reads an integer member in [lo, hi]; absent keeps *out. `where` names the line ("handshake",
// "reply") and `prefix` the enclosing object ("profile.") in errors.
Status readInt(const nlohmann::json& j, const char* key, std::int64_t lo, std::int64_t hi, std::int64_t* out,
               std::string_view where = "handshake", std::string_view prefix = "") {
    const auto it = j.find(key);
    if (it == j.end()) {
        return {};
    }
    const std::string name = std::string(where) + ": \"" + std::string(prefix) + key + "\"";
    if (!it->is_number_integer()) {
        return Error{name + " must be an integer"};
    }
    // Unsigned values above INT64_MAX are out of every range here.
    if (it->is_number_unsigned() && it->get<std::uint64_t>() > static_cast<std::uint64_t>(hi)) {
        return Error{name + " = " + std::to_string(it->get<std::uint64_t>()) + " outside [" + std::to_string(lo) +
                     ", " + std::to_string(hi) + "]"};
    }
    const auto v = it->get<std::int64_t>();
    if (v < lo || v > hi) {
        return Error{name + " = " + std::to_string(v) + " outside [" + std::to_string(lo) + ", " + std::to_string(hi) +
                     "]"};
    }
    *out = v;
    return {};
}

Status readInt(const nlohmann::json& j, const char* key, int lo, int hi, int* out, std::string_view where = "handshake",
               std::string_view prefix = "") {
    std::int64_t v = *out;
    if (auto s = readInt(j, key, std::int64_t{lo}, std::int64_t{hi}, &v, where, prefix); !s) {
        return s;
    }
    *out = static_cast<int>(v);
    return {};
}

Result<std::string> readString(const nlohmann::json& j, const char* key, std::size_t max_len,
                               std::string_view where = "handshake", std::string_view prefix = "") {
    const auto it = j.find(key);
    if (it == j.end()) {
        return std::string();
    }
    const std::string name = std::string(where) + ": \"" + std::string(prefix) + key + "\"";
    if (!it->is_string()) {
        return Error{name + " must be a string"};
    }
    std::string s = it->get<std::string>();
    if (s.empty() || s.size() > max_len) {
        return Error{name + " must have 1.." + std::to_string(max_len) + " characters"};
    }
    return s;
}

bool printableAscii(std::string_view s) {
    for (const char c : s) {
        if (static_cast<unsigned char>(c) < 0x20 || c == '"' || c == '\\' || static_cast<unsigned char>(c) >= 0x7F) {
            return false;
        }
    }
    return true;
}

// The "profile" object of a reply: each field present must have the type and range a request
// may give it; the size and format must be the requested ones.
Status readGrantedProfile(const nlohmann::json& j, const StreamProfile& asked, StreamProfile* out) {
    if (!j.is_object()) {
        return Error{"reply: \"profile\" must be an object"};
    }
    StreamProfile p = asked;
    auto name = readString(j, "name", 64, "reply", "profile.");
    if (!name) {
        return Error{name.error().message};
    }
    if (!name.value().empty()) {
        if (!printableAscii(name.value())) {
            return Error{"reply: \"profile.name\" must be printable ASCII"};
        }
        p.name = name.value();
    }
    for (const auto& [key, lo, hi, field] : {std::tuple{"width", kMinStreamDimension, kMaxStreamDimension, &p.width},
                                             std::tuple{"height", kMinStreamDimension, kMaxStreamDimension, &p.height},
                                             std::tuple{"fps", 0, kMaxStreamFps, &p.fps}}) {
        if (auto s = readInt(j, key, lo, hi, field, "reply", "profile."); !s) {
            return s;
        }
    }
    auto view = readString(j, "view", 16, "reply", "profile.");
    if (!view) {
        return Error{view.error().message};
    }
    if (!view.value().empty()) {
        if (!knownView(view.value())) {
            return Error{"reply: \"profile.view\" must be bird, snail or hud"};
        }
        p.view = view.value();
    }
    auto format = readString(j, "format", 16, "reply", "profile.");
    if (!format) {
        return Error{format.error().message};
    }
    if (!format.value().empty()) {
        const auto f = parsePixelFormat(format.value());
        if (!f) {
            return Error{"reply: \"profile.format\" must be rgba8 or rgb565"};
        }
        p.format = *f;
    }
    if (p.width != asked.width || p.height != asked.height || p.format != asked.format) {
        return Error{"reply: granted " + std::to_string(p.width) + "x" + std::to_string(p.height) + " " +
                     pixelFormatName(p.format) + ", asked for " + std::to_string(asked.width) + "x" +
                     std::to_string(asked.height) + " " + pixelFormatName(asked.format)};
    }
    *out = p;
    return {};
}

// The "ring" object of a shm reply: its sizes must be the layout of the granted profile.
Status readRing(const nlohmann::json& reply, const StreamProfile& p, StreamReply* out) {
    const auto it = reply.find("ring");
    if (it == reply.end()) {
        return Error{"reply: payload shm without \"ring\""};
    }
    if (!it->is_object()) {
        return Error{"reply: \"ring\" must be an object"};
    }
    const nlohmann::json& ring = *it;
    std::int64_t slots = -1;
    if (auto s = readInt(ring, "slots", 1, kMaxRingSlots, &slots, "reply", "ring."); !s) {
        return s;
    }
    if (slots < 0) {
        return Error{"reply: \"ring.slots\" missing"};
    }
    const FrameRingLayout l =
        FrameRingLayout::make(static_cast<std::uint32_t>(slots), static_cast<std::uint32_t>(p.width),
                              static_cast<std::uint32_t>(p.height), p.format);
    const auto total = static_cast<std::int64_t>(l.total_bytes);
    const auto slot_bytes = static_cast<std::int64_t>(l.slot_bytes);
    // Each size present must be the layout's; total_bytes is required (the client maps that much).
    const std::tuple<const char*, std::int64_t, bool> expect[] = {
        {"total_bytes", total, true},
        {"slot_bytes", slot_bytes, false},
        {"header_offset", static_cast<std::int64_t>(kSlotHeaderOffset), false},
        {"pixel_offset", static_cast<std::int64_t>(kSlotPixelOffset), false},
    };
    for (const auto& [key, want, required] : expect) {
        std::int64_t v = -1;
        if (auto s = readInt(ring, key, 0, std::numeric_limits<std::int64_t>::max(), &v, "reply", "ring."); !s) {
            return s;
        }
        if (v < 0 && required) {
            return Error{std::string("reply: \"ring.") + key + "\" missing"};
        }
        if (v >= 0 && v != want) {
            return Error{std::string("reply: \"ring.") + key + "\" = " + std::to_string(v) + ", the layout of " +
                         std::to_string(slots) + " slots of " + std::to_string(p.width) + "x" +
                         std::to_string(p.height) + " " + pixelFormatName(p.format) + " has " + std::to_string(want)};
        }
    }
    out->ring_slots = static_cast<std::uint32_t>(slots);
    out->ring_total_bytes = l.total_bytes;
    return {};
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
        case StreamPayload::Dmabuf: return "dmabuf";
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
                                        "view",    "format",  "payload", "hold",   "meta"};
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
    if (!printableAscii(req.profile.name)) {
        return Error{"handshake: \"profile\" must be printable ASCII"};
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
    } else if (payload.value() == "dmabuf") {
        req.payload = StreamPayload::Dmabuf;
    } else {
        return Error{"handshake: unknown payload (shm, raw, zlib, dmabuf)"};
    }
    if (const auto it = j.find("hold"); it != j.end()) {
        if (!it->is_boolean()) {
            return Error{"handshake: \"hold\" must be true or false"};
        }
        req.hold = it->get<bool>();
        if (req.hold && req.payload != StreamPayload::Shm && req.payload != StreamPayload::Dmabuf) {
            return Error{"handshake: \"hold\" needs payload shm (frames are held in the shared-memory ring)"};
        }
    }
    if (const auto it = j.find("meta"); it != j.end()) {
        if (!it->is_boolean()) {
            return Error{"handshake: \"meta\" must be true or false"};
        }
        req.meta = it->get<bool>();
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
    if (request.meta) {
        j["meta"] = true;
    }
    return j.dump(-1, ' ', true, nlohmann::json::error_handler_t::replace) + "\n";
}

Result<StreamReply> parseStreamReply(std::string_view line, const StreamRequest& request) {
    if (line.size() > kMaxHandshakeBytes) {
        return Error{"reply: longer than " + std::to_string(kMaxHandshakeBytes) + " bytes"};
    }
    const auto j = nlohmann::json::parse(line.begin(), line.end(), nullptr, false);
    if (j.is_discarded() || !j.is_object()) {
        return Error{"reply: not a JSON object"};
    }
    const auto ok = j.find("ok");
    if (ok == j.end() || !ok->is_boolean()) {
        return Error{"reply: \"ok\" must be true or false"};
    }
    StreamReply reply;
    if (!ok->get<bool>()) {
        const auto why = j.find("error");
        reply.refusal = why != j.end() && why->is_string() && !why->get_ref<const std::string&>().empty()
                            ? why->get<std::string>()
                            : "?";
        return reply;
    }
    int version = 1;
    if (auto s = readInt(j, "version", 1, 1, &version, "reply"); !s) {
        return Error{s.message()};
    }
    reply.accepted = true;
    reply.profile = request.profile;
    if (const auto p = j.find("profile"); p != j.end()) {
        if (auto s = readGrantedProfile(*p, request.profile, &reply.profile); !s) {
            return Error{s.message()};
        }
    }
    auto payload = readString(j, "payload", 16, "reply");
    if (!payload) {
        return payload.error();
    }
    if (!payload.value().empty() && payload.value() != streamPayloadName(request.payload)) {
        return Error{"reply: payload \"" + payload.value().substr(0, 16) + "\", asked for \"" +
                     streamPayloadName(request.payload) + "\""};
    }
    if (const auto hold = j.find("hold");
        hold != j.end() && (!hold->is_boolean() || hold->get<bool>() != request.hold)) {
        return Error{"reply: \"hold\" must be " + std::string(request.hold ? "true" : "false") + " as asked"};
    }
    // Asked for metadata: the server names the block version it sends; not asked: no key.
    if (const auto meta = j.find("meta"); request.meta) {
        if (meta == j.end() || !meta->is_number_integer() || meta->get<std::int64_t>() != kFrameMetaVersion) {
            return Error{"reply: \"meta\" must be " + std::to_string(kFrameMetaVersion) +
                         " (the metadata block version this client reads)"};
        }
    } else if (meta != j.end()) {
        return Error{"reply: \"meta\" without asking for metadata"};
    }
    const auto stride = static_cast<std::int64_t>(reply.profile.width) * bytesPerPixel(reply.profile.format);
    std::int64_t v = stride;
    if (auto s = readInt(j, "stride", 1, std::numeric_limits<std::int64_t>::max(), &v, "reply"); !s) {
        return Error{s.message()};
    }
    if (v != stride) {
        return Error{"reply: \"stride\" = " + std::to_string(v) + ", expected " + std::to_string(stride)};
    }
    v = static_cast<std::int64_t>(kFrameHeaderBytes);
    if (auto s = readInt(j, "header_bytes", 1, std::numeric_limits<std::int64_t>::max(), &v, "reply"); !s) {
        return Error{s.message()};
    }
    if (v != static_cast<std::int64_t>(kFrameHeaderBytes)) {
        return Error{"reply: \"header_bytes\" = " + std::to_string(v) + ", expected " +
                     std::to_string(kFrameHeaderBytes)};
    }
    if (const auto layout = j.find("dmabuf"); request.payload == StreamPayload::Dmabuf) {
        // The version of the 48-byte block every frame will carry: this client reads version 1.
        if (layout == j.end() || !layout->is_number_integer() || layout->get<std::int64_t>() != kDmabufBlockVersion) {
            return Error{"reply: \"dmabuf\" must be " + std::to_string(kDmabufBlockVersion) +
                         " (the dma-buf block version this client reads)"};
        }
    } else if (layout != j.end()) {
        return Error{"reply: \"dmabuf\" without asking for payload dmabuf"};
    }
    if (request.payload == StreamPayload::Shm) {
        if (auto s = readRing(j, reply.profile, &reply); !s) {
            return Error{s.message()};
        }
    }
    return reply;
}

}  // namespace navmap::ipc
