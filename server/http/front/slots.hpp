#pragma once
// A fixed number of slots for work that holds something scarce for long (a core, a database
// snapshot): a request finding none free is answered 503 server_busy with Retry-After at once,
// rather than queued behind the others on an HTTP worker. Used by GET …/quality (CPU) and
// GET …/export (a connection and read snapshot each, for as long as the client reads).
#include <httplib.h>

#include <cstddef>
#include <mutex>
#include <string>

namespace locus::http {

class Slots {
public:
    // A taken slot, given back when the last owner lets go of it; movable, so it can live in a
    // response's content provider as long as the answer is being written.
    class Held {
    public:
        Held(Held&& other) noexcept : slots_(other.slots_) { other.slots_ = nullptr; }
        Held& operator=(Held&&) = delete;
        Held(const Held&) = delete;
        Held& operator=(const Held&) = delete;
        ~Held() {
            if (slots_) slots_->give_back();
        }

    private:
        friend class Slots;
        explicit Held(Slots* slots) : slots_(slots) {}
        Slots* slots_;
    };

    explicit Slots(std::size_t count) : free_(count) {}
    Slots(const Slots&) = delete;
    Slots& operator=(const Slots&) = delete;

    // A slot, or ApiError 503 server_busy (`busy_message`) with Retry-After set on `res`.
    Held take(httplib::Response& res, const std::string& busy_message, int retry_after_s = 1);

private:
    void give_back();
    std::mutex mu_;
    std::size_t free_;
};

}  // namespace locus::http
