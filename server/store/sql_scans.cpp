// An RP's measurements and what adds to them: scan uploads merged into the stored statistics
// (Welford, RssStats::merge), radio maps and map bundles imported in one transaction each.
// Each is one write transaction under the store's lock; a merge costs one read and one write
// per AP of the upload, an import one insert per RP, measurement and transmitter.
#include <map>
#include <tuple>
#include <utility>

#include "store/sql_store.hpp"

namespace locus::store {

std::vector<Measurement> SqlStore::measurements_of(std::int64_t rp_id) {
    Stmt s(db_,
           "SELECT type, bssid, mean, variance, count FROM measurements WHERE rp_id = ? ORDER BY type, bssid");
    s.bind(1, rp_id);
    std::vector<Measurement> out;
    while (s.step()) out.push_back({s.text(0), Bssid::stored(s.text(1)), RssStats{s.real(2), s.real(3), s.int64(4)}});
    return out;
}

RpRecord SqlStore::rp_with_measurements(std::int64_t rp_id) {
    std::lock_guard lock(mu_);
    Transaction tx(db_, Transaction::Mode::read);
    RpRecord out{get_locked(kind("rps"), rp_id), measurements_of(rp_id)};
    tx.commit();
    return out;
}

RssStats merged_or_refused(RssStats stored, const Measurement& m) {
    if (m.stats.count < 1 || !stored.can_merge(m.stats))
        throw OutOfRange("the count of " + m.bssid.str() + " at this RP would pass 2^53");
    stored.merge(m.stats);
    return stored;
}

void refuse_scans_past_max(std::optional<std::int64_t> stored, std::int64_t scans) {
    if (scans < 0 || scans > kMaxCount || (stored && *stored > kMaxCount - scans))
        throw OutOfRange("the RP's scan count would pass 2^53");
}

void SqlStore::merge_measurements(std::int64_t rp_id, const std::vector<Measurement>& ms, std::int64_t scans) {
    Stmt sel(db_, "SELECT mean, variance, count FROM measurements WHERE rp_id = ? AND type = ? AND bssid = ?");
    Stmt put(db_,
             "INSERT INTO measurements (rp_id, type, bssid, mean, variance, count) VALUES (?, ?, ?, ?, ?, ?) "
             "ON CONFLICT (rp_id, type, bssid) DO UPDATE SET mean = excluded.mean, "
             "variance = excluded.variance, count = excluded.count");
    for (const auto& m : ms) {
        sel.reset();
        sel.bind(1, rp_id).bind(2, m.type).bind(3, m.bssid.str());
        RssStats stats;
        if (sel.step()) stats = RssStats{sel.real(0), sel.real(1), sel.int64(2)};
        stats = merged_or_refused(stats, m);
        put.reset();
        put.bind(1, rp_id).bind(2, m.type).bind(3, m.bssid.str()).bind(4, stats.mean).bind(5, stats.variance).bind(6, stats.count);
        put.run();
    }
    Stmt cur(db_, "SELECT scans FROM rps WHERE id = ?");
    cur.bind(1, rp_id);
    refuse_scans_past_max(cur.step() ? std::optional(cur.int64(0)) : std::nullopt, scans);
    Stmt upd(db_, "UPDATE rps SET scans = scans + ? WHERE id = ?");
    upd.bind(1, scans).bind(2, rp_id).run();
}

UploadResult SqlStore::merge_scans(std::int64_t rp_id, const ScanBatch& batch) {
    return write([&](std::vector<Change>& changes) {
        if (db_.is_postgres()) return pg_merge_scans(rp_id, batch, changes);  // sql_upload_pg.cpp
        UploadResult result;
        require_exists(kind("rps"), rp_id);
        bool fresh = true;
        if (batch.upload_id) {
            Stmt s(db_, "INSERT OR IGNORE INTO uploads (rp_id, upload_id) VALUES (?, ?)");
            s.bind(1, rp_id).bind(2, *batch.upload_id).run();
            fresh = db_.changes() > 0;
        }
        if (fresh) {
            merge_measurements(rp_id, batch.measurements, batch.scans);
            Stmt at(db_, "UPDATE rps SET last_upload_at = strftime('%Y-%m-%dT%H:%M:%fZ', 'now') WHERE id = ?");
            at.bind(1, rp_id).run();
            changes.push_back(change_of(kind("rps"), rp_id, false));
        }
        result.applied = fresh;
        result.rp = {get_locked(kind("rps"), rp_id), measurements_of(rp_id)};
        return result;
    });
}

std::int64_t SqlStore::insert_radiomap(std::int64_t floor_id, const RadioMapDocument& doc, std::int64_t* measurements) {
    const std::int64_t rm_id = insert_row(kind("radiomaps"), floor_id, doc.fields);
    insert_rps(rm_id, doc.rps, measurements);
    return rm_id;
}

void SqlStore::insert_rps(std::int64_t rm_id, const std::vector<RpDocument>& rps, std::int64_t* measurements) {
    for (const auto& rp : rps) {
        Fields f;
        f.values = {{"name", rp.name}, {"x", rp.at.x}, {"y", rp.at.y}};
        const std::int64_t rp_id = insert_row(kind("rps"), rm_id, f);
        if (rp.generated) {  // not a writable field: only a model's radio map sets it
            Stmt g(db_, "UPDATE rps SET generated = 1 WHERE id = ?");
            g.bind(1, rp_id).run();
        }
        merge_measurements(rp_id, rp.measurements, rp.scans);
        if (measurements) *measurements += static_cast<std::int64_t>(rp.measurements.size());
    }
}

ImportedRadioMap SqlStore::add_rps(std::int64_t radiomap_id, const std::vector<RpDocument>& rps) {
    return write([&](std::vector<Change>& changes) {
        ImportedRadioMap out;
        require_exists(kind("radiomaps"), radiomap_id);
        insert_rps(radiomap_id, rps, &out.measurement_count);
        out.radiomap = get_locked(kind("radiomaps"), radiomap_id);
        out.rp_count = static_cast<std::int64_t>(rps.size());
        changes.push_back(change_of(kind("radiomaps"), radiomap_id, false));
        return out;
    });
}

std::pair<std::int64_t, std::int64_t> SqlStore::insert_transmitters(std::int64_t floor_id, const std::vector<Fields>& txs,
                                                                       std::vector<Change>& changes) {
    const Kind& tk = kind("transmitters");
    Stmt has(db_, "SELECT 1 FROM transmitters WHERE floor_id = ? AND type = ? AND bssid = ?");
    std::int64_t created = 0, kept = 0;
    for (const auto& t : txs) {
        has.reset();
        has.bind(1, floor_id).bind(2, t.get<std::string>("type")).bind(3, t.get<std::string>("bssid"));
        if (has.step()) {
            ++kept;
            continue;
        }
        changes.push_back(change_of(tk, insert_row(tk, floor_id, t), false));
        ++created;
    }
    return {created, kept};
}

ImportedRadioMap SqlStore::import_radiomap(std::int64_t floor_id, const RadioMapDocument& doc) {
    return write([&](std::vector<Change>& changes) {
        ImportedRadioMap out;
        const std::int64_t rm_id = insert_radiomap(floor_id, doc, &out.measurement_count);
        out.radiomap = get_locked(kind("radiomaps"), rm_id);
        out.rp_count = static_cast<std::int64_t>(doc.rps.size());
        changes.push_back(change_of(kind("radiomaps"), rm_id, false));
        std::tie(out.transmitters_created, out.transmitters_kept) = insert_transmitters(floor_id, doc.transmitters, changes);
        return out;
    });
}

Record SqlStore::import_map_bundle(const MapBundle& bundle) {
    return write([&](std::vector<Change>& changes) {
        const std::int64_t map_id = insert_row(kind("maps"), std::nullopt, bundle.fields);
        for (const auto& b : bundle.buildings) {
            const std::int64_t b_id = insert_row(kind("buildings"), map_id, b.fields);
            for (const auto& f : b.floors) {
                const std::int64_t f_id = insert_row(kind("floors"), b_id, f.fields);
                for (const auto& r : f.rooms) insert_row(kind("rooms"), f_id, r);
                for (const auto& p : f.pois) insert_row(kind("pois"), f_id, p);
                for (const auto& rm : f.radiomaps) {
                    changes.push_back(change_of(kind("radiomaps"), insert_radiomap(f_id, rm, nullptr), false));
                    insert_transmitters(f_id, rm.transmitters, changes);
                }
            }
        }
        changes.insert(changes.begin(), change_of(kind("maps"), map_id, false));
        return get_locked(kind("maps"), map_id);
    });
}

}  // namespace locus::store
