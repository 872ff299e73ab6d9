#include "http/front/slots.hpp"

#include "http/api_error.hpp"

namespace locus::http {

Slots::Held Slots::take(httplib::Response& res, const std::string& busy_message, int retry_after_s) {
    {
        std::lock_guard lock(mu_);
        if (free_ > 0) {
            --free_;
            return Held(this);
        }
    }
    res.set_header("Retry-After", std::to_string(retry_after_s));
    throw ApiError(503, "server_busy", busy_message);
}

void Slots::give_back() {
    std::lock_guard lock(mu_);
    ++free_;
}

}  // namespace locus::http
