#include "locus/match/cv_folds.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>

namespace locus::match {

namespace {

// The number after "name:", whole text consumed; nullopt otherwise.
template <class T>
std::optional<T> number_after(std::string_view text, std::string_view name) {
    if (text.size() <= name.size() + 1 || text.substr(0, name.size()) != name || text[name.size()] != ':')
        return std::nullopt;
    const std::string_view digits = text.substr(name.size() + 1);
    T value{};
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (ec != std::errc{} || end != digits.data() + digits.size()) return std::nullopt;
    return value;
}

// The cell holding coordinate v. Converting a double outside long long's range is undefined:
// a coordinate that far out (or not finite) shares the outermost cell on its side.
long long cell_index(double v, double cell_m) {
    constexpr double kLimit = 9.0e18;  // below 2^63, and exact as a double
    const double q = std::floor(v / cell_m);
    if (std::isnan(q)) return 0;
    return static_cast<long long>(std::clamp(q, -kLimit, kLimit));
}

}  // namespace

std::optional<FoldScheme> parse_fold_scheme(std::string_view text) {
    if (text == "position") return FoldScheme{};
    if (auto g = number_after<double>(text, "spatial"); g && std::isfinite(*g) && *g >= kMinCellM)
        return FoldScheme{FoldBlocks::spatial, *g, 1};
    // from_chars into an unsigned type would reject "-3" anyway; long long keeps 0 and negatives explicit.
    if (auto n = number_after<long long>(text, "order"); n && *n >= 1)
        return FoldScheme{FoldBlocks::order, 0.0, static_cast<std::size_t>(*n)};
    return std::nullopt;
}

std::string to_string(const FoldScheme& scheme) {
    switch (scheme.blocks) {
        case FoldBlocks::spatial: {
            // The shortest text that reads back as the same double ("20", "2.5", "0.01"):
            // fixed six decimals printed 1e-7 as "0".
            char buf[32];
            const auto r = std::to_chars(buf, buf + sizeof buf, scheme.cell_m);
            return "spatial:" + std::string(buf, r.ptr);
        }
        case FoldBlocks::order:
            return "order:" + std::to_string(scheme.run);
        case FoldBlocks::position:
            break;
    }
    return "position";
}

std::vector<int> assign_folds(std::span<const FoldSite> sites, int k, const FoldScheme& scheme) {
    if (k < 1) throw std::invalid_argument("a CV needs at least 1 fold");
    if (scheme.blocks == FoldBlocks::spatial && !(scheme.cell_m >= kMinCellM && std::isfinite(scheme.cell_m)))
        throw std::invalid_argument("a spatial block needs a cell side of at least 0.01 m");
    if (scheme.blocks == FoldBlocks::order && scheme.run < 1)
        throw std::invalid_argument("an order block needs at least 1 position");

    // Positions, numbered in order of their first scan.
    std::map<std::tuple<long long, long long, double, double>, std::size_t> position_of;
    std::vector<std::size_t> position(sites.size());
    std::vector<std::size_t> first_site;  // per position
    for (std::size_t i = 0; i < sites.size(); ++i) {
        const auto& s = sites[i];
        const auto [it, inserted] = position_of.try_emplace({s.building, s.floor, s.at.x, s.at.y}, first_site.size());
        if (inserted) first_site.push_back(i);
        position[i] = it->second;
    }

    // Each position's block, blocks numbered in order of their first position.
    std::vector<std::size_t> block(first_site.size());
    std::size_t blocks = 0;
    switch (scheme.blocks) {
        case FoldBlocks::position:
            for (std::size_t p = 0; p < block.size(); ++p) block[p] = p;
            blocks = block.size();
            break;
        case FoldBlocks::order:
            for (std::size_t p = 0; p < block.size(); ++p) block[p] = p / scheme.run;
            blocks = (block.size() + scheme.run - 1) / scheme.run;
            break;
        case FoldBlocks::spatial: {
            std::map<std::tuple<long long, long long, long long, long long>, std::size_t> cell_block;
            for (std::size_t p = 0; p < block.size(); ++p) {
                const auto& s = sites[first_site[p]];
                const auto cx = cell_index(s.at.x, scheme.cell_m);
                const auto cy = cell_index(s.at.y, scheme.cell_m);
                block[p] = cell_block.try_emplace({s.building, s.floor, cx, cy}, cell_block.size()).first->second;
            }
            blocks = cell_block.size();
            break;
        }
    }

    // Blocks in order of first appearance, each to the least-loaded fold: balanced in
    // positions without sorting by size, and blocks next to each other in the file (often next
    // to each other in space) land in different folds.
    std::vector<std::size_t> size(blocks, 0);
    for (const auto b : block) ++size[b];
    std::vector<std::size_t> load(static_cast<std::size_t>(k), 0);
    std::vector<int> fold_of_block(blocks);
    for (std::size_t b = 0; b < blocks; ++b) {
        const auto f = static_cast<std::size_t>(std::min_element(load.begin(), load.end()) - load.begin());
        fold_of_block[b] = static_cast<int>(f);
        load[f] += size[b];
    }

    std::vector<int> out(sites.size());
    for (std::size_t i = 0; i < sites.size(); ++i) out[i] = fold_of_block[block[position[i]]];
    return out;
}

}  // namespace locus::match
