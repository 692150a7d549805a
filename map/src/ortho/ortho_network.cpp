// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/ortho/ortho_network.h"

#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "../byte_io.h"
#include "navmap/common/untrusted_file.h"

namespace navmap::map::ortho {

namespace {

constexpr char kMagic[8] = {'N', 'A', 'V', 'M', 'A', 'P', 'N', 'N'};
constexpr std::uint32_t kFileVersion = 1;
constexpr std::uint32_t kHeaderSize = 64;

std::uint32_t crc(const std::uint8_t* data, std::size_t n) {
    return static_cast<std::uint32_t>(::crc32(::crc32(0L, Z_NULL, 0), data, static_cast<uInt>(n)));
}

constexpr std::size_t payloadFloats(int inputs, int hidden) {
    return static_cast<std::size_t>(inputs) * hidden + hidden + 3 * static_cast<std::size_t>(hidden) + 3;
}

constexpr int kMaxHidden = 1024;
// The largest file the format allows (this build's inputs, kMaxHidden hidden neurons): 192,588
// bytes. A longer file is refused on its size, before it is read (docs/architecture.md
// "Untrusted files").
constexpr FileKind kWeightsFile{"orthoimage weights", kHeaderSize + 4 * payloadFloats(kOrthoInputs, kMaxHidden)};

}  // namespace

OrthoNetwork OrthoNetwork::zeros(int inputs, int hidden) {
    OrthoNetwork n;
    n.inputs = inputs;
    n.hidden = hidden;
    n.w0.assign(static_cast<std::size_t>(inputs) * hidden, 0.0f);
    n.b0.assign(static_cast<std::size_t>(hidden), 0.0f);
    n.w1.assign(static_cast<std::size_t>(hidden) * 3, 0.0f);
    return n;
}

std::array<float, 3> OrthoNetwork::forward(const OrthoInput& in, std::vector<float>& a) const {
    // seed eq. 6.1: a0 = b0 + i w0, over the active inputs only (6.6.2).
    a.assign(b0.begin(), b0.end());
    for (int k = 0; k < kOrthoActive; ++k) {
        const int node = in.node(k);
        const float v = in.value(k);
        if (v == 0.0f || node >= inputs) continue;
        const float* row = &w0[static_cast<std::size_t>(node) * hidden];
        for (int j = 0; j < hidden; ++j) a[static_cast<std::size_t>(j)] += v * row[j];
    }
    // eq. 6.2, 6.3: sigmoid, then the linear output layer.
    std::array<float, 3> out = b1;
    for (int j = 0; j < hidden; ++j) {
        const float s = sigmoid(a[static_cast<std::size_t>(j)]);
        a[static_cast<std::size_t>(j)] = s;
        const float* row = &w1[static_cast<std::size_t>(j) * 3];
        out[0] += s * row[0];
        out[1] += s * row[1];
        out[2] += s * row[2];
    }
    return out;
}

std::array<float, 3> OrthoNetwork::forward(const OrthoInput& in) const {
    thread_local std::vector<float> hidden_values;
    return forward(in, hidden_values);
}

std::array<std::uint8_t, 3> OrthoNetwork::color(const OrthoInput& in) const {
    const auto rgb = forward(in);
    std::array<std::uint8_t, 3> out{};
    for (std::size_t c = 0; c < 3; ++c)
        out[c] = static_cast<std::uint8_t>(std::lround(std::clamp(rgb[c], 0.0f, 1.0f) * 255.0f));
    return out;
}

std::vector<std::uint8_t> encodeNetwork(const OrthoNetwork& net) {
    detail::ByteWriter payload;
    for (float v : net.w0) payload.f32(v);
    for (float v : net.b0) payload.f32(v);
    for (float v : net.w1) payload.f32(v);
    for (float v : net.b1) payload.f32(v);
    detail::ByteWriter w;
    w.raw(kMagic, 8);
    w.u32(kFileVersion);
    w.u32(kHeaderSize);
    w.u32(kOrthoEncodingVersion);
    w.u32(static_cast<std::uint32_t>(net.inputs));
    w.u32(static_cast<std::uint32_t>(net.hidden));
    w.u32(3);
    w.u32(net.info.seed);
    w.u32(0);
    w.u32(net.info.epochs);
    w.u32(net.info.samples);
    w.f32(net.info.held_out_delta_e);
    w.u32(static_cast<std::uint32_t>(payload.size()));
    w.u32(crc(payload.bytes().data(), payload.size()));
    w.u32(crc(w.bytes().data(), w.size()));
    w.raw(payload.bytes().data(), payload.size());
    return std::move(w.bytes());
}

OrthoNetwork decodeNetwork(const std::vector<std::uint8_t>& bytes, const std::string& name) {
    auto fail = [&](const std::string& problem) -> OrthoNetworkError {
        return OrthoNetworkError(name + ": " + problem);
    };
    if (bytes.size() < 8 || std::memcmp(bytes.data(), kMagic, 8) != 0)
        throw fail("not a navmap network weights file (bad magic)");
    if (bytes.size() < kHeaderSize) {
        throw fail("truncated: " + std::to_string(bytes.size()) + " bytes, shorter than the " +
                   std::to_string(kHeaderSize) + "-byte header");
    }
    detail::ByteReader r(std::span<const std::uint8_t>(bytes).subspan(8));
    const std::uint32_t version = r.u32();
    if (version != kFileVersion) {
        throw fail("weights file format version " + std::to_string(version) + ", this build reads version " +
                   std::to_string(kFileVersion));
    }
    const std::uint32_t header_size = r.u32();
    const std::uint32_t encoding = r.u32();
    const auto inputs = static_cast<int>(r.u32());
    const auto hidden = static_cast<int>(r.u32());
    const std::uint32_t outputs = r.u32();
    OrthoTrainingInfo info;
    info.seed = r.u32();
    (void)r.u32();
    info.epochs = r.u32();
    info.samples = r.u32();
    info.held_out_delta_e = r.f32();
    const std::uint32_t payload_size = r.u32();
    const std::uint32_t payload_crc = r.u32();
    const std::uint32_t header_crc = r.u32();
    if (header_crc != crc(bytes.data(), kHeaderSize - 4)) throw fail("header checksum mismatch");
    if (header_size != kHeaderSize)
        throw fail("header size " + std::to_string(header_size) + ", expected " + std::to_string(kHeaderSize));
    if (encoding != kOrthoEncodingVersion) {
        throw fail("trained for input encoding version " + std::to_string(encoding) + ", this build encodes version " +
                   std::to_string(kOrthoEncodingVersion) + " (retrain with navmap-ortho-train)");
    }
    if (inputs != kOrthoInputs || outputs != 3 || hidden < 1 || hidden > kMaxHidden) {
        throw fail("network shape " + std::to_string(inputs) + "-" + std::to_string(hidden) + "-" +
                   std::to_string(outputs) + " does not fit this build's " + std::to_string(kOrthoInputs) +
                   " inputs and 3 outputs");
    }
    const std::size_t floats = payloadFloats(inputs, hidden);
    if (payload_size != floats * 4)
        throw fail("payload size " + std::to_string(payload_size) + " does not match the shape");
    if (bytes.size() < kHeaderSize + payload_size) {
        throw fail("truncated: " + std::to_string(bytes.size()) + " of " + std::to_string(kHeaderSize + payload_size) +
                   " bytes");
    }
    if (bytes.size() > kHeaderSize + payload_size) {
        throw fail(std::to_string(bytes.size() - kHeaderSize - payload_size) + " bytes after the weights");
    }
    if (payload_crc != crc(bytes.data() + kHeaderSize, payload_size)) throw fail("weights checksum mismatch");
    OrthoNetwork net = OrthoNetwork::zeros(inputs, hidden);
    net.info = info;
    detail::ByteReader p(std::span<const std::uint8_t>(bytes).subspan(kHeaderSize));
    auto read_all = [&](auto& dst) {
        for (auto& v : dst) {
            v = p.f32();
            if (!std::isfinite(v)) throw fail("weight is not finite");
        }
    };
    read_all(net.w0);
    read_all(net.b0);
    read_all(net.w1);
    read_all(net.b1);
    return net;
}

OrthoNetwork loadNetwork(const std::filesystem::path& path) {
    std::string problem;
    const auto bytes = UntrustedFile::readBytes(path, kWeightsFile, problem);
    if (!bytes) throw OrthoNetworkError(problem);
    return decodeNetwork(*bytes, path.string());
}

void saveNetwork(const OrthoNetwork& net, const std::filesystem::path& path) {
    const std::vector<std::uint8_t> bytes = encodeNetwork(net);
    const std::filesystem::path tmp = path.string() + ".tmp-" + std::to_string(::getpid());
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw OrthoNetworkError("open(" + tmp.string() + "): " + std::strerror(errno));
        out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
        if (!out.flush()) throw OrthoNetworkError("write(" + tmp.string() + "): " + std::strerror(errno));
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        throw OrthoNetworkError("rename(" + tmp.string() + ", " + path.string() + "): " + ec.message());
    }
}

}  // namespace navmap::map::ortho
