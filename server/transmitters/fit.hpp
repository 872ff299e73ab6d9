#pragma once
// Fitting each AP's log-distance model (ranging/fit.hpp) to a floor's survey: every AP heard in
// the floor's surveyed RPs gets its tx power and exponent fitted at its stored position, or the
// position too when the floor has no transmitter of that type and bssid (or `refit_positions`);
// `apply` stores the fits in one transaction (known transmitters updated, new ones created).
// POST /v1/floors/{id}/transmitters/fit is its HTTP face (http/transmitters/transmitter_fit.cpp).
//
// Cost: one read of every RP of the floor's radio maps and of its transmitters, then one fit
// per AP heard at enough RPs (a least-squares solve over its samples; a position fit searches
// the floor, ranging/fit.hpp), all on the caller's thread; at most one write transaction.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/ranging/path_loss.hpp"
#include "store/store.hpp"

namespace locus::transmitters {

struct FitRequest {
    std::int64_t floor_id = 0;
    int min_rps = 5;               // an AP heard at fewer RPs is skipped (a named one refuses)
    bool refit_positions = false;  // fit known transmitters' positions too
    double phone_height = 1.2;     // m, against a transmitter's z
    std::set<std::int64_t> named;  // transmitter ids that must be fitted; empty: every AP heard
    bool apply = false;            // store the fits
};

struct FittedTransmitter {
    std::optional<std::int64_t> id;  // the floor's transmitter; none for a new one not applied
    std::string type, bssid;
    Point at;
    bool position_fitted = false;  // else `at` is the stored position
    ranging::PathLoss model;
    double r2 = 0.0, residual_db = 0.0;
    int rps = 0;  // samples the fit used
};

struct SkippedTransmitter {
    std::string type, bssid;
    std::size_t rps = 0;
    std::string reason;  // too_few_rps, degenerate (every RP at one distance), implausible_tx_power
};

struct FitResult {
    std::size_t rps = 0;  // surveyed RPs of the floor
    bool applied = false;
    std::vector<FittedTransmitter> fitted;  // by type and bssid
    std::vector<SkippedTransmitter> skipped;
};

// NotFound for an unknown floor or a named transmitter not on it; Refused `too_few_rps` when a
// named transmitter is heard at fewer than `min_rps` RPs (nothing is written then).
FitResult fit_transmitters(store::Store& store, const FitRequest& request);

}  // namespace locus::transmitters
