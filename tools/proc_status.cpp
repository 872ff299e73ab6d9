#include "proc_status.hpp"

#include <unistd.h>

#include <fstream>
#include <iterator>
#include <sstream>

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

double proc_cpu_seconds(int pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
    const std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto name_end = stat.rfind(')');  // field 2, the command name, may hold spaces and ')'
    if (name_end == std::string::npos || name_end + 2 > stat.size()) return -1.0;
    std::istringstream fields(stat.substr(name_end + 2));
    std::string field;
    double utime = -1.0, stime = -1.0;
    for (int i = 3; i <= 15 && fields >> field; ++i) {
        if (i == 14) utime = std::stod(field);
        if (i == 15) stime = std::stod(field);
    }
    if (utime < 0 || stime < 0) return -1.0;
    return (utime + stime) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

}  // namespace locus::tools
