#pragma once
// Where a radio map is weak (GET /v1/radiomaps/{id}/quality, the viewer's predicted-error
// layer): each RP held out as tune's folds hold them out (locus/match/tune.hpp) and localized,
// with its stored means as the scan, by one setting: the radio map's own. An RP whose
// neighbours cannot place it is where a phone there will be placed badly too.
#include <cstddef>
#include <optional>
#include <vector>

#include "locus/match/index.hpp"
#include "locus/match/tune.hpp"

namespace locus::match {

struct RpQuality {
    std::size_t rp = 0;                // index into the RPs given
    std::optional<double> error_m;     // EvAAL-style (tune's penalties); none: not localized (subsample, no measurement)
    std::optional<double> horizontal_m;  // none also when no answer (then error_m is the building penalty)
    bool floor_ok = false;
};

struct QualityReport {
    std::vector<RpQuality> rps;  // one per RP given, in their order
    std::size_t folds = 0, queries = 0;
    bool subsampled = false;
};

// Throws TuneRefused as tune does (fewer than 2 RPs, no measurement at all).
QualityReport held_out_errors(const std::vector<IndexedRp>& rps, const Setting& setting, const FloorLevel& level_of,
                              const TuneLimits& limits = {}, const IndexParams& params = {});

}  // namespace locus::match
