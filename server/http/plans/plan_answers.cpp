#include "http/plans/plan_answers.hpp"

#include <exception>

namespace locus::http {

PlanAnswers::PlanAnswers(store::Store& store, std::size_t max_bytes) : store_(store), max_bytes_(max_bytes) {
    token_ = store_.subscribe([this](const store::Change&) { on_change(); });
}

PlanAnswers::~PlanAnswers() { store_.unsubscribe(token_); }

void PlanAnswers::on_change() {
    std::lock_guard lock(mu_);
    entries_.clear();  // builds under way keep their own futures; their results are not kept
    bytes_ = 0;
    ++generation_;
}

PlanAnswers::Text PlanAnswers::get(std::int64_t floor_id, bool wgs84, const std::function<std::string()>& build) {
    const Key key{floor_id, wgs84};
    std::promise<Text> promise;
    std::shared_future<Text> waiting;
    std::uint64_t generation = 0;
    {
        std::lock_guard lock(mu_);
        if (const auto it = entries_.find(key); it != entries_.end()) {
            waiting = it->second;
        } else {
            entries_.emplace(key, promise.get_future().share());
            generation = generation_;
        }
    }
    if (waiting.valid()) return waiting.get();  // kept, or being built: its text or its exception
    Text text;
    try {
        text = std::make_shared<const std::string>(build());
    } catch (...) {
        promise.set_exception(std::current_exception());
        std::lock_guard lock(mu_);
        if (generation == generation_) entries_.erase(key);
        throw;
    }
    promise.set_value(text);
    std::lock_guard lock(mu_);
    if (generation == generation_) {
        if (bytes_ + text->size() <= max_bytes_) bytes_ += text->size();
        else entries_.erase(key);  // answered, not kept
    }
    return text;
}

}  // namespace locus::http
