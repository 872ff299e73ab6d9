#pragma once
// The matchers' working memory, owned by the caller: the core keeps no state between calls,
// so concurrency is whatever the caller makes of it.
#include <memory>

namespace locus::match {

class Workspace;

namespace detail {
struct Scratch;
Scratch& scratch_of(Workspace& workspace);
}  // namespace detail

// What match::localize works in: one accumulator slot per reference point of the index
// (an int and four doubles, 36 bytes; 933 UJIIndoorLoc RPs take about 34 KB), plus the
// query's known APs and its scored candidates. It is allocated on first use and grows to
// the largest index and query it has served, and it never shrinks: with a warmed-up
// workspace the per-posting and per-RP loops allocate nothing (a query still allocates its
// Result and the short list of RPs its answer is built from), and destroying the workspace
// is how that memory is given back. Any workspace serves any Index, and an answer never
// depends on what the workspace served before.
//
// Not thread-safe: concurrent queries need a workspace each; keep one per worker thread
// and reuse it for every query that thread runs. Constructing one is free.
class Workspace {
public:
    Workspace() noexcept;
    ~Workspace();
    Workspace(Workspace&&) noexcept;
    Workspace& operator=(Workspace&&) noexcept;
    // A copy would only duplicate memory that is meaningless between queries.
    Workspace(const Workspace&) = delete;
    Workspace& operator=(const Workspace&) = delete;

private:
    friend detail::Scratch& detail::scratch_of(Workspace& workspace);
    // Opaque so the matchers' internal types stay out of the public headers; the matchers
    // resolve the pointer once per query, never per posting.
    std::unique_ptr<detail::Scratch> scratch_;
};

}  // namespace locus::match
