#include "transmitters/floor_transmitters.hpp"

#include "store/kinds.hpp"

namespace locus::transmitters {

namespace {
// Rows per store page: the API's largest page, so one page costs what a client's list may.
constexpr std::int64_t kPage = 1000;
}  // namespace

std::vector<store::Record> transmitters_of_floor(store::Store& store, std::int64_t floor_id) {
    const store::Kind& k = store::kind("transmitters");
    std::vector<store::Record> out;
    for (std::int64_t offset = 0;; offset += kPage) {
        auto page = store.list(k, floor_id, kPage, offset);
        for (auto& r : page.items) out.push_back(std::move(r));
        if (static_cast<std::int64_t>(out.size()) >= page.total || page.items.empty()) return out;
    }
}

}  // namespace locus::transmitters
