#pragma once
// A directory of the test's own under the system's temp dir, removed with all it holds when
// the object goes, so a test's SQLite database or image files never meet another run's.
// Header-only: the unit tests use it without linking the integration tests' support library.
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace locus::testing {

class TempDir {
public:
    // `tag` names the directory (locus-TAG-XXXXXX) so a leftover one says which test made it.
    explicit TempDir(const std::string& tag = "test") {
        std::string tmpl = (std::filesystem::temp_directory_path() / ("locus-" + tag + "-XXXXXX")).string();
        if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed for " + tmpl);
        dir_ = tmpl;
    }
    ~TempDir() {
        std::error_code ignored;  // a destructor must not throw; the OS cleans temp later
        std::filesystem::remove_all(dir_, ignored);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    std::string file(const std::string& name) const { return (dir_ / name).string(); }
    // The test's SQLite database file (not yet created).
    std::string path() const { return file("t.db"); }

private:
    std::filesystem::path dir_;
};

}  // namespace locus::testing
