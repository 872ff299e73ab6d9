#include "proc_status.hpp"

#include <fstream>

namespace locus::tools {

long long proc_status_kb(int pid, const std::string& field) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(field, 0) == 0) {
            try {
                return std::stoll(line.substr(field.size()));
            } catch (const std::exception&) {
                return -1;
            }
        }
    return -1;
}

}  // namespace locus::tools
