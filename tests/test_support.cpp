#include "test_support.h"

#include <cstdlib>

namespace librt::testing {

std::filesystem::path data_dir() {
    if (const char* env = std::getenv("LIBRT_DATA_DIR"); env && *env) return env;
    return LIBRT_DEFAULT_DATA_DIR;
}

bool data_required() {
    const char* env = std::getenv("LIBRT_REQUIRE_DATA");
    return env && std::string(env) == "1";
}

}  // namespace librt::testing
