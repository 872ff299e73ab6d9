#pragma once
// The text of GET /v1/floors/{id}/plan, kept per floor and form (floor metres or WGS84) until
// the change feed says anything changed. Building it reads the stored plan and makes its JSON
// tree, some 20 times the text (a 5.6 MB plan of 50,000 walls: ~100 MB for a moment); kept,
// a GET is one lookup and a copy, and requests arriving while it is built wait for that one
// build (as route graphs do, routing/service.hpp), so a hundred readers asking at once cost
// one build, not a hundred.
//
// Memory: the kept texts, at most `max_bytes` together (past it a text is answered but not
// kept). Any change empties it: plans are written rarely, and a plan's answer also depends on
// its floor's georeference and its rooms.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

#include "store/store.hpp"

namespace locus::http {

class PlanAnswers {
public:
    using Text = std::shared_ptr<const std::string>;
    PlanAnswers(store::Store& store, std::size_t max_bytes = 64u << 20);
    ~PlanAnswers();
    PlanAnswers(const PlanAnswers&) = delete;
    PlanAnswers& operator=(const PlanAnswers&) = delete;

    // The kept text for (floor, form), else `build`'s, shared with the requests that asked
    // meanwhile. Whatever `build` throws reaches every request that waited on it, and nothing
    // is kept.
    Text get(std::int64_t floor_id, bool wgs84, const std::function<std::string()>& build);

private:
    using Key = std::pair<std::int64_t, bool>;
    void on_change();

    store::Store& store_;
    std::size_t max_bytes_;
    std::mutex mu_;
    std::map<Key, std::shared_future<Text>> entries_;
    std::size_t bytes_ = 0;         // of the kept texts that are built
    std::uint64_t generation_ = 0;  // bumped by every change: a build that raced one is not kept
    std::size_t token_ = 0;
};

}  // namespace locus::http
