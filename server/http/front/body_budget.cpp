#include "http/front/body_budget.hpp"

#include <utility>

namespace locus::http {

BodyBudget::Ticket& BodyBudget::Ticket::operator=(Ticket&& other) noexcept {
    if (this != &other) {
        reset();
        budget_ = std::exchange(other.budget_, nullptr);
        client_ = std::move(other.client_);
        bytes_ = std::exchange(other.bytes_, 0);
        small_ = other.small_;
    }
    return *this;
}

void BodyBudget::Ticket::reset() {
    if (budget_) budget_->release(*this);
    budget_ = nullptr;
    client_.reset();
    bytes_ = 0;
}

BodyBudget::Verdict BodyBudget::admit(const std::optional<std::string>& client, std::uint64_t bytes, Ticket& ticket) {
    ticket.reset();
    if (bytes == 0) return Verdict::admitted;
    const bool small = bytes <= options_.small_bytes;
    std::lock_guard lock(mu_);
    if (small && !client) return Verdict::admitted;  // the operator's small bodies: nothing to share
    if (!small && total_ > 0 && total_ + bytes > options_.total_bytes) return Verdict::server_full;
    if (client) {
        Held& held = clients_[*client];
        std::uint64_t& mine = small ? held.small : held.large;
        const std::uint64_t share = small ? options_.client_small_bytes : options_.client_bytes;
        if (mine > 0 && mine + bytes > share) return Verdict::client_full;
        mine += bytes;
    }
    if (!small) total_ += bytes;
    ticket.budget_ = this;
    ticket.client_ = client;
    ticket.bytes_ = bytes;
    ticket.small_ = small;
    return Verdict::admitted;
}

void BodyBudget::release(const Ticket& ticket) {
    std::lock_guard lock(mu_);
    if (!ticket.small_) total_ -= ticket.bytes_;
    if (!ticket.client_) return;
    const auto it = clients_.find(*ticket.client_);
    if (it == clients_.end()) return;
    (ticket.small_ ? it->second.small : it->second.large) -= ticket.bytes_;
    if (it->second.large == 0 && it->second.small == 0) clients_.erase(it);
}

std::uint64_t BodyBudget::in_flight() const {
    std::lock_guard lock(mu_);
    return total_;
}

}  // namespace locus::http
