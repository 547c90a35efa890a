#include <librt/version.h>

namespace librt {

const char* library_version_string() { return LIBRT_VERSION_STRING; }

}  // namespace librt
