// SPDX-License-Identifier: Apache-2.0
#pragma once
// Command-line conventions of every navmap tool (CLI11, header-only like CLI11 itself):
// `--help` and `--version` print to stdout and exit 0; a usage error prints one line naming the
// option and the problem and exits 2; bad input and run-time failures are the tool's own and exit
// 1 (docs/tools.md). Numeric options take finite numbers in a stated range only: CLI::Range lets
// "nan" through (every comparison with NaN is false) and accepts "inf".

#include <CLI/CLI.hpp>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>

#include "navmap/version.h"

namespace navmap::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;  ///< bad input (a file, a peer's answer) or a run-time failure
inline constexpr int kExitUsage = 2;    ///< the command line itself is wrong

/// A number as the help text and the error messages print it (1e+07, 0.5, 65535).
inline std::string formatNumber(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

/// A finite decimal number in [lo, hi]; "nan", "inf", "1e999" and trailing junk are refused with
/// "'abc' is not a finite number in [lo, hi]".
inline CLI::Validator finiteIn(double lo, double hi) {
    const std::string range = "[" + formatNumber(lo) + ", " + formatNumber(hi) + "]";
    return CLI::Validator(
        [lo, hi, range](std::string& input) -> std::string {
            char* end = nullptr;
            errno = 0;
            const double v = std::strtod(input.c_str(), &end);
            if (input.empty() || end != input.c_str() + input.size() || errno == ERANGE || !std::isfinite(v) ||
                v < lo || v > hi) {
                return "'" + input + "' is not a finite number in " + range;
            }
            return {};
        },
        "NUMBER in " + range);
}

/// A whole decimal number in [lo, hi] ("1.5", "0x10" and "12abc" are refused).
inline CLI::Validator integerIn(long long lo, long long hi) {
    const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    return CLI::Validator(
        [lo, hi, range](std::string& input) -> std::string {
            char* end = nullptr;
            errno = 0;
            const long long v = std::strtoll(input.c_str(), &end, 10);
            if (input.empty() || end != input.c_str() + input.size() || errno == ERANGE || v < lo || v > hi) {
                return "'" + input + "' is not an integer in " + range;
            }
            return {};
        },
        "INTEGER in " + range);
}

/// The version line every tool prints for --version: "<program> <version>" (help2man reads it).
inline std::string versionLine(const std::string& program) { return program + " " + NAVMAP_VERSION; }

/// Adds --version and the failure message of the conventions above to `app`.
inline void setUp(CLI::App& app, const std::string& program) {
    app.set_version_flag("--version", versionLine(program));
    app.failure_message([program](const CLI::App*, const CLI::Error& e) {
        return program + ": " + e.what() + "\nRun with --help for more information.\n";
    });
}

/// Parses the command line. nullopt: go on; otherwise the process exit status (0 after --help or
/// --version, kExitUsage after a usage error, which is printed to stderr).
inline std::optional<int> parse(CLI::App& app, int argc, char** argv) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? kExitOk : kExitUsage;  // CLI11's own codes are 100 and up
    }
    return std::nullopt;
}

}  // namespace navmap::cli
