#pragma once
// Where tests find data: the repo's own data/ (always there) and ../shared/data (developer and
// CI machines only; tests that need it skip with a reason when it is absent).

#include <filesystem>
#include <optional>

namespace navmap::test {

std::filesystem::path sourceDir();
std::filesystem::path binaryDir();
std::filesystem::path dataDir();  ///< the repo's data/
/// ../shared/data beside the checkout, if present.
std::optional<std::filesystem::path> sharedDataDir();

}  // namespace navmap::test
