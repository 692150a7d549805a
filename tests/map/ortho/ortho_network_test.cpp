// SPDX-License-Identifier: Apache-2.0
// The orthoimage network (seed 6.6): the compressed forward pass against the full one, the
// weights file and its damage, and training on a small synthetic set that must recover a known
// mapping.

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "navmap/map/compile/ortho/ortho_training.h"
#include "navmap/map/ortho/color_difference.h"
#include "navmap/map/ortho/ortho_network.h"
#include "navmap/map/ortho/rng.h"

namespace {

using namespace navmap::map::ortho;
namespace fs = std::filesystem;

OrthoNetwork randomNetwork(int hidden, std::uint64_t seed) {
    OrthoNetwork n = OrthoNetwork::zeros(kOrthoInputs, hidden);
    Rng r(seed);
    for (auto* v : {&n.w0, &n.b0, &n.w1}) {
        for (float& w : *v) w = static_cast<float>(r.uniform(-1, 1));
    }
    for (float& b : n.b1) b = static_cast<float>(r.uniform(0, 0.5));
    return n;
}

OrthoPixel randomPixel(Rng& r) {
    OrthoPixel p;
    p.cover.first = static_cast<std::uint8_t>(r.below(kGlobalCoverCount));
    p.cover.second = static_cast<std::uint8_t>(r.below(kGlobalCoverCount));
    p.cover.first_share = static_cast<float>(r.uniform(0.5, 1.0));
    p.cover.second_share = 1.0f - p.cover.first_share;
    p.climate.first = static_cast<std::uint8_t>(r.below(kClimateClassCount));
    p.climate.second = static_cast<std::uint8_t>(r.below(kClimateClassCount));
    p.climate.first_share = static_cast<float>(r.uniform(0.5, 1.0));
    p.climate.second_share = 1.0f - p.climate.first_share;
    p.elevation_m = static_cast<float>(r.uniform(-100, 5000));
    p.temp_dec_c = static_cast<float>(r.uniform(-40, 30));
    p.temp_jul_c = static_cast<float>(r.uniform(-20, 40));
    p.precip_dec_mm = static_cast<float>(r.uniform(0, 400));
    p.precip_jul_mm = static_cast<float>(r.uniform(0, 400));
    p.lights = static_cast<float>(r.uniform(0, 1));
    return p;
}

TEST(OrthoNetwork, CompressedInputsGiveTheFullForwardPass) {
    const OrthoNetwork net = randomNetwork(kOrthoInputs, 5);
    Rng r(9);
    for (int i = 0; i < 200; ++i) {
        const OrthoInput in = encodeInput(randomPixel(r));
        // eq. 6.1-6.3 over the full n-vector.
        const auto x = expandInput(in);
        std::array<double, 3> out{net.b1[0], net.b1[1], net.b1[2]};
        for (int j = 0; j < net.hidden; ++j) {
            double a = net.b0[static_cast<std::size_t>(j)];
            for (int k = 0; k < kOrthoInputs; ++k)
                a += x[static_cast<std::size_t>(k)] * net.w0[static_cast<std::size_t>(k * net.hidden + j)];
            const double s = 1.0 / (1.0 + std::exp(-a));
            for (std::size_t c = 0; c < 3; ++c) out[c] += s * net.w1[static_cast<std::size_t>(j) * 3 + c];
        }
        const auto y = net.forward(in);
        for (std::size_t c = 0; c < 3; ++c) EXPECT_NEAR(y[c], out[c], 1e-4) << i;
    }
}

TEST(OrthoNetwork, WeightsFileRoundTripAndDamage) {
    OrthoNetwork net = randomNetwork(12, 3);
    net.info = {7, 40, 1000, 9.5f};
    const std::vector<std::uint8_t> bytes = encodeNetwork(net);
    EXPECT_EQ(bytes.size(), 64u + 4u * (43 * 12 + 12 + 36 + 3));
    const OrthoNetwork back = decodeNetwork(bytes, "w.nnw");
    EXPECT_EQ(back.hidden, 12);
    EXPECT_EQ(back.w0, net.w0);
    EXPECT_EQ(back.w1, net.w1);
    EXPECT_EQ(back.b1, net.b1);
    EXPECT_EQ(back.info.seed, 7u);
    EXPECT_FLOAT_EQ(back.info.held_out_delta_e, 9.5f);

    auto error = [](const std::vector<std::uint8_t>& b) -> std::string {
        try {
            (void)decodeNetwork(b, "w.nnw");
        } catch (const OrthoNetworkError& e) {
            return e.what();
        }
        return "";
    };
    auto truncated = bytes;
    truncated.resize(812);
    EXPECT_EQ(error(truncated), "w.nnw: truncated: 812 of " + std::to_string(bytes.size()) + " bytes");
    EXPECT_EQ(error({bytes.begin(), bytes.begin() + 40}),
              "w.nnw: truncated: 40 bytes, shorter than the 64-byte header");
    auto flipped = bytes;
    flipped[200] ^= 0x10;
    EXPECT_EQ(error(flipped), "w.nnw: weights checksum mismatch");
    auto header = bytes;
    header[24] ^= 1;  // hidden
    EXPECT_EQ(error(header), "w.nnw: header checksum mismatch");
    auto magic = bytes;
    magic[0] = 'X';
    EXPECT_EQ(error(magic), "w.nnw: not a navmap network weights file (bad magic)");
    auto longer = bytes;
    longer.push_back(0);
    EXPECT_EQ(error(longer), "w.nnw: 1 bytes after the weights");
    OrthoNetwork other = OrthoNetwork::zeros(20, 4);
    EXPECT_EQ(error(encodeNetwork(other)),
              "w.nnw: network shape 20-4-3 does not fit this build's 43 inputs and 3 outputs");

    // Files: a truncated one names the path.
    const fs::path path = fs::temp_directory_path() / ("navmap-w-" + std::to_string(::getpid()) + ".nnw");
    saveNetwork(net, path);
    EXPECT_EQ(loadNetwork(path).w0, net.w0);
    fs::resize_file(path, 100);
    try {
        (void)loadNetwork(path);
        FAIL() << "no error";
    } catch (const OrthoNetworkError& e) {
        EXPECT_EQ(std::string(e.what()),
                  path.string() + ": truncated: 100 of " + std::to_string(bytes.size()) + " bytes");
    }
    fs::remove(path);
    try {
        (void)loadNetwork(path);
        FAIL() << "no error";
    } catch (const OrthoNetworkError& e) {
        EXPECT_EQ(std::string(e.what()), "open(" + path.string() + "): No such file or directory (orthoimage weights)");
    }
}

// docs/architecture.md "Untrusted files": the weights are a regular file no longer than the format
// allows, checked before a byte is read. A 2 GiB file used to be read whole (2.1 GiB RSS), /dev/zero
// for ever, and a FIFO blocked the reader until a writer came.
TEST(OrthoNetwork, WeightsThatAreNoRegularFileOrTooLongAreRefusedUnread) {
    const fs::path dir = fs::temp_directory_path() / ("navmap-w-files-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    auto error = [](const fs::path& p) {
        try {
            (void)loadNetwork(p);
        } catch (const OrthoNetworkError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    const fs::path fifo = dir / "fifo.nnw";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    EXPECT_EQ(error(fifo), fifo.string() + ": is a FIFO, not a regular file (orthoimage weights)");
    EXPECT_EQ(error("/dev/zero"), "/dev/zero: is a character device, not a regular file (orthoimage weights)");
    // The largest shape the format allows (1024 hidden neurons) is the limit exactly.
    const fs::path largest = dir / "largest.nnw";
    saveNetwork(OrthoNetwork::zeros(kOrthoInputs, 1024), largest);
    EXPECT_EQ(fs::file_size(largest), 192588u);
    EXPECT_EQ(loadNetwork(largest).hidden, 1024);
    // One byte more, or 2 GiB (sparse: no disk), is refused on the size.
    for (const std::uintmax_t size : {std::uintmax_t{192589}, std::uintmax_t{2} << 30}) {
        fs::resize_file(largest, size);
        EXPECT_EQ(error(largest), largest.string() + ": " + std::to_string(size) +
                                      " bytes, over the limit of 192588 bytes (orthoimage weights)");
    }
    fs::remove_all(dir);
}

TEST(OrthoTraining, RecoversAKnownMappingFromATinySyntheticSet) {
    // The mapping: a colour per land-cover class, darkened with elevation and greener with July
    // rain; climate and the rest are distractors.
    const std::array<std::array<float, 3>, kGlobalCoverCount> colour{{{0.05f, 0.1f, 0.35f},
                                                                      {0.45f, 0.4f, 0.25f},
                                                                      {0.1f, 0.2f, 0.4f},
                                                                      {0.9f, 0.92f, 0.95f},
                                                                      {0.8f, 0.85f, 0.9f},
                                                                      {0.5f, 0.48f, 0.45f},
                                                                      {0.85f, 0.8f, 0.7f}}};
    auto target = [&](const OrthoPixel& p) {
        std::array<float, 3> t = colour[p.cover.first];
        const float dark = 1.0f - 0.3f * std::clamp(p.elevation_m / 5000.0f, 0.0f, 1.0f);
        const float green = 0.15f * std::sqrt(std::clamp(p.precip_jul_mm / 400.0f, 0.0f, 1.0f));
        return std::array<float, 3>{t[0] * dark, std::min(1.0f, t[1] * dark + green), t[2] * dark};
    };
    Rng r(11);
    auto make = [&](int n) {
        std::vector<TrainingSample> v;
        for (int i = 0; i < n; ++i) {
            OrthoPixel p = randomPixel(r);
            p.cover.first_share = 1.0f;
            p.cover.second_share = 0.0f;
            v.push_back({encodeInput(p), target(p)});
        }
        return v;
    };
    const auto train = make(1500), validation = make(300), test = make(300);
    TrainOptions o;
    o.hidden = 16;
    o.epochs = 400;
    o.seed = 3;
    const OrthoNetwork net = trainNetwork(train, validation, o);
    double mean_de = 0;
    for (const auto& s : test) mean_de += deltaE76(net.forward(s.input), s.target);
    mean_de /= double(test.size());
    EXPECT_LT(mean_de, 3.0) << "mean delta E on unseen samples";
    EXPECT_LT(meanSquaredError(net, test), 5e-4);
    // A network that learned nothing (the initial one, trained for no epoch) is far off.
    TrainOptions none = o;
    none.epochs = 0;
    double untrained = 0;
    const OrthoNetwork start = trainNetwork(train, {}, none);
    for (const auto& s : test) untrained += deltaE76(start.forward(s.input), s.target);
    EXPECT_GT(untrained / double(test.size()), 5.0 * mean_de);
}

}  // namespace
