#include "store/store.hpp"

#include <algorithm>

namespace locus::store {

std::size_t Store::subscribe(ChangeListener listener) {
    std::lock_guard lock(listeners_mu_);
    listeners_.emplace_back(next_token_, std::move(listener));
    return next_token_++;
}

void Store::unsubscribe(std::size_t token) {
    std::lock_guard lock(listeners_mu_);
    std::erase_if(listeners_, [token](const auto& l) { return l.first == token; });
}

void Store::publish(const std::vector<Change>& changes) {
    // Held while listeners run, so that once unsubscribe returns none is still running.
    std::lock_guard lock(listeners_mu_);
    // The write has committed: a listener that fails must neither turn it into an error for
    // the client nor keep the change from the listeners after it. Listeners catch what they
    // can handle (localize::Service marks everything stale), so this is a last resort.
    for (const auto& change : changes)
        for (const auto& [token, listener] : listeners_) try {
                listener(change);
            } catch (...) {
            }
}

}  // namespace locus::store
