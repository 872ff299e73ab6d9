#include "localize_body.hpp"

#include <cmath>
#include <nlohmann/json.hpp>

namespace locus::tools {

std::string localize_body(const std::vector<Scan>& scans, const std::string& algorithm) {
    using nlohmann::json;
    json s = json::array();
    for (const auto& scan : scans) {
        json readings = json::array();
        for (const auto& r : scan) {
            json reading = {{"bssid", r.bssid}};
            if (r.rss == std::trunc(r.rss)) reading["rss"] = static_cast<long long>(r.rss);
            else reading["rss"] = r.rss;
            if (r.type != "wifi") reading["type"] = r.type;
            readings.push_back(std::move(reading));
        }
        s.push_back(std::move(readings));
    }
    return json{{"algorithm", algorithm}, {"scans", s}}.dump();
}

}  // namespace locus::tools
