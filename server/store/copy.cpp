#include "store/copy.hpp"

#include <charconv>

namespace locus::store {

const std::vector<std::string>& data_tables() {
    static const std::vector<std::string> tables{
        "maps",         "buildings",  "floors",     "rooms",      "room_rects",        "pois",
        "radiomaps",    "rps",        "measurements", "uploads",  "floor_plans",       "plan_features",
        "plan_points",  "plan_tags",  "plan_links", "floor_images", "radiomap_settings", "transmitters",
        "tracks",       "track_fixes", "track_shares"};
    return tables;
}

namespace {

// The table's columns in SQLite's names (the store's SQL spelling; Db rewrites it for PostgreSQL).
std::vector<std::string> columns_of(Db& db, const std::string& table) {
    std::vector<std::string> out;
    if (db.is_postgres()) {
        Stmt s(db, "SELECT column_name FROM information_schema.columns WHERE table_schema = current_schema() "
                   "AND table_name = ? ORDER BY ordinal_position");
        s.bind(1, std::string_view(table));
        while (s.step()) {
            std::string c = s.text(0);
            if (c.starts_with("rect_")) c.erase(0, 5);  // rect_xmin: xmin in the store's SQL
            out.push_back(c);
        }
    } else {
        Stmt s(db, "SELECT name FROM pragma_table_info(?) ORDER BY cid");
        s.bind(1, std::string_view(table));
        while (s.step()) out.push_back(s.text(0));
    }
    return out;
}

std::string joined(const std::vector<std::string>& cols) {
    std::string out;
    for (const auto& c : cols) {
        if (!out.empty()) out += ", ";
        out += c;
    }
    return out;
}

bool has_id(const std::vector<std::string>& cols) { return !cols.empty() && cols.front() == "id"; }

// Rows in a stable order: by id, else by every column.
std::string select_all(const std::string& table, const std::vector<std::string>& cols) {
    std::string order;
    for (std::size_t i = 1; i <= (has_id(cols) ? 1 : cols.size()); ++i) {
        if (!order.empty()) order += ", ";
        order += std::to_string(i);
    }
    return "SELECT " + joined(cols) + " FROM " + table + " ORDER BY " + order;
}

std::string rendered(const Stmt& s, int col) {
    switch (s.column_type(col)) {
        case SQLITE_NULL: return "NULL";
        case SQLITE_INTEGER:
        case SQLITE_FLOAT: {
            char buf[64];
            const auto r = std::to_chars(buf, buf + sizeof buf, s.real(col));
            return std::string(buf, r.ptr);
        }
        case SQLITE_BLOB: {
            std::string out = "blob:";
            out += s.blob(col);
            return out;
        }
        default: {
            std::string out = "'";
            out += s.text(col);
            out += '\'';
            return out;
        }
    }
}

}  // namespace

bool is_empty(Db& db) {
    Stmt s(db, "SELECT (SELECT COUNT(*) FROM maps) + (SELECT COUNT(*) FROM tracks)");
    s.step();
    return s.int64(0) == 0;
}

std::vector<std::pair<std::string, std::int64_t>> copy_database(Db& from, Db& to) {
    std::vector<std::pair<std::string, std::int64_t>> counts;
    Transaction tx(to);
    for (const auto& table : data_tables()) {
        const auto cols = columns_of(from, table);
        std::string marks;
        for (std::size_t i = 0; i < cols.size(); ++i) marks += i ? ", ?" : "?";
        Stmt read(from, select_all(table, cols));
        Stmt write(to, "INSERT INTO " + table + " (" + joined(cols) + ") VALUES (" + marks + ")");
        std::int64_t n = 0;
        std::vector<std::string> blobs(cols.size());  // bind_blob keeps a view until the row is written
        while (read.step()) {
            write.reset();
            for (int c = 0; c < static_cast<int>(cols.size()); ++c) {
                switch (read.column_type(c)) {
                    case SQLITE_NULL: write.bind_null(c + 1); break;
                    case SQLITE_INTEGER: write.bind_int64(c + 1, read.int64(c)); break;
                    case SQLITE_FLOAT: write.bind(c + 1, read.real(c)); break;
                    case SQLITE_BLOB:
                        blobs[static_cast<std::size_t>(c)] = read.blob(c);
                        write.bind_blob(c + 1, blobs[static_cast<std::size_t>(c)]);
                        break;
                    default: write.bind(c + 1, std::string_view(read.text(c))); break;
                }
            }
            write.run();
            ++n;
        }
        counts.emplace_back(table, n);
        if (!has_id(cols) || !to.is_postgres()) continue;
        // The next id: past every id the source ever handed out (SQLite's AUTOINCREMENT keeps
        // the largest in sqlite_sequence, deleted rows included).
        std::int64_t last = 0;
        {
            Stmt max(from, "SELECT COALESCE(MAX(id), 0) FROM " + table);
            max.step();
            last = max.int64(0);
        }
        if (!from.is_postgres()) {
            Stmt seq(from, "SELECT seq FROM sqlite_sequence WHERE name = ?");
            seq.bind(1, std::string_view(table));
            if (seq.step() && seq.int64(0) > last) last = seq.int64(0);
        }
        if (last > 0) {
            Stmt set(to, "SELECT setval(pg_get_serial_sequence('" + table + "', 'id'), ?)");
            set.bind(1, last).run();
        }
    }
    tx.commit();
    return counts;
}

std::string first_difference(Db& a, Db& b) {
    for (const auto& table : data_tables()) {
        const auto cols = columns_of(a, table);
        Stmt ra(a, select_all(table, cols)), rb(b, select_all(table, cols));
        for (std::int64_t row = 0;; ++row) {
            const bool ha = ra.step(), hb = rb.step();
            if (!ha && !hb) break;
            if (ha != hb) return "table " + table + ": " + (ha ? "the target" : "the source") + " has only " + std::to_string(row) + " rows";
            for (int c = 0; c < static_cast<int>(cols.size()); ++c)
                if (rendered(ra, c) != rendered(rb, c))
                    return "table " + table + ", row " + std::to_string(row + 1) + ", column " + cols[static_cast<std::size_t>(c)] +
                           ": " + rendered(ra, c) + " vs " + rendered(rb, c);
        }
    }
    return {};
}

}  // namespace locus::store
