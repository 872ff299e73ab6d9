#pragma once
// What the load commands (`bench localize`, `bench connections`) share: the loopback-only
// target, the localize bodies they replay, and the latency percentiles they report.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "survey_connect.hpp"

namespace locus::tools {

struct Target {
    std::string host;  // as getaddrinfo wants it: no brackets around an IPv6 address
    int port = 0;
    std::string host_port;  // for the Host header
};

// Only loopback servers: a load test must not leave the machine. `command` names the caller
// in the error.
Target loopback_target(const std::string& url, const std::string& command);

// Localize bodies replaying real scans: a UJIIndoorLoc CSV (one query per row), a survey file
// (one per scan), or, with no file, each RP of the radio map queried with its own stored
// means. Scans that share no AP with the radio map (another building's rows) would only
// measure the 422 path, so they are left out.
std::vector<std::string> localize_bodies(const ServerArgs& server, std::int64_t radiomap, const std::string& scans_file,
                                         const std::string& algorithm);

// The latency figures the load commands print, {"p50_ms", "p99_ms"}: interpolated percentiles
// (locus/metrics.hpp) of `ms`, 0 when nothing was answered. Sorts `ms`.
nlohmann::json latency_percentiles(std::vector<double>& ms);

}  // namespace locus::tools
