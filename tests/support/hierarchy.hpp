#pragma once
// Builds a small map -> building -> floor -> radio map -> RPs over HTTP for integration tests.
#include <cstdint>
#include <string>

#include "server_process.hpp"

namespace locus::testing {

struct Hierarchy {
    std::int64_t map = 0, building = 0, floor = 0, radiomap = 0;
};

// Creates the chain with fixed names; fails the current test (ADD_FAILURE) on any non-201.
Hierarchy make_hierarchy(const ServerProcess& server, const std::string& map_name = "HQ");
std::int64_t make_rp(const ServerProcess& server, std::int64_t radiomap, const std::string& name, double x, double y);

}  // namespace locus::testing
