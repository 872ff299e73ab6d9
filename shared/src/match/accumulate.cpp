#include "accumulate.hpp"

namespace locus::match::detail {

namespace {
thread_local Scratch t_scratch;
}  // namespace

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

Scratch& scratch_for(const Index& index) {
    Scratch& s = t_scratch;
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

}  // namespace locus::match::detail
