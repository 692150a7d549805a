// SPDX-License-Identifier: Apache-2.0
// NAVMAP_CHECK stays on in release builds: this file is compiled with NDEBUG (tests/common/
// CMakeLists.txt), so assert() is gone here and the check must still abort with its message.
#include <gtest/gtest.h>

#include <cassert>
#include <csignal>

#include "navmap/common/check.h"

#ifndef NDEBUG
#error "check_test.cpp must be compiled with NDEBUG: it shows the check survives release builds"
#endif

namespace {

int g_evaluations = 0;
bool countedTrue() {
    ++g_evaluations;
    return true;
}

void failingCheck(int vertices, int index) { NAVMAP_CHECK(index < vertices, "index past its vertices"); }

}  // namespace

TEST(NavmapCheck, FiresInAReleaseBuildWithFileLineConditionAndMessage) {
    // assert() is compiled out here (NDEBUG): this must not abort.
    assert(false);
    EXPECT_EXIT(failingCheck(3, 7), testing::KilledBySignal(SIGABRT),
                "<2>navmap: check failed: .*check_test\\.cpp:[0-9]+: index < vertices: index past its vertices");
}

TEST(NavmapCheck, PassingCheckDoesNothingAndEvaluatesTheConditionOnce) {
    g_evaluations = 0;
    NAVMAP_CHECK(countedTrue(), "never printed");
    EXPECT_EQ(g_evaluations, 1);
    failingCheck(3, 2);  // in range: returns
}
