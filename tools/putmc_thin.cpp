#include "putmc_thin.hpp"

#include "walk_eval.hpp"

namespace locus::tools::walks {

std::vector<ThinBatch> thin_batches(const datasets::putmc::Walk& walk) {
    const std::vector<PhoneStep> steps = detect_steps(walk);
    std::vector<ThinBatch> out;
    out.reserve(walk.scans.size());
    std::size_t next = 0;
    for (const auto& scan : walk.scans) {
        ThinBatch b;
        b.t_s = scan.t_s;
        b.scan = &scan;
        b.truth = walk.truth_of(scan);
        while (next < steps.size() && steps[next].t_s <= scan.t_s) b.steps.push_back(steps[next++]);
        out.push_back(std::move(b));
    }
    return out;
}

}  // namespace locus::tools::walks
