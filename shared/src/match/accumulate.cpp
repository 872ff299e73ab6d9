#include "accumulate.hpp"

namespace locus::match {

Workspace::Workspace() noexcept = default;
Workspace::~Workspace() = default;
Workspace::Workspace(Workspace&&) noexcept = default;
Workspace& Workspace::operator=(Workspace&&) noexcept = default;

namespace detail {

// Allocated here rather than in the constructor so a moved-from workspace is usable again.
Scratch& scratch_of(Workspace& workspace) {
    if (!workspace.scratch_) workspace.scratch_ = std::make_unique<Scratch>();
    return *workspace.scratch_;
}

void Scratch::clear() {
    for (auto i : touched) {
        shared[i] = 0;
        acc[i] = 0.0;
        acc_wd[i] = 0.0;
        acc_w[i] = 0.0;
        acc_knn[i] = 0.0;
    }
    touched.clear();
}

Scratch& scratch_for(const Index& index, Workspace& workspace) {
    Scratch& s = scratch_of(workspace);
    const std::size_t n = index.size();
    if (s.shared.size() < n) {
        s.shared.resize(n, 0);
        s.acc.resize(n, 0.0);
        s.acc_wd.resize(n, 0.0);
        s.acc_w.resize(n, 0.0);
        s.acc_knn.resize(n, 0.0);
    }
    s.clear();
    return s;
}

}  // namespace detail

}  // namespace locus::match
