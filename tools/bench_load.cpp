#include "bench_load.hpp"

#include <httplib.h>

#include <algorithm>
#include <chrono>
#include <nlohmann/json.hpp>
#include <set>

#include "command_registry.hpp"
#include "datasets/survey_format.hpp"
#include "datasets/uji_csv.hpp"
#include "localize_body.hpp"
#include "locus/api/client.hpp"
#include "locus/metrics.hpp"
#include "survey_connect.hpp"

namespace locus::tools {

using nlohmann::json;

Target loopback_target(const std::string& url, const std::string& command) {
    for (const char* prefix : {"http://127.0.0.1:", "http://localhost:", "http://[::1]:"}) {
        const std::string p = prefix;
        if (url.rfind(p, 0) != 0) continue;
        Target t;
        t.host_port = url.substr(7);
        while (!t.host_port.empty() && t.host_port.back() == '/') t.host_port.pop_back();
        t.host = p.substr(7, p.size() - 8);
        if (t.host.front() == '[') t.host = t.host.substr(1, t.host.size() - 2);
        try {
            std::size_t used = 0;
            t.port = std::stoi(url.substr(p.size()), &used);
            if (p.size() + used != 7 + t.host_port.size() || t.port < 1 || t.port > 65535) throw std::invalid_argument("port");
        } catch (const std::exception&) {
            throw CommandError("cannot read the port of " + url);
        }
        return t;
    }
    throw CommandError(command + " only targets a loopback server (http://127.0.0.1:PORT)");
}

std::vector<std::string> localize_bodies(const ServerArgs& server, std::int64_t radiomap, const std::string& scans_file,
                                         const std::string& algorithm) {
    httplib::Client http(server.client_options().base_url);
    // cpp-httplib's default 5 s is too short for a large radio map: 100,000 RPs take ~10 s.
    http.set_read_timeout(std::chrono::seconds(300));
    auto r = http.Get("/v1/radiomaps/" + std::to_string(radiomap) + "/export");
    if (!r) {
        // The REST client retries and names the reason: "cannot connect to URL (connection
        // refused) after 6 attempts; is locus-server running?".
        locus::api::Client(server.client_options()).get("/health");
        throw CommandError("no answer from " + server.server + " (" + httplib::to_string(r.error()) + ")");
    }
    if (r->status != 200) {
        // The server's {"error": {"code", "message"}}: a 404 means there is no such radio map.
        const json err = json::parse(r->body, nullptr, false);
        std::string message = r->body.substr(0, 300);
        if (err.is_object() && err.contains("error") && err["error"].is_object())
            message = err["error"].value("message", message);
        const std::string rm = "radio map " + std::to_string(radiomap);
        if (r->status == 404) throw CommandError(rm + " does not exist on " + server.server + " (" + message + ")");
        throw CommandError("cannot read " + rm + " (HTTP " + std::to_string(r->status) + "): " + message);
    }
    const json doc = json::parse(r->body);
    std::set<std::string> known;
    std::vector<Scan> scans;
    for (const auto& rp : doc.at("rps")) {
        Scan s;
        for (const auto& m : rp.at("measurements")) {
            s.push_back({m.value("type", "wifi"), m.at("bssid").get<std::string>(), m.at("mean").get<double>()});
            known.insert(s.back().bssid);
        }
        if (scans_file.empty()) scans.push_back(std::move(s));
    }
    if (!scans_file.empty()) {
        const std::string text = read_file(scans_file);
        if (text.rfind("WAP", 0) == 0) {
            const auto data = datasets::uji::parse(text);
            for (const auto& row : data.rows) scans.push_back(datasets::uji::scan_of(data, row));
        } else {
            const auto file = datasets::survey::parse(text, datasets::survey::format_of(scans_file));
            for (const auto& rp : file.rps) scans.insert(scans.end(), rp.scans.begin(), rp.scans.end());
        }
    }
    std::vector<std::string> bodies;
    for (const auto& s : scans)
        if (std::any_of(s.begin(), s.end(), [&](const Reading& rd) { return known.count(rd.bssid) > 0; }))
            bodies.push_back(localize_body({s}, algorithm));
    if (bodies.empty()) throw CommandError("no scan shares an access point with radio map " + std::to_string(radiomap));
    return bodies;
}

json latency_percentiles(std::vector<double>& ms) {
    if (ms.empty()) return {{"p50_ms", 0.0}, {"p99_ms", 0.0}};
    std::sort(ms.begin(), ms.end());
    return {{"p50_ms", metrics::percentile_interpolated(ms, 0.50)}, {"p99_ms", metrics::percentile_interpolated(ms, 0.99)}};
}

}  // namespace locus::tools
