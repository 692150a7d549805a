// SPDX-License-Identifier: Apache-2.0
// MetricsRegistry: each family once with HELP and TYPE, samples beside it, label values escaped,
// numbers exact, duplicates refused naming the family.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "navmap/ipc/stream/metrics_registry.h"

using navmap::ipc::MetricsRegistry;

TEST(MetricsRegistry, WritesEachFamilyOnceWithHelpTypeAndSamples) {
    MetricsRegistry r;
    r.counter("navmap_frames_total", "Frames.").sample({{"profile", "cluster"}}, 42).sample({{"profile", "hud"}}, 7);
    r.summary("navmap_frame_seconds", "Frame time.")
        .sample({{"quantile", "0.5"}, {"profile", "cluster"}}, 0.0125)
        .sample({{"profile", "cluster"}}, 1.5, "_sum")
        .sample({{"profile", "cluster"}}, 120, "_count");
    r.gauge("navmap_bytes", "Bytes.").sample(1073741824.0);
    EXPECT_EQ(r.text(),
              "# HELP navmap_frames_total Frames.\n"
              "# TYPE navmap_frames_total counter\n"
              "navmap_frames_total{profile=\"cluster\"} 42\n"
              "navmap_frames_total{profile=\"hud\"} 7\n"
              "# HELP navmap_frame_seconds Frame time.\n"
              "# TYPE navmap_frame_seconds summary\n"
              "navmap_frame_seconds{profile=\"cluster\",quantile=\"0.5\"} 0.0125\n"
              "navmap_frame_seconds_sum{profile=\"cluster\"} 1.5\n"
              "navmap_frame_seconds_count{profile=\"cluster\"} 120\n"
              "# HELP navmap_bytes Bytes.\n"
              "# TYPE navmap_bytes gauge\n"
              "navmap_bytes 1073741824\n");
}

TEST(MetricsRegistry, EscapesLabelValuesAndHelpAndPrintsNonFiniteValues) {
    MetricsRegistry r;
    r.gauge("g", "a \\ b\nc").sample({{"l", "q\"x\\y\nz"}}, std::numeric_limits<double>::quiet_NaN());
    r.gauge("h", "h").sample(std::numeric_limits<double>::infinity());
    r.gauge("i", "i").sample(-std::numeric_limits<double>::infinity());
    EXPECT_EQ(r.text(),
              "# HELP g a \\\\ b\\nc\n# TYPE g gauge\ng{l=\"q\\\"x\\\\y\\nz\"} NaN\n"
              "# HELP h h\n# TYPE h gauge\nh +Inf\n# HELP i i\n# TYPE i gauge\ni -Inf\n");
}

TEST(MetricsRegistry, RefusesAFamilyOrASampleTwiceAndBadNames) {
    MetricsRegistry r;
    r.counter("navmap_x_total", "x").sample(1);
    try {
        r.gauge("navmap_x_total", "again");
        FAIL() << "a family declared twice was accepted";
    } catch (const std::logic_error& e) {
        EXPECT_STREQ(e.what(), "metric family navmap_x_total declared twice");
    }
    auto& f = r.gauge("navmap_y", "y");
    f.sample({{"a", "1"}, {"b", "2"}}, 1);
    EXPECT_THROW(f.sample({{"b", "2"}, {"a", "1"}}, 2), std::logic_error);  // the same labels, other order
    EXPECT_THROW(f.sample(std::vector<MetricsRegistry::Label>{}, 3, "_sum"), std::logic_error);  // _sum on a gauge
    EXPECT_THROW(r.gauge("9starts_with_a_digit", "n"), std::logic_error);
    EXPECT_THROW(r.gauge("has-dash", "n"), std::logic_error);
    EXPECT_THROW(r.gauge("ok_name", "n").sample({{"__reserved", "v"}}, 1), std::logic_error);
    MetricsRegistry other;
    other.counter("navmap_x_total", "from elsewhere");
    EXPECT_THROW(r.append(other), std::logic_error);
    MetricsRegistry more;
    more.gauge("navmap_z", "z").sample(5);
    r.append(more);
    EXPECT_TRUE(r.has("navmap_z"));
    EXPECT_EQ(r.size(), 4U);  // x_total, y, ok_name, z
}
