#include "fuzz_corpus.h"

#include <random>

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

}  // namespace navmap::test
