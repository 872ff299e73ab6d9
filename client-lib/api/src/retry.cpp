#include "locus/api/retry.hpp"

#include <algorithm>
#include <cmath>

namespace locus::api {

bool is_retryable(int status) { return status == 0 || status == 429 || status >= 500; }

std::chrono::milliseconds backoff_delay(const RetryPolicy& policy, int attempt, double jitter) {
    if (attempt < 1) return std::chrono::milliseconds{0};
    const double base = static_cast<double>(policy.initial_backoff.count()) * std::pow(policy.multiplier, attempt - 1);
    const double capped = std::min(base, static_cast<double>(policy.max_backoff.count()));
    const double j = std::clamp(jitter, 0.5, 1.0);
    return std::chrono::milliseconds{static_cast<std::int64_t>(std::llround(capped * j))};
}

}  // namespace locus::api
