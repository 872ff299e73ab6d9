// Where the build put the binaries under test, and where the sources, the test fixtures and the
// real data sets are (../shared/data beside the repository; tests that need it skip without it).
//
// Absolute paths differ from one clone to the next, so they are compiled into one file only
// (build_paths.cpp, its definitions set in tests/CMakeLists.txt): every other test and benchmark
// source compiles to the same object in any clone, and the compiler cache serves a second clone
// from the first one's build (CMakeLists.txt, LOCUS_CCACHE). The macros keep the names the
// tests always used; each is a C string, so `std::string(LOCUS_DATA_DIR) + "/putmc"`.
#pragma once

namespace locus::build_paths {
const char* server_bin();    // locus-server of this build
const char* cli_bin();       // locus of this build
const char* data_dir();      // the real data sets
const char* fixtures_dir();  // tests/fixtures
const char* source_dir();    // the repository
}  // namespace locus::build_paths

#define LOCUS_SERVER_BIN (::locus::build_paths::server_bin())
#define LOCUS_CLI_BIN (::locus::build_paths::cli_bin())
#define LOCUS_DATA_DIR (::locus::build_paths::data_dir())
#define LOCUS_TEST_FIXTURES (::locus::build_paths::fixtures_dir())
#define LOCUS_SOURCE_DIR (::locus::build_paths::source_dir())
