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
    for (const auto& change : changes)
        for (const auto& [token, listener] : listeners_) listener(change);
}

}  // namespace locus::store
