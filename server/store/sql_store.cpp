#include "store/sql_store.hpp"

#include <map>
#include <tuple>
#include <utility>

#include "store/migrations.hpp"

namespace locus::store {

std::string column_list(const Kind& k) {
    std::string cols = "id";
    if (!k.parent_column.empty()) cols += ", " + std::string(k.parent_column);
    for (const auto& f : k.fields) cols += ", " + std::string(f.name);
    return cols;
}

static std::vector<Rect> read_rects(Db& db, std::int64_t room_id) {
    Stmt s(db, "SELECT xmin, ymin, xmax, ymax FROM room_rects WHERE room_id = ? ORDER BY id");
    s.bind(1, room_id);
    std::vector<Rect> out;
    while (s.step()) out.push_back({s.real(0), s.real(1), s.real(2), s.real(3)});
    return out;
}

Record read_row(Db& db, const Kind& k, Stmt& s) {
    Record r;
    r.id = s.int64(0);
    int col = 1;
    if (!k.parent_column.empty()) r.parent_id = s.int64(col++);
    for (const auto& f : k.fields) {
        Value v;
        if (!s.is_null(col)) {
            switch (f.type) {
                case FieldType::Text: v = s.text(col); break;
                case FieldType::Real: v = s.real(col); break;
                case FieldType::Integer: v = s.int64(col); break;
            }
        }
        r.fields.values.emplace(std::string(f.name), std::move(v));
        ++col;
    }
    if (k.has_rects) r.fields.rects = read_rects(db, r.id);
    return r;
}

namespace {

void bind_value(Stmt& s, int i, const Value& v) {
    std::visit(
        [&](const auto& x) {
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_same_v<T, std::monostate>) s.bind_null(i);
            else if constexpr (std::is_same_v<T, std::string>) s.bind(i, std::string_view(x));
            else if constexpr (std::is_same_v<T, double>) s.bind(i, x);
            else s.bind_int64(i, x);
        },
        v);
}

template <typename F>
auto translate_constraints(const Kind& k, F&& body) {
    try {
        return body();
    } catch (const DbError& e) {
        if (e.is_unique())
            throw Conflict("a " + std::string(k.singular) + " with that name already exists here");
        throw;
    }
}

}  // namespace

SqlStore::SqlStore(const std::string& path) : db_(path) {
    try {
        migrate(db_);
    } catch (const DbError& e) {
        throw DbError(e.code, "database '" + db_.path() + "': " + e.what(), db_.path());
    }
    if (db_.is_postgres()) pg_start_watching();
}

void SqlStore::probe_write() {
    std::lock_guard lock(mu_);
    Transaction tx(db_);
    Stmt s(db_, "INSERT INTO ready_probe (id, writes) VALUES (1, 1) ON CONFLICT (id) DO UPDATE SET writes = ready_probe.writes + 1");
    s.run();
    tx.commit();
}

Record SqlStore::row(const Kind& k, Stmt& s) { return read_row(db_, k, s); }

std::vector<Rect> SqlStore::rects_of(std::int64_t room_id) { return read_rects(db_, room_id); }

void SqlStore::replace_rects(std::int64_t room_id, const std::vector<Rect>& rects) {
    Stmt del(db_, "DELETE FROM room_rects WHERE room_id = ?");
    del.bind(1, room_id).run();
    Stmt ins(db_, "INSERT INTO room_rects (room_id, xmin, ymin, xmax, ymax) VALUES (?, ?, ?, ?, ?)");
    for (const auto& r : rects) {
        ins.reset();
        ins.bind(1, room_id).bind(2, r.xmin).bind(3, r.ymin).bind(4, r.xmax).bind(5, r.ymax).run();
    }
}

void SqlStore::require_exists(const Kind& k, std::int64_t id) {
    Stmt s(db_, "SELECT 1 FROM " + std::string(k.name) + " WHERE id = ?");
    s.bind(1, id);
    if (!s.step()) throw NotFound(std::string(k.singular) + " " + std::to_string(id) + " not found");
}

Record SqlStore::get_locked(const Kind& k, std::int64_t id) {
    Stmt s(db_, "SELECT " + column_list(k) + " FROM " + std::string(k.name) + " WHERE id = ?");
    s.bind(1, id);
    if (!s.step()) throw NotFound(std::string(k.singular) + " " + std::to_string(id) + " not found");
    return row(k, s);
}

std::optional<std::int64_t> SqlStore::map_of_radiomap_locked(std::int64_t radiomap_id) {
    Stmt s(db_, "SELECT b.map_id FROM radiomaps rm JOIN floors f ON f.id = rm.floor_id "
                "JOIN buildings b ON b.id = f.building_id WHERE rm.id = ?");
    s.bind(1, radiomap_id);
    if (!s.step()) return std::nullopt;
    return s.int64(0);
}

Change SqlStore::change_of(const Kind& k, std::int64_t id, bool deleted) {
    Change c{&k, id, deleted, false, std::nullopt, std::nullopt};
    if (k.name == "rps") {
        Stmt s(db_, "SELECT radiomap_id FROM rps WHERE id = ?");
        s.bind(1, id);
        if (s.step()) c.radiomap_id = s.int64(0);
        if (c.radiomap_id) c.map_id = map_of_radiomap_locked(*c.radiomap_id);
    } else if (k.name == "radiomaps") {
        c.radiomap_id = id;
        c.map_id = map_of_radiomap_locked(id);
    }
    return c;
}

std::int64_t SqlStore::insert_row(const Kind& k, std::optional<std::int64_t> parent_id, const Fields& values) {
    if (!k.parent_column.empty()) require_exists(kind(k.parent_kind), parent_id.value());
    std::string cols, marks;
    std::vector<const Value*> bound;
    if (!k.parent_column.empty()) {
        cols = std::string(k.parent_column);
        marks = "?";
    }
    for (const auto& f : k.fields) {
        const auto it = values.values.find(f.name);
        if (!f.writable || it == values.values.end()) continue;
        if (!cols.empty()) {
            cols += ", ";
            marks += ", ";
        }
        cols += std::string(f.name);
        marks += "?";
        bound.push_back(&it->second);
    }
    Stmt s(db_, "INSERT INTO " + std::string(k.name) + " (" + cols + ") VALUES (" + marks + ")");
    int i = 1;
    if (!k.parent_column.empty()) s.bind(i++, *parent_id);
    for (const Value* v : bound) bind_value(s, i++, *v);
    translate_constraints(k, [&] {
        s.run();
        return 0;
    });
    const std::int64_t id = db_.last_insert_id();
    if (k.has_rects) replace_rects(id, values.rects.value_or(std::vector<Rect>{}));
    return id;
}

Record SqlStore::create(const Kind& k, std::optional<std::int64_t> parent_id, const Fields& values) {
    return write([&](std::vector<Change>& changes) {
        const std::int64_t id = insert_row(k, parent_id, values);
        changes.push_back(change_of(k, id, false));
        return get_locked(k, id);
    });
}

Record SqlStore::get(const Kind& k, std::int64_t id) {
    std::lock_guard lock(mu_);
    return get_locked(k, id);
}

RecordPage SqlStore::list(const Kind& k, std::optional<std::int64_t> parent_id, std::int64_t limit,
                             std::int64_t offset) {
    std::lock_guard lock(mu_);
    Transaction tx(db_, Transaction::Mode::read);  // count and page from one snapshot
    const std::string table(k.name);
    std::string where;
    if (!k.parent_column.empty()) {
        require_exists(kind(k.parent_kind), parent_id.value());
        where = " WHERE " + std::string(k.parent_column) + " = ?1";
    }
    RecordPage page;
    page.limit = limit;
    page.offset = offset;
    Stmt count(db_, "SELECT COUNT(*) FROM " + table + where);
    if (!where.empty()) count.bind(1, *parent_id);
    count.step();
    page.total = count.int64(0);

    Stmt s(db_, "SELECT " + column_list(k) + " FROM " + table + where + " ORDER BY id LIMIT ?2 OFFSET ?3");
    if (!where.empty()) s.bind(1, *parent_id);
    s.bind(2, limit).bind(3, offset);
    while (s.step()) page.items.push_back(row(k, s));
    tx.commit();
    return page;
}

void SqlStore::update_row(const Kind& k, std::int64_t id, const Fields& values) {
    require_exists(k, id);
    refuse_if_kept(k, id);
    std::string sets;
    std::vector<const Value*> bound;
    for (const auto& f : k.fields) {
        const auto it = values.values.find(f.name);
        if (!f.writable || it == values.values.end()) continue;
        if (!sets.empty()) sets += ", ";
        sets += std::string(f.name) + " = ?";
        bound.push_back(&it->second);
    }
    if (!bound.empty()) {
        Stmt s(db_, "UPDATE " + std::string(k.name) + " SET " + sets + " WHERE id = ?");
        int i = 1;
        for (const Value* v : bound) bind_value(s, i++, *v);
        s.bind(i, id);
        translate_constraints(k, [&] {
            s.run();
            return 0;
        });
    }
    if (k.has_rects && values.rects) replace_rects(id, *values.rects);
}

Record SqlStore::update(const Kind& k, std::int64_t id, const Fields& values) {
    return write([&](std::vector<Change>& changes) {
        update_row(k, id, values);
        changes.push_back(change_of(k, id, false));
        return get_locked(k, id);
    });
}

std::vector<Record> SqlStore::write_rows(const Kind& k, std::optional<std::int64_t> parent_id,
                                            const std::vector<RowWrite>& rows) {
    return write([&](std::vector<Change>& changes) {
        std::vector<std::int64_t> ids;
        for (const auto& r : rows) {
            if (r.id) {
                update_row(k, *r.id, r.fields);
                ids.push_back(*r.id);
            } else {
                ids.push_back(insert_row(k, parent_id, r.fields));
            }
            changes.push_back(change_of(k, ids.back(), false));
        }
        std::vector<Record> out;
        for (const auto id : ids) out.push_back(get_locked(k, id));
        return out;
    });
}

void SqlStore::remove(const Kind& k, std::int64_t id) {
    write([&](std::vector<Change>& changes) {
        require_exists(k, id);
        refuse_if_kept(k, id);
        changes.push_back(change_of(k, id, true));  // before the row, and its place, are gone
        Stmt s(db_, "DELETE FROM " + std::string(k.name) + " WHERE id = ?");
        s.bind(1, id).run();
    });
}

bool SqlStore::has_maps() {
    std::lock_guard lock(mu_);
    Stmt s(db_, "SELECT EXISTS (SELECT 1 FROM maps)");
    s.step();
    return s.int64(0) != 0;
}

std::vector<StoredRp> SqlStore::load_rps(std::string_view where, std::int64_t id) {
    std::lock_guard lock(mu_);
    Transaction tx(db_, Transaction::Mode::read);
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
            {m.text(1), Bssid::stored(m.text(2)), RssStats{m.real(3), m.real(4), m.int64(5)}});
    }
    tx.commit();
    return out;
}

std::vector<StoredRp> SqlStore::rps_of_radiomap(std::int64_t radiomap_id) { return load_rps("rm.id", radiomap_id); }
std::vector<StoredRp> SqlStore::rps_of_map(std::int64_t map_id) { return load_rps("b.map_id", map_id); }

std::vector<Room> SqlStore::rooms_of_floor(std::int64_t floor_id) {
    std::lock_guard lock(mu_);
    Transaction tx(db_, Transaction::Mode::read);
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

std::int64_t SqlStore::map_of_radiomap(std::int64_t radiomap_id) {
    std::lock_guard lock(mu_);
    if (auto map = map_of_radiomap_locked(radiomap_id)) return *map;
    throw NotFound("radiomap " + std::to_string(radiomap_id) + " not found");
}

std::vector<std::int64_t> SqlStore::radiomap_ids() {
    std::lock_guard lock(mu_);
    Stmt s(db_, "SELECT id FROM radiomaps ORDER BY id");
    std::vector<std::int64_t> ids;
    while (s.step()) ids.push_back(s.int64(0));
    return ids;
}

}  // namespace locus::store
