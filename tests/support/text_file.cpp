#include "text_file.hpp"

#include <fstream>
#include <sstream>

namespace locus::testing {

std::string slurp(const std::string& path) {
    std::ifstream in(path);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

}  // namespace locus::testing
