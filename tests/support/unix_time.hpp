#pragma once
// Now in Unix seconds, as a phone stamps its fixes and steps (the tracks tests date their inputs
// from it: a track keeps only those within its retention).
#include <chrono>

namespace locus::testing {

inline double unix_now() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

}  // namespace locus::testing
