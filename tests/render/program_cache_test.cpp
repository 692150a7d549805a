// SPDX-License-Identifier: Apache-2.0
// The program binary cache (RendererOptions::program_cache_dir): a second renderer loads every
// program from the binaries the first one stored and draws the same pixels; binaries that are
// corrupt (a damaged file frame, or a payload the driver rejects) are compiled again from GLSL,
// replaced, and the frame is still the same.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "andorra_drive.h"
#include "navmap/render/renderer.h"

namespace {

namespace fs = std::filesystem;
using namespace navmap::render;

constexpr int kW = 480, kH = 180;

struct Rendered {
    Image image;
    ProgramCacheStats cache;
};

Rendered renderWithCache(const fs::path& dir) {
    RendererOptions o;
    o.width = kW;
    o.height = kH;
    o.program_cache_dir = dir.string();
    auto renderer = Renderer::create(o);
    MapFrame frame = navmap::test::settledAndorraFrame(ViewMode::Snail, kW, kH);
    renderer->renderMap(frame);
    return {renderer->readSync(), renderer->programCache()};
}

std::vector<fs::path> binaries(const fs::path& dir) {
    std::vector<fs::path> out;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().extension() == ".glprog") out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

std::size_t differingPixels(const Image& a, const Image& b) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.rgba.size() && i < b.rgba.size(); i += 4)
        n += std::memcmp(&a.rgba[i], &b.rgba[i], 4) != 0;
    return n;
}

class ProgramCache : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / ("navmap-program-cache-" + std::to_string(::getpid()));
        fs::remove_all(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }
    fs::path m_dir;
};

TEST_F(ProgramCache, ASecondRendererLoadsTheBinariesAndCorruptOnesAreCompiledAgain) {
    const Rendered first = renderWithCache(m_dir);
    if (!first.cache.problem.empty()) GTEST_SKIP() << "program binary cache off: " << first.cache.problem;
    ASSERT_EQ(first.cache.dir, m_dir.string());
    EXPECT_GT(first.cache.compiled, 10u);
    EXPECT_EQ(first.cache.loaded, 0u);
    EXPECT_EQ(first.cache.stored, first.cache.compiled);
    EXPECT_EQ(first.cache.write_errors, 0u);
    const std::vector<fs::path> files = binaries(m_dir);
    ASSERT_GT(files.size(), 10u);  // one per program (two passes may share one)
    ASSERT_LE(files.size(), first.cache.stored);

    const Rendered second = renderWithCache(m_dir);
    EXPECT_EQ(second.cache.loaded, first.cache.stored);
    EXPECT_EQ(second.cache.compiled, 0u);
    EXPECT_EQ(second.cache.rejected, 0u);
    EXPECT_EQ(differingPixels(second.image, first.image), 0u);

    // Damage every binary: the even ones in the driver's payload (the driver refuses it), the
    // odd ones in the file's own frame (the size no longer matches).
    for (std::size_t i = 0; i < files.size(); ++i) {
        std::ifstream in(files[i], std::ios::binary);
        std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        in.close();
        ASSERT_GT(bytes.size(), 64u);
        if (i % 2 == 0) {
            for (std::size_t b = 32; b < bytes.size(); b += 7) bytes[b] = static_cast<char>(bytes[b] ^ 0x5a);
        } else {
            bytes.resize(bytes.size() - 5);
        }
        std::ofstream(files[i], std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
    }
    const Rendered third = renderWithCache(m_dir);
    EXPECT_EQ(third.cache.rejected, files.size());
    EXPECT_EQ(third.cache.compiled, files.size());
    EXPECT_EQ(third.cache.stored, files.size());
    EXPECT_EQ(third.cache.loaded + third.cache.compiled, first.cache.compiled);
    EXPECT_EQ(differingPixels(third.image, first.image), 0u);

    // The replaced binaries load again.
    const Rendered fourth = renderWithCache(m_dir);
    EXPECT_EQ(fourth.cache.loaded, first.cache.compiled);
    EXPECT_EQ(fourth.cache.rejected, 0u);
    EXPECT_EQ(differingPixels(fourth.image, first.image), 0u);
}

TEST_F(ProgramCache, AnUnwritableDirectoryLeavesTheCacheOffAndTheRendererWorking) {
    fs::create_directories(m_dir);
    const fs::path file = m_dir / "not-a-directory";
    std::ofstream(file) << "x";
    const Rendered r = renderWithCache(file / "cache");
    EXPECT_FALSE(r.cache.problem.empty());
    EXPECT_EQ(r.cache.loaded + r.cache.stored, 0u);
    const Rendered plain = renderWithCache(fs::path());
    EXPECT_TRUE(plain.cache.dir.empty());
    EXPECT_EQ(differingPixels(r.image, plain.image), 0u);
}

}  // namespace
