#pragma once
// A JSON-aware mutator for the targets whose input is a JSON body. libFuzzer's byte mutations
// rarely keep a document valid enough to pass validation, so half the time the input is
// parsed, one node is changed (to null, an edge value, another key's value, a copy of a
// sibling, ...) and the document is written back. Inputs that do not parse, and the other
// half, get libFuzzer's own mutations (with the target's dictionary).
#include <cstddef>
#include <cstdint>
#include <cmath>
#include <cstring>
#include <iterator>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <utility>
#include <vector>

extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

namespace locus::fuzz {

inline std::size_t mutate_json(std::uint8_t* data, std::size_t size, std::size_t max_size, unsigned seed) {
    using nlohmann::json;
    std::minstd_rand rng(seed);
    auto pick = [&](std::size_t n) { return static_cast<std::size_t>(rng() % n); };
    if (pick(2) == 0) return LLVMFuzzerMutate(data, size, max_size);
    json doc = json::parse(data, data + size, nullptr, false);
    if (doc.is_discarded()) return LLVMFuzzerMutate(data, size, max_size);

    // Every node, iteratively; deep documents are left to the byte mutations (dump recurses).
    std::vector<std::pair<json*, int>> stack{{&doc, 0}};
    std::vector<json*> nodes;
    while (!stack.empty()) {
        auto [node, depth] = stack.back();
        stack.pop_back();
        if (depth > 64) return LLVMFuzzerMutate(data, size, max_size);
        nodes.push_back(node);
        if (node->is_structured())
            for (auto& child : *node) stack.emplace_back(&child, depth + 1);
    }
    json& n = *nodes[pick(nodes.size())];

    static const char* const kKeys[] = {"name", "description", "format", "rps", "x", "y", "scans", "measurements",
                                        "type", "bssid", "rss", "mean", "variance", "count", "algorithm", "options",
                                        "upload_id", "k", "near", "radius", "candidates"};
    const json kNumbers[] = {0, -0.0, -1, 1, -120, -120.000001, 0.000001, 1.5, 3600, 3600.000002, 1e7, -1e7, 10000000.5,
                             std::int64_t{1} << 53, (std::int64_t{1} << 53) + 1, 1e300, -1e-300, 2.0, 9.0e18,
                             std::uint64_t{18446744073709551615u}};
    const json kStrings[] = {"", " ", "wifi", "ble", "WIFI", "locus-radiomap/1", "AA-BB-CC-DD-EE-FF", "aa:bb:cc:dd:ee:ff",
                             " aa:bb:cc:dd:ee:ff ", std::string(64, 'b'), std::string(65, 'b'), std::string(201, 'n'),
                             "\xc3\xa9", "a\tb", "bayes", "wknn", "nn"};
    switch (pick(9)) {
        case 0: n = nullptr; break;
        case 1: n = kNumbers[pick(std::size(kNumbers))]; break;
        case 2: n = kStrings[pick(std::size(kStrings))]; break;
        case 3:  // a copy of one of its elements, appended
            if (n.is_array() && !n.empty()) n.push_back(json(n[pick(n.size())]));
            else if (n.is_object()) n[kKeys[pick(std::size(kKeys))]] = n.empty() ? json(1) : json(n.begin().value());
            break;
        case 4:  // one element or key fewer
            if (n.is_array() && !n.empty()) n.erase(pick(n.size()));
            else if (n.is_object() && !n.empty()) n.erase(std::next(n.begin(), static_cast<std::ptrdiff_t>(pick(n.size()))));
            break;
        case 5: n = pick(2) ? json(pick(2) == 0) : pick(2) ? json::array() : json::object(); break;
        case 6:  // a nearby number
            if (n.is_number()) {
                const double d = n.get<double>();
                const double options[] = {d + 1, d - 1, -d, d * 2, d / 3, std::nextafter(d, 1e300), std::nextafter(d, -1e300)};
                n = options[pick(std::size(options))];
            } else {
                n = kNumbers[pick(std::size(kNumbers))];
            }
            break;
        case 7:  // the same node one level deeper
            n = pick(2) ? json::array({n}) : json{{kKeys[pick(std::size(kKeys))], n}};
            break;
        default:  // another node's value (a whole reading, RP or scan, say) in its place
            n = json(*nodes[pick(nodes.size())]);
            break;
    }
    const std::string out = doc.dump(-1, ' ', false, json::error_handler_t::replace);
    if (out.size() > max_size) return LLVMFuzzerMutate(data, size, max_size);
    std::memcpy(data, out.data(), out.size());
    return out.size();
}

}  // namespace locus::fuzz

// Each JSON target defines libFuzzer's hook with this line.
#define LOCUS_FUZZ_JSON_MUTATOR                                                                              \
    extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size, \
                                                   unsigned int seed) {                                        \
        return locus::fuzz::mutate_json(data, size, max_size, seed);                                           \
    }
