#include "locus/radio_map.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <utility>

namespace locus {

bool valid_rss(double rss) { return std::isfinite(rss) && rss >= kMinRss && rss <= kMaxRss; }

std::string_view trim_bssid(std::string_view raw) {
    // By hand rather than std::isspace: the same set as the "C" locale, without a call per
    // character on every reading of every request.
    const auto space = [](char c) { return c == ' ' || (c >= '\t' && c <= '\r'); };
    while (!raw.empty() && space(raw.front())) raw.remove_prefix(1);
    while (!raw.empty() && space(raw.back())) raw.remove_suffix(1);
    return raw;
}

Bssid::Bssid(std::string_view raw) {
    std::string& out = text_;
    out = trim_bssid(raw);
    // ASCII only and without the locale: this runs for every reading of every request.
    for (auto& c : out)
        if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    // A MAC written aa-bb-cc-dd-ee-ff is the same AP as aa:bb:cc:dd:ee:ff.
    const bool mac_with_dashes = out.size() == 17 &&
        std::all_of(out.begin(), out.end(), [](char c) { return std::isxdigit(static_cast<unsigned char>(c)) || c == '-'; }) &&
        std::count(out.begin(), out.end(), '-') == 5;
    if (mac_with_dashes) std::replace(out.begin(), out.end(), '-', ':');
}

std::vector<Measurement> aggregate_scans(const std::vector<Scan>& scans) {
    std::vector<Measurement> out;
    std::map<std::pair<std::string, Bssid>, std::size_t> index;
    for (const auto& scan : scans) {
        for (const auto& r : scan) {
            auto key = std::make_pair(r.type, r.bssid);
            auto [it, inserted] = index.try_emplace(key, out.size());
            if (inserted) out.push_back(Measurement{key.first, key.second, {}});
            out[it->second].stats.add(r.rss);
        }
    }
    return out;
}

bool combine_aggregates(std::vector<Measurement>& ms, std::string* overflow) {
    std::vector<Measurement> out;
    std::map<std::pair<std::string, Bssid>, std::size_t> index;
    for (auto& m : ms) {
        const auto [it, inserted] = index.try_emplace({m.type, m.bssid}, out.size());
        if (inserted) {
            out.push_back(std::move(m));
            continue;
        }
        auto& into = out[it->second].stats;
        if (!into.can_merge(m.stats)) {
            if (overflow) *overflow = m.bssid;
            return false;
        }
        into.merge(m.stats);
    }
    ms = std::move(out);
    return true;
}

}  // namespace locus
