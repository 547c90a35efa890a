#include "io/file_io.h"

#include <librt/io/check_writable.h>

namespace librt {

void check_writable(const std::filesystem::path& path) {
    // The writers' own first step, discarded: what fails here would fail them at the end.
    const detail::AtomicFile probe(path);
}

}  // namespace librt
