#pragma once
// Choosing a radio map's matcher settings from its own RPs, and saying how well the chosen
// ones do: tune cross-validates the RPs over a small grid of settings (match::tune), stores
// the best as the radio map's settings and returns the CV table; quality gives each RP's
// held-out error with the current settings (match::held_out_errors, tune's folds), for the
// viewer's predicted-error layer. POST /v1/radiomaps/{id}/tune and GET …/quality are their HTTP
// face (http/radiomaps/tune_routes.cpp).
//
// Both run on the caller's thread over one snapshot of the RPs (a read of the radio map's RPs
// and of each floor's level) and hold no lock a localize needs: localize keeps the old settings
// until the new ones are committed, and the commit's change makes its index pick them up.
// Cost: a quality assessment is one setting over up to max_queries held-out RPs (up to ~0.4 s
// of a core); a tune is that for every candidate of the grid (0.27 s on UJIIndoorLoc's 933
// RPs, 1.5 s on TUT6, docs/matchers.md "Self-tuning radio maps"). So one tune per radio map
// runs at a time (a second would only compute the same table again), and at most
// `quality_at_once` assessments run at once: it is an open GET, and a burst is refused (Busy)
// rather than queued where it would starve localize.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <string>
#include <unordered_set>
#include <vector>

#include "locus/match/index.hpp"
#include "locus/match/quality.hpp"
#include "locus/match/tune.hpp"
#include "store/documents.hpp"
#include "store/store.hpp"

namespace locus::tuning {

// How the settings are spelled in the store: JSON text, which http/ writes and reads
// (http/radiomaps/radiomap_settings.hpp); this layer only moves the text.
struct SettingsText {
    // The stored text read back; the built-in defaults when it is unreadable.
    std::function<match::Setting(const std::string& text)> read;
    std::function<std::string(const match::Setting& setting)> write;
    // The CV table of a tune that took `seconds`.
    std::function<std::string(const match::TuneReport& report, double seconds)> write_table;
};

// Every quality slot is taken (the API answers 503 server_busy with Retry-After).
struct Busy : std::runtime_error {
    using std::runtime_error::runtime_error;
};
// The radio map is being tuned already (the API answers 409 tune_running).
struct Running : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct Quality {
    match::Setting setting;  // the radio map's settings, or the built-in defaults
    bool tuned = false;      // the settings are stored (a tune chose them)
    std::vector<match::IndexedRp> rps;  // the snapshot assessed; report.rps index into it
    match::QualityReport report;
};

struct Tuned {
    match::TuneReport report;  // report.rows[report.best].setting is what was stored
    double seconds = 0.0;      // the tune's duration, snapshot included
    store::RadiomapSettings written;  // as stored, with its updated_at
};

class Service {
public:
    Service(store::Store& store, SettingsText text, std::size_t quality_at_once = 2);
    Service(const Service&) = delete;
    Service& operator=(const Service&) = delete;

    // NotFound for an unknown radio map, then Busy when `quality_at_once` run already;
    // match::TuneRefused when the RPs cannot be assessed (fewer than 2, no measurement).
    Quality quality(std::int64_t radiomap_id, const match::TuneLimits& limits);
    // NotFound for an unknown radio map, then Running; match::TuneRefused when the RPs cannot
    // be tuned. Stores the best setting and the table in one write.
    Tuned tune(std::int64_t radiomap_id, const match::TuneLimits& limits);

private:
    class TuneGuard;
    class QualitySlot;

    store::Store& store_;
    SettingsText text_;
    std::mutex mu_;  // guards the two below
    std::unordered_set<std::int64_t> tuning_;  // radio maps being tuned
    std::size_t quality_free_;
    const std::size_t quality_at_once_;
};

}  // namespace locus::tuning
