#include "store/repository.hpp"

#include <map>
#include <utility>

#include "store/migrations.hpp"

namespace locus::store {

using nlohmann::json;

namespace {

std::string column_list(const Kind& k) {
    std::string cols = "id";
    if (!k.parent_column.empty()) cols += ", " + std::string(k.parent_column);
    for (const auto& f : k.fields) cols += ", " + std::string(f.name);
    return cols;
}

void bind_value(Stmt& s, int i, const Field& f, const json& v) {
    if (v.is_null()) {
        s.bind_null(i);
        return;
    }
    switch (f.type) {
        case FieldType::Text: s.bind(i, v.get<std::string>()); break;
        case FieldType::Real: s.bind(i, v.get<double>()); break;
        case FieldType::Integer: s.bind(i, v.get<std::int64_t>()); break;
    }
}

template <typename F>
auto translate_constraints(const Kind& k, F&& body) {
    try {
        return body();
    } catch (const SqliteError& e) {
        if (e.is_unique())
            throw Conflict("a " + std::string(k.singular) + " with that name already exists here");
        throw;
    }
}

}  // namespace

Repository::Repository(const std::string& path) : db_(path) {
    try {
        migrate(db_);
    } catch (const SqliteError& e) {
        throw SqliteError(e.code, "database '" + path + "': " + e.what(), path);
    }
}

void Repository::probe_write() {
    std::lock_guard lock(mu_);
    Transaction tx(db_);
    Stmt s(db_, "INSERT INTO ready_probe (id, writes) VALUES (1, 1) ON CONFLICT (id) DO UPDATE SET writes = writes + 1");
    s.run();
    tx.commit();
}

json Repository::row_json(const Kind& k, Stmt& s) {
    json row;
    row["id"] = s.int64(0);
    int col = 1;
    if (!k.parent_column.empty()) row[std::string(k.parent_column)] = s.int64(col++);
    for (const auto& f : k.fields) {
        const std::string name(f.name);
        if (s.is_null(col)) {
            row[name] = nullptr;
        } else {
            switch (f.type) {
                case FieldType::Text: row[name] = s.text(col); break;
                case FieldType::Real: row[name] = s.real(col); break;
                case FieldType::Integer: row[name] = s.int64(col); break;
            }
        }
        ++col;
    }
    if (k.has_rects) row["rects"] = rects_of(row["id"].get<std::int64_t>());
    return row;
}

json Repository::rects_of(std::int64_t room_id) {
    Stmt s(db_, "SELECT xmin, ymin, xmax, ymax FROM room_rects WHERE room_id = ? ORDER BY id");
    s.bind(1, room_id);
    json out = json::array();
    while (s.step())
        out.push_back({{"xmin", s.real(0)}, {"ymin", s.real(1)}, {"xmax", s.real(2)}, {"ymax", s.real(3)}});
    return out;
}

void Repository::replace_rects(std::int64_t room_id, const json& rects) {
    Stmt del(db_, "DELETE FROM room_rects WHERE room_id = ?");
    del.bind(1, room_id).run();
    Stmt ins(db_, "INSERT INTO room_rects (room_id, xmin, ymin, xmax, ymax) VALUES (?, ?, ?, ?, ?)");
    for (const auto& r : rects) {
        ins.reset();
        ins.bind(1, room_id)
            .bind(2, r.at("xmin").get<double>())
            .bind(3, r.at("ymin").get<double>())
            .bind(4, r.at("xmax").get<double>())
            .bind(5, r.at("ymax").get<double>())
            .run();
    }
}

void Repository::require_exists(const Kind& k, std::int64_t id) {
    Stmt s(db_, "SELECT 1 FROM " + std::string(k.name) + " WHERE id = ?");
    s.bind(1, id);
    if (!s.step()) throw NotFound(std::string(k.singular) + " " + std::to_string(id) + " not found");
}

json Repository::get_locked(const Kind& k, std::int64_t id) {
    Stmt s(db_, "SELECT " + column_list(k) + " FROM " + std::string(k.name) + " WHERE id = ?");
    s.bind(1, id);
    if (!s.step()) throw NotFound(std::string(k.singular) + " " + std::to_string(id) + " not found");
    return row_json(k, s);
}

std::int64_t Repository::insert_row(const Kind& k, std::optional<std::int64_t> parent_id, const json& values) {
    if (!k.parent_column.empty()) require_exists(kind(k.parent_kind), parent_id.value());
    std::string cols, marks;
    std::vector<const Field*> bound;
    if (!k.parent_column.empty()) {
        cols = std::string(k.parent_column);
        marks = "?";
    }
    for (const auto& f : k.fields) {
        if (!f.writable || !values.contains(f.name)) continue;
        if (!cols.empty()) {
            cols += ", ";
            marks += ", ";
        }
        cols += std::string(f.name);
        marks += "?";
        bound.push_back(&f);
    }
    Stmt s(db_, "INSERT INTO " + std::string(k.name) + " (" + cols + ") VALUES (" + marks + ")");
    int i = 1;
    if (!k.parent_column.empty()) s.bind(i++, *parent_id);
    for (const Field* f : bound) bind_value(s, i++, *f, values.at(f->name));
    translate_constraints(k, [&] {
        s.run();
        return 0;
    });
    const std::int64_t id = db_.last_insert_id();
    if (k.has_rects) replace_rects(id, values.value("rects", json::array()));
    return id;
}

json Repository::create(const Kind& k, std::optional<std::int64_t> parent_id, const json& values) {
    std::lock_guard lock(mu_);
    Transaction tx(db_);
    const std::int64_t id = insert_row(k, parent_id, values);
    json row = get_locked(k, id);
    tx.commit();
    return row;
}

json Repository::get(const Kind& k, std::int64_t id) {
    std::lock_guard lock(mu_);
    return get_locked(k, id);
}

json Repository::list(const Kind& k, std::optional<std::int64_t> parent_id, std::int64_t limit,
                      std::int64_t offset) {
    std::lock_guard lock(mu_);
    Transaction tx(db_);  // count and page from one snapshot
    const std::string table(k.name);
    std::string where;
    if (!k.parent_column.empty()) {
        require_exists(kind(k.parent_kind), parent_id.value());
        where = " WHERE " + std::string(k.parent_column) + " = ?1";
    }
    Stmt count(db_, "SELECT COUNT(*) FROM " + table + where);
    if (!where.empty()) count.bind(1, *parent_id);
    count.step();
    const std::int64_t total = count.int64(0);

    Stmt s(db_, "SELECT " + column_list(k) + " FROM " + table + where + " ORDER BY id LIMIT ?2 OFFSET ?3");
    if (!where.empty()) s.bind(1, *parent_id);
    s.bind(2, limit).bind(3, offset);
    json items = json::array();
    while (s.step()) items.push_back(row_json(k, s));
    tx.commit();
    return {{"items", items}, {"total", total}, {"limit", limit}, {"offset", offset}};
}

json Repository::update(const Kind& k, std::int64_t id, const json& values) {
    std::lock_guard lock(mu_);
    Transaction tx(db_);
    require_exists(k, id);
    std::string sets;
    std::vector<const Field*> bound;
    for (const auto& f : k.fields) {
        if (!f.writable || !values.contains(f.name)) continue;
        if (!sets.empty()) sets += ", ";
        sets += std::string(f.name) + " = ?";
        bound.push_back(&f);
    }
    if (!bound.empty()) {
        Stmt s(db_, "UPDATE " + std::string(k.name) + " SET " + sets + " WHERE id = ?");
        int i = 1;
        for (const Field* f : bound) bind_value(s, i++, *f, values.at(f->name));
        s.bind(i, id);
        translate_constraints(k, [&] {
            s.run();
            return 0;
        });
    }
    if (k.has_rects && values.contains("rects")) replace_rects(id, values.at("rects"));
    json row = get_locked(k, id);
    tx.commit();
    return row;
}

void Repository::remove(const Kind& k, std::int64_t id) {
    std::lock_guard lock(mu_);
    Transaction tx(db_);
    require_exists(k, id);
    Stmt s(db_, "DELETE FROM " + std::string(k.name) + " WHERE id = ?");
    s.bind(1, id).run();
    tx.commit();
}

json Repository::measurements_of(std::int64_t rp_id) {
    Stmt s(db_,
           "SELECT type, bssid, mean, variance, count FROM measurements WHERE rp_id = ? ORDER BY type, bssid");
    s.bind(1, rp_id);
    json out = json::array();
    while (s.step())
        out.push_back({{"type", s.text(0)},
                       {"bssid", s.text(1)},
                       {"mean", s.real(2)},
                       {"variance", s.real(3)},
                       {"count", s.int64(4)}});
    return out;
}

json Repository::rp_with_measurements(std::int64_t rp_id) {
    std::lock_guard lock(mu_);
    Transaction tx(db_);
    json rp = get_locked(kind("rps"), rp_id);
    rp["measurements"] = measurements_of(rp_id);
    tx.commit();
    return rp;
}

void Repository::merge_measurements(std::int64_t rp_id, const std::vector<Measurement>& ms, std::int64_t scans) {
    Stmt sel(db_, "SELECT mean, variance, count FROM measurements WHERE rp_id = ? AND type = ? AND bssid = ?");
    Stmt put(db_,
             "INSERT INTO measurements (rp_id, type, bssid, mean, variance, count) VALUES (?, ?, ?, ?, ?, ?) "
             "ON CONFLICT (rp_id, type, bssid) DO UPDATE SET mean = excluded.mean, "
             "variance = excluded.variance, count = excluded.count");
    for (const auto& m : ms) {
        sel.reset();
        sel.bind(1, rp_id).bind(2, m.type).bind(3, m.bssid);
        RssStats stats;
        if (sel.step()) stats = RssStats{sel.real(0), sel.real(1), sel.int64(2)};
        if (m.stats.count < 1 || !stats.can_merge(m.stats))
            throw OutOfRange("the count of " + m.bssid + " at this RP would pass 2^53");
        stats.merge(m.stats);
        put.reset();
        put.bind(1, rp_id).bind(2, m.type).bind(3, m.bssid).bind(4, stats.mean).bind(5, stats.variance).bind(6, stats.count);
        put.run();
    }
    Stmt cur(db_, "SELECT scans FROM rps WHERE id = ?");
    cur.bind(1, rp_id);
    if (scans < 0 || scans > kMaxCount || (cur.step() && cur.int64(0) > kMaxCount - scans))
        throw OutOfRange("the RP's scan count would pass 2^53");
    Stmt upd(db_, "UPDATE rps SET scans = scans + ? WHERE id = ?");
    upd.bind(1, scans).bind(2, rp_id).run();
}

UploadResult Repository::merge_scans(std::int64_t rp_id, const ScanUpload& upload) {
    std::lock_guard lock(mu_);
    Transaction tx(db_);
    require_exists(kind("rps"), rp_id);
    UploadResult result;
    bool fresh = true;
    if (upload.upload_id) {
        Stmt s(db_, "INSERT OR IGNORE INTO uploads (rp_id, upload_id) VALUES (?, ?)");
        s.bind(1, rp_id).bind(2, *upload.upload_id).run();
        fresh = db_.changes() > 0;
    }
    if (fresh) merge_measurements(rp_id, upload.measurements, upload.scans);
    result.applied = fresh;
    result.rp = get_locked(kind("rps"), rp_id);
    result.rp["measurements"] = measurements_of(rp_id);
    tx.commit();
    return result;
}

json Repository::export_radiomap(std::int64_t radiomap_id) {
    std::lock_guard lock(mu_);
    Transaction tx(db_);
    const json rm = get_locked(kind("radiomaps"), radiomap_id);
    json rps = json::array();
    Stmt s(db_, "SELECT id, name, x, y, scans FROM rps WHERE radiomap_id = ? ORDER BY id");
    s.bind(1, radiomap_id);
    while (s.step()) {
        rps.push_back({{"name", s.text(1)},
                       {"x", s.real(2)},
                       {"y", s.real(3)},
                       {"scans", s.int64(4)},
                       {"measurements", measurements_of(s.int64(0))}});
    }
    tx.commit();
    return {{"format", "locus-radiomap/1"},
            {"name", rm.at("name")},
            {"description", rm.at("description")},
            {"floor_id", rm.at("floor_id")},
            {"rps", rps}};
}

namespace {
std::vector<Measurement> measurements_from(const json& arr) {
    std::vector<Measurement> out;
    for (const auto& m : arr)
        // A null "type" is wifi, as validation reads it (value() would throw on the null).
        out.push_back({m.contains("type") && !m.at("type").is_null() ? m.at("type").get<std::string>() : "wifi",
                       normalise_bssid(m.at("bssid").get<std::string>()),
                       RssStats{m.at("mean").get<double>(), m.at("variance").get<double>(),
                                m.at("count").get<std::int64_t>()}});
    return out;
}

json values_of(const Kind& k, const json& doc) {
    json v = json::object();
    for (const auto& f : k.fields)
        if (f.writable && doc.contains(f.name)) v[std::string(f.name)] = doc.at(f.name);
    if (k.has_rects && doc.contains("rects")) v["rects"] = doc.at("rects");
    return v;
}
}  // namespace

json Repository::import_radiomap(std::int64_t floor_id, const json& doc) {
    std::lock_guard lock(mu_);
    Transaction tx(db_);
    const std::int64_t rm_id = insert_row(kind("radiomaps"), floor_id, values_of(kind("radiomaps"), doc));
    std::int64_t rp_count = 0, measurement_count = 0;
    for (const auto& rp : doc.at("rps")) {
        const std::int64_t rp_id = insert_row(kind("rps"), rm_id, values_of(kind("rps"), rp));
        const auto ms = measurements_from(rp.value("measurements", json::array()));
        std::int64_t scans = rp.value("scans", std::int64_t{0});
        merge_measurements(rp_id, ms, scans);
        ++rp_count;
        measurement_count += static_cast<std::int64_t>(ms.size());
    }
    json out = get_locked(kind("radiomaps"), rm_id);
    out["rp_count"] = rp_count;
    out["measurement_count"] = measurement_count;
    tx.commit();
    return out;
}

json Repository::import_map_bundle(const json& bundle) {
    std::lock_guard lock(mu_);
    Transaction tx(db_);
    const std::int64_t map_id = insert_row(kind("maps"), std::nullopt, values_of(kind("maps"), bundle.at("map")));
    for (const auto& b : bundle.value("buildings", json::array())) {
        const std::int64_t b_id = insert_row(kind("buildings"), map_id, values_of(kind("buildings"), b));
        for (const auto& f : b.value("floors", json::array())) {
            const std::int64_t f_id = insert_row(kind("floors"), b_id, values_of(kind("floors"), f));
            for (const auto& r : f.value("rooms", json::array())) insert_row(kind("rooms"), f_id, values_of(kind("rooms"), r));
            for (const auto& p : f.value("pois", json::array())) insert_row(kind("pois"), f_id, values_of(kind("pois"), p));
            for (const auto& rm : f.value("radiomaps", json::array())) {
                const std::int64_t rm_id = insert_row(kind("radiomaps"), f_id, values_of(kind("radiomaps"), rm));
                for (const auto& rp : rm.value("rps", json::array())) {
                    const std::int64_t rp_id = insert_row(kind("rps"), rm_id, values_of(kind("rps"), rp));
                    merge_measurements(rp_id, measurements_from(rp.value("measurements", json::array())),
                                       rp.value("scans", std::int64_t{0}));
                }
            }
        }
    }
    json out = get_locked(kind("maps"), map_id);
    tx.commit();
    return out;
}

bool Repository::has_maps() {
    std::lock_guard lock(mu_);
    Stmt s(db_, "SELECT EXISTS (SELECT 1 FROM maps)");
    s.step();
    return s.int64(0) != 0;
}

std::vector<StoredRp> Repository::load_rps(std::string_view where, std::int64_t id) {
    std::lock_guard lock(mu_);
    Transaction tx(db_);
    const std::string from =
        " FROM rps r JOIN radiomaps rm ON rm.id = r.radiomap_id JOIN floors f ON f.id = rm.floor_id "
        "JOIN buildings b ON b.id = f.building_id WHERE " + std::string(where) + " = ?";
    std::vector<StoredRp> out;
    std::map<std::int64_t, std::size_t> by_id;
    Stmt s(db_, "SELECT r.id, r.name, r.x, r.y, r.scans, r.radiomap_id, f.id, b.id" + from + " ORDER BY r.id");
    s.bind(1, id);
    while (s.step()) {
        StoredRp rp;
        rp.rp.id = s.int64(0);
        rp.rp.name = s.text(1);
        rp.rp.at = {s.real(2), s.real(3)};
        rp.rp.scans = s.int64(4);
        rp.radiomap_id = s.int64(5);
        rp.floor_id = s.int64(6);
        rp.building_id = s.int64(7);
        by_id[rp.rp.id] = out.size();
        out.push_back(std::move(rp));
    }
    Stmt m(db_, "SELECT m.rp_id, m.type, m.bssid, m.mean, m.variance, m.count FROM measurements m "
                "JOIN rps r ON r.id = m.rp_id JOIN radiomaps rm ON rm.id = r.radiomap_id "
                "JOIN floors f ON f.id = rm.floor_id JOIN buildings b ON b.id = f.building_id WHERE " +
                    std::string(where) + " = ? ORDER BY m.rp_id, m.type, m.bssid");
    m.bind(1, id);
    while (m.step()) {
        auto it = by_id.find(m.int64(0));
        if (it == by_id.end()) continue;
        out[it->second].rp.measurements.push_back(
            {m.text(1), m.text(2), RssStats{m.real(3), m.real(4), m.int64(5)}});
    }
    tx.commit();
    return out;
}

std::vector<StoredRp> Repository::rps_of_radiomap(std::int64_t radiomap_id) { return load_rps("rm.id", radiomap_id); }
std::vector<StoredRp> Repository::rps_of_map(std::int64_t map_id) { return load_rps("b.map_id", map_id); }

std::vector<Room> Repository::rooms_of_floor(std::int64_t floor_id) {
    std::lock_guard lock(mu_);
    Transaction tx(db_);
    std::vector<Room> rooms;
    Stmt s(db_, "SELECT id, name FROM rooms WHERE floor_id = ? ORDER BY id");
    s.bind(1, floor_id);
    while (s.step()) rooms.push_back({s.int64(0), s.text(1), {}});
    Stmt r(db_, "SELECT xmin, ymin, xmax, ymax FROM room_rects WHERE room_id = ? ORDER BY id");
    for (auto& room : rooms) {
        r.reset();
        r.bind(1, room.id);
        while (r.step()) room.rects.push_back({r.real(0), r.real(1), r.real(2), r.real(3)});
    }
    tx.commit();
    return rooms;
}

std::int64_t Repository::map_of_radiomap(std::int64_t radiomap_id) {
    std::lock_guard lock(mu_);
    Stmt s(db_, "SELECT b.map_id FROM radiomaps rm JOIN floors f ON f.id = rm.floor_id "
                "JOIN buildings b ON b.id = f.building_id WHERE rm.id = ?");
    s.bind(1, radiomap_id);
    if (!s.step()) throw NotFound("radiomap " + std::to_string(radiomap_id) + " not found");
    return s.int64(0);
}

std::vector<std::int64_t> Repository::radiomap_ids() {
    std::lock_guard lock(mu_);
    Stmt s(db_, "SELECT id FROM radiomaps ORDER BY id");
    std::vector<std::int64_t> ids;
    while (s.step()) ids.push_back(s.int64(0));
    return ids;
}

}  // namespace locus::store
