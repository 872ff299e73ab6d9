#pragma once
// Small text helpers the tests that run the CLI or read fixtures share.
#include <string>

namespace locus::testing {

// The whole file as text; empty when it cannot be read (the assertion on its content says so).
std::string slurp(const std::string& path);

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace locus::testing
