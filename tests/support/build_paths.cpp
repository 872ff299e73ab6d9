// The paths of build_paths.hpp, given by tests/CMakeLists.txt as compile definitions of this
// file alone.
#include "build_paths.hpp"

namespace locus::build_paths {
const char* server_bin() { return LOCUS_BUILD_SERVER_BIN; }
const char* cli_bin() { return LOCUS_BUILD_CLI_BIN; }
const char* data_dir() { return LOCUS_BUILD_DATA_DIR; }
const char* fixtures_dir() { return LOCUS_BUILD_FIXTURES_DIR; }
const char* source_dir() { return LOCUS_BUILD_SOURCE_DIR; }
}  // namespace locus::build_paths
