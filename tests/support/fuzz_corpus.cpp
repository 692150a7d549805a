// SPDX-License-Identifier: Apache-2.0
#include "fuzz_corpus.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include "test_paths.h"

namespace navmap::test {

std::size_t runFuzzCorpus(FuzzEntry entry, const std::vector<std::string>& seeds, const std::vector<std::string>& extra,
                          int flipped_copies_per_seed) {
    std::size_t runs = 0;
    const auto run = [&](const std::string& s) {
        entry(reinterpret_cast<const std::uint8_t*>(s.data()), s.size());
        ++runs;
    };
    std::mt19937 rng(7);
    for (const auto& seed : seeds) {
        for (std::size_t n = 0; n <= seed.size(); ++n) run(seed.substr(0, n));
        if (seed.empty()) continue;
        for (int i = 0; i < flipped_copies_per_seed; ++i) {
            std::string s = seed;
            for (int k = 0; k < 3; ++k) s[rng() % s.size()] = static_cast<char>(rng());
            run(s);
        }
    }
    for (const auto& e : extra) run(e);
    return runs;
}

std::size_t runCheckedInCorpus(FuzzEntry entry, std::string_view target) {
    std::vector<std::filesystem::path> files;
    for (const auto& dir : {fuzzCorpusDir(target), sourceDir() / "tests" / "fuzz" / "seeds" / target}) {
        if (!std::filesystem::is_directory(dir)) continue;
        for (const auto& e : std::filesystem::directory_iterator(dir)) {
            if (e.is_regular_file()) files.push_back(e.path());
        }
    }
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
        std::fprintf(stderr, "fuzz corpus: %s\n", f.c_str());
        std::ifstream in(f, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        // A copy of exactly the file's size, so reads past the end are caught by ASan builds.
        const std::vector<std::uint8_t> data(bytes.begin(), bytes.end());
        entry(data.data(), data.size());
    }
    return files.size();
}

}  // namespace navmap::test
