#pragma once
// When and how long the client waits before trying a request again. Pure, so it is testable.
#include <chrono>
#include <cstdint>

namespace locus::api {

struct RetryPolicy {
    int max_attempts = 6;  // first try included
    std::chrono::milliseconds initial_backoff{100};
    std::chrono::milliseconds max_backoff{5000};
    double multiplier = 2.0;
};

// A status of 0 means the request got no answer (connection refused, reset, timed out).
// 4xx other than 429 says the request itself is wrong: sending it again cannot help.
bool is_retryable(int status);

// Delay before attempt `attempt` (1 = the first retry): initial · multiplier^(attempt-1),
// capped at max_backoff, then scaled by `jitter` in [0.5, 1] so that many clients that
// failed together do not all come back together.
std::chrono::milliseconds backoff_delay(const RetryPolicy& policy, int attempt, double jitter = 1.0);

}  // namespace locus::api
