// SPDX-License-Identifier: Apache-2.0
// The render cases (docs/architecture.md "Render cases"): one test per directory of
// tests/render/cases (or $NAVMAP_RENDER_CASES), listed when the program starts. Each renders its
// case.json and compares the frame with its expected.png at the case's tolerance; a case whose
// feature is off on this context (the ES 3.0 run) takes its fallback and says so. A mismatch or
// a missing expected.png writes the actual image to <build>/golden-failures/ for
// scripts/approve-goldens.sh; a case.json that cannot be used fails its test with the file and
// the reason.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include "case_renderer.h"
#include "golden.h"
#include "render_case.h"
#include "test_paths.h"

namespace {

using navmap::test::CaseStats;
using navmap::test::RenderCase;

const std::vector<std::filesystem::path>& caseDirs() {
    static const std::vector<std::filesystem::path> kDirs =
        navmap::test::listRenderCases(navmap::test::renderCasesDir());
    return kDirs;
}

// Test names: the directory names, made unique where two differ only in characters a test
// name cannot hold (RenderCases.DirectoryNamesAreTestNames fails for those).
const std::vector<std::string>& caseNames() {
    static const std::vector<std::string> kNames = [] {
        std::vector<std::string> names;
        std::set<std::string> taken;
        for (std::size_t i = 0; i < caseDirs().size(); ++i) {
            std::string name = navmap::test::caseTestName(caseDirs()[i].filename().string());
            if (name.empty() || taken.count(name)) name += "_" + std::to_string(i);
            taken.insert(name);
            names.push_back(name);
        }
        return names;
    }();
    return kNames;
}

// The golden's path for matchesGolden: relative to tests/ of the source tree when it lies there
// (scripts/approve-goldens.sh copies approved images there), else absolute.
std::string goldenPath(const std::filesystem::path& expected) {
    const auto tests = std::filesystem::weakly_canonical(navmap::test::sourceDir() / "tests");
    const auto file = std::filesystem::weakly_canonical(expected);
    const auto relative = file.lexically_relative(tests);
    if (!relative.empty() && *relative.begin() != "..") return relative.generic_string();
    return file.string();
}

void expectStats(const CaseStats& want, const navmap::render::MapFrameStats& stats) {
    for (const auto& [name, least] : want.at_least) {
        EXPECT_GE(navmap::test::countStat(stats, name).value_or(0), least) << "frame statistic " << name;
    }
    for (const auto& [name, value] : want.equal) {
        EXPECT_EQ(navmap::test::flagStat(stats, name).value_or(!value), value) << "frame statistic " << name;
    }
}

class RenderCaseTest : public ::testing::TestWithParam<std::size_t> {};

TEST_P(RenderCaseTest, MatchesExpected) {
    std::string error;
    const auto loaded = navmap::test::loadRenderCase(caseDirs()[GetParam()], &error);
    if (!loaded) GTEST_FAIL() << error;
    const RenderCase& c = *loaded;
    if (!c.description.empty()) std::printf("[ case     ] %s: %s\n", c.name.c_str(), c.description.c_str());
    const navmap::test::CaseFrame frame = navmap::test::renderCase(c);
    const auto& off = frame.features_off;
    if (c.fallback && std::any_of(off.begin(), off.end(),
                                  [&](const std::string& f) { return f.starts_with(c.fallback->feature_off); })) {
        // The documented fallback of a context without the feature (docs/gles-profile.md).
        std::printf("[ fallback ] %s: %s off, compared with %s\n", c.name.c_str(), c.fallback->feature_off.c_str(),
                    c.fallback->expected_case.c_str());
        expectStats(c.fallback->stats, frame.stats);
        EXPECT_GOLDEN(frame.image, goldenPath(c.expectedPath(c.fallback->expected_case)), c.tolerance);
        return;
    }
    expectStats(c.stats, frame.stats);
    EXPECT_GOLDEN(frame.image, goldenPath(c.expectedPath()), c.tolerance);
}

INSTANTIATE_TEST_SUITE_P(Cases, RenderCaseTest, ::testing::Range<std::size_t>(0, caseDirs().size()),
                         [](const ::testing::TestParamInfo<std::size_t>& p) { return caseNames()[p.param]; });

TEST(RenderCases, TheCasesDirectoryHoldsCases) {
    EXPECT_FALSE(caseDirs().empty()) << "no case directories in " << navmap::test::renderCasesDir();
}

TEST(RenderCases, DirectoryNamesAreTestNames) {
    for (const auto& dir : caseDirs()) {
        const std::string name = dir.filename().string();
        EXPECT_EQ(navmap::test::caseTestName(name), name)
            << dir << ": a case directory's name holds only letters, digits and '_' (it names the test)";
    }
}

}  // namespace
