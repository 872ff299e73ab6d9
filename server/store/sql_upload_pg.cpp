// A scan upload on PostgreSQL in two statements after write()'s BEGIN+lock, whatever the number
// of APs: every statement is a round trip to the database, and SQLite's path (a read and an
// upsert per AP, then the RP, its change's place and the answer read back) costs 2 APs + 10 of
// them. The merge itself stays the core's RssStats::merge in C++ (merged_or_refused, as on
// SQLite), so the stored doubles are SQLite's to the bit; SQL only carries them. PostgreSQL's
// float8 arithmetic would also raise an error on an underflow that C++ rounds to zero.
#include <algorithm>
#include <charconv>
#include <map>
#include <utility>

#include "store/sql_store.hpp"

namespace locus::store {

namespace {

// The RP's columns (column_list) as `alias`.column, for a statement that joins other tables.
std::string rp_columns(std::string_view alias) {
    const Kind& k = kind("rps");
    std::string out = std::string(alias) + ".id";
    if (!k.parent_column.empty()) out += ", " + std::string(alias) + "." + std::string(k.parent_column);
    for (const auto& f : k.fields) out += ", " + std::string(alias) + "." + std::string(f.name);
    return out;
}

int rp_column_count() {
    const Kind& k = kind("rps");
    return 1 + (k.parent_column.empty() ? 0 : 1) + static_cast<int>(k.fields.size());
}

// PostgreSQL array literals, bound as text and cast in the statement (…::text[]).
std::string text_array(const std::vector<std::string>& items) {
    std::string out = "{";
    for (const auto& item : items) {
        if (out.size() > 1) out += ',';
        out += '"';
        for (const char c : item) {
            if (c == '"' || c == '\\') out += '\\';
            out += c;
        }
        out += '"';
    }
    return out + "}";
}

template <typename T>
std::string number_array(const std::vector<T>& items) {
    std::string out = "{";
    for (const T v : items) {
        if (out.size() > 1) out += ',';
        // The shortest text that reads back as the same number (as Stmt::bind does a double).
        char buf[64];
        const auto r = std::to_chars(buf, buf + sizeof buf, v);
        out.append(buf, r.ptr);
    }
    return out + "}";
}

// The measurements of an RP's rows from column `first` on (type, bssid, mean, variance, count),
// in the statement's order; a row without one (an RP that has none) is skipped.
void read_measurements(Stmt& s, int first, std::vector<Measurement>& out) {
    if (s.is_null(first)) return;
    out.push_back({s.text(first), Bssid::stored(s.text(first + 1)),
                   RssStats{s.real(first + 2), s.real(first + 3), s.int64(first + 4)}});
}

}  // namespace

UploadResult SqlStore::pg_merge_scans(std::int64_t rp_id, const ScanBatch& batch, std::vector<Change>& changes) {
    const int n = rp_column_count();
    // The RP (its row, its map for the change, its measurements in measurements_of's order) and
    // the upload_id recorded if new: nothing is recorded for an RP that does not exist.
    Stmt read(db_,
              "WITH rp AS (SELECT r.*, b.map_id AS map_of_rp FROM rps r "
              "LEFT JOIN radiomaps rm ON rm.id = r.radiomap_id LEFT JOIN floors f ON f.id = rm.floor_id "
              "LEFT JOIN buildings b ON b.id = f.building_id WHERE r.id = ?1::bigint), "
              "ins AS (INSERT INTO uploads (rp_id, upload_id) SELECT id, ?2::text FROM rp WHERE ?2::text IS NOT NULL "
              "ON CONFLICT DO NOTHING RETURNING 1) "
              "SELECT " + rp_columns("rp") + ", rp.map_of_rp, (SELECT count(*) FROM ins), "
              "m.type, m.bssid, m.mean, m.variance, m.count "
              "FROM rp LEFT JOIN measurements m ON m.rp_id = rp.id ORDER BY m.type, m.bssid");
    read.bind(1, rp_id);
    if (batch.upload_id) read.bind(2, *batch.upload_id);
    else read.bind_null(2);
    if (!read.step()) throw NotFound("rp " + std::to_string(rp_id) + " not found");

    UploadResult result;
    result.rp.rp = read_row(db_, kind("rps"), read);
    const std::int64_t stored_scans = result.rp.rp.fields.get<std::int64_t>("scans");
    Change change{&kind("rps"), rp_id, false, false, result.rp.rp.parent_id, std::nullopt};
    if (!read.is_null(n)) change.map_id = read.int64(n);
    result.applied = !batch.upload_id || read.int64(n + 1) > 0;
    std::map<std::pair<std::string, std::string>, RssStats> stored;
    do {
        read_measurements(read, n + 2, result.rp.measurements);
        if (!read.is_null(n + 2)) stored[{read.text(n + 2), read.text(n + 3)}] = result.rp.measurements.back().stats;
    } while (read.step());
    if (!result.applied) return result;  // a retry: nothing written, the RP as it is

    // Merged in the batch's order, an AP the batch names twice twice, as SQLite's path does.
    std::vector<std::pair<std::string, std::string>> order;
    for (const auto& m : batch.measurements) {
        const std::pair key{m.type, m.bssid.str()};
        auto at = stored.find(key);
        if (at == stored.end()) at = stored.emplace(key, RssStats{}).first;
        if (std::find(order.begin(), order.end(), key) == order.end()) order.push_back(key);
        at->second = merged_or_refused(at->second, m);
    }
    refuse_scans_past_max(stored_scans, batch.scans);
    std::vector<std::string> types, bssids;
    std::vector<double> means, variances;
    std::vector<std::int64_t> counts;
    for (const auto& key : order) {
        const RssStats& s = stored.at(key);
        types.push_back(key.first);
        bssids.push_back(key.second);
        means.push_back(s.mean);
        variances.push_back(s.variance);
        counts.push_back(s.count);
    }
    // Every merged AP and the RP in one statement; it answers the RP after it (the statement
    // reads the table as it was before it, so the merged APs come from the batch's values).
    Stmt write(db_,
               "WITH u (type, bssid, mean, variance, count) AS ("
               "SELECT * FROM unnest(?2::text[], ?3::text[], ?4::float8[], ?5::float8[], ?6::int8[])), "
               "put AS (INSERT INTO measurements (rp_id, type, bssid, mean, variance, count) "
               "SELECT ?1::bigint, type, bssid, mean, variance, count FROM u ON CONFLICT (rp_id, type, bssid) "
               "DO UPDATE SET mean = excluded.mean, variance = excluded.variance, count = excluded.count), "
               "r AS (UPDATE rps SET scans = scans + ?7::bigint, last_upload_at = strftime('%Y-%m-%dT%H:%M:%fZ', 'now') "
               "WHERE id = ?1::bigint RETURNING *), "
               "m AS (SELECT type, bssid, mean, variance, count FROM u UNION ALL "
               "SELECT x.type, x.bssid, x.mean, x.variance, x.count FROM measurements x WHERE x.rp_id = ?1::bigint "
               "AND NOT EXISTS (SELECT 1 FROM u WHERE u.type = x.type AND u.bssid = x.bssid)) "
               "SELECT " + rp_columns("r") + ", m.type, m.bssid, m.mean, m.variance, m.count "
               "FROM r LEFT JOIN m ON true ORDER BY m.type, m.bssid");
    write.bind(1, rp_id)
        .bind(2, text_array(types))
        .bind(3, text_array(bssids))
        .bind(4, number_array(means))
        .bind(5, number_array(variances))
        .bind(6, number_array(counts))
        .bind(7, batch.scans);
    if (!write.step()) throw NotFound("rp " + std::to_string(rp_id) + " not found");
    result.rp.rp = read_row(db_, kind("rps"), write);
    result.rp.measurements.clear();
    do read_measurements(write, n, result.rp.measurements);
    while (write.step());
    changes.push_back(change);
    return result;
}

}  // namespace locus::store
