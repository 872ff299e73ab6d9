#pragma once
// The memory of request bodies in flight (docs/deploy.md "Request bodies in flight"): a body is admitted
// before it is read, against a server-wide budget and a per-client share of it, and holds its
// bytes until its answer has been written. Parsing a body costs a few times its size (its JSON
// document, the request's own types), so bounding the bytes being received and parsed at once
// bounds that memory too: without it, 24 connections of one address sending 8 MiB bodies held
// 2.8 GB, and 100 connections trickling the last bytes of theirs held 0.9 GB.
//
// Small bodies (at most `small_bytes`: a phone's localize, fixes, steps) have a share of their
// own per client and are not counted in the total: a client's large upload in flight does not
// stop its phone, and clients holding the total in large bodies stop no one's phone; yet one
// client's 2,048 connections each holding 64 KiB until their last bytes arrive together parse
// at most `client_small_bytes` at once. A body whose length is not known before it is read
// (chunked, or encoded: its decoded size) counts as the route's limit. A request with the API
// key has no per-client share but counts against the server-wide budget (memory is memory).
//
// Costs: admit() and a ticket's release take one mutex and at most one hash lookup. Memory: one
// entry per client holding a counted body, no more than there are such bodies.
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>

namespace locus::http {

struct BodyBudgetOptions {
    // One body at the 8 MiB limit per client (a JSON document costs up to some 30 times its
    // text: one client's is then within 300 MB), four clients' worth in all. The answers being
    // written and the requests being handled are counted by the same class (app.hpp).
    std::uint64_t total_bytes = 32u << 20;
    std::uint64_t client_bytes = 8u << 20;
    std::uint64_t small_bytes = 64u << 10;
    std::uint64_t client_small_bytes = 1u << 20;  // sixteen small bodies at their largest
};

class BodyBudget {
public:
    explicit BodyBudget(BodyBudgetOptions options) : options_(options) {}
    BodyBudget(const BodyBudget&) = delete;
    BodyBudget& operator=(const BodyBudget&) = delete;

    // What an admitted body holds; its bytes are given back when it is destroyed or reset.
    class Ticket {
    public:
        Ticket() = default;
        Ticket(Ticket&& other) noexcept { *this = std::move(other); }
        Ticket& operator=(Ticket&& other) noexcept;
        ~Ticket() { reset(); }
        void reset();
        std::uint64_t bytes() const { return bytes_; }

    private:
        friend class BodyBudget;
        BodyBudget* budget_ = nullptr;
        std::optional<std::string> client_;
        std::uint64_t bytes_ = 0;
        bool small_ = false;
    };

    enum class Verdict { admitted, server_full, client_full };
    // Admits a body of `bytes` for `client` (nullopt: the operator, no share), filling `ticket`,
    // or says which budget it does not fit. A body that does not fit a budget holding nothing
    // else (larger than the share or the total) is admitted alone, so no body the route's size
    // limit accepts is refused for ever.
    Verdict admit(const std::optional<std::string>& client, std::uint64_t bytes, Ticket& ticket);

    const BodyBudgetOptions& options() const { return options_; }
    std::uint64_t in_flight() const;  // the large bodies' bytes, every client together

private:
    void release(const Ticket& ticket);

    struct Held {
        std::uint64_t large = 0, small = 0;
    };
    BodyBudgetOptions options_;
    mutable std::mutex mu_;
    std::uint64_t total_ = 0;  // large bodies
    std::unordered_map<std::string, Held> clients_;
};

}  // namespace locus::http
