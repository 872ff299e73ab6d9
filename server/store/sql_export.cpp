// A radio map's export, read a batch of RPs at a time from one read transaction: the whole
// document at once for export_radiomap (under the store's lock, on its connection), or as
// the HTTP layer writes it out for read_radiomap (on a connection of its own, so a client
// reading slowly holds no lock). Both read through the same reader.
#include <utility>

#include "store/sql_store.hpp"

namespace locus::store {

namespace {

class SqlRadioMapReader final : public RadioMapReader {
public:
    // `owned`, when given, is the connection `db` names, kept for as long as the reader.
    SqlRadioMapReader(std::unique_ptr<Db> owned, Db& db, std::int64_t radiomap_id)
        : owned_(std::move(owned)), db_(db), tx_(db_, Transaction::Mode::read), radiomap_id_(radiomap_id) {
        const Kind& rk = kind("radiomaps");
        Stmt r(db_, "SELECT " + column_list(rk) + " FROM radiomaps WHERE id = ?");
        r.bind(1, radiomap_id);
        if (!r.step()) throw NotFound(std::string(rk.singular) + " " + std::to_string(radiomap_id) + " not found");
        radiomap_ = read_row(db_, rk, r);
        const Kind& tk = kind("transmitters");
        Stmt t(db_, "SELECT " + column_list(tk) + " FROM transmitters WHERE floor_id = ? ORDER BY id");
        t.bind(1, radiomap_.parent_id.value_or(0));
        while (t.step()) transmitters_.push_back(read_row(db_, tk, t));
    }

    const Record& radiomap() const override { return radiomap_; }
    const std::vector<Record>& transmitters() const override { return transmitters_; }

    std::vector<RpDocument> next_rps(std::size_t n) override {
        // Keyset pages rather than one cursor: PostgreSQL's client holds a statement's whole
        // result, and the snapshot keeps the pages consistent. Both queries walk ids in order
        // (`radiomap_id + 0`: not the (radiomap_id, name) index, which SQLite would scan whole
        // and sort at every page); measurements of another radio map's RPs in the id range
        // are skipped here.
        std::vector<RpDocument> out;
        Stmt s(db_, "SELECT id, name, x, y, scans FROM rps WHERE radiomap_id + 0 = ? AND id > ? ORDER BY id LIMIT ?");
        s.bind(1, radiomap_id_).bind(2, after_).bind(3, static_cast<std::int64_t>(n));
        std::vector<std::int64_t> ids;
        while (s.step()) {
            ids.push_back(s.int64(0));
            out.push_back({s.text(1), {s.real(2), s.real(3)}, s.int64(4), {}, false});
        }
        if (out.empty()) return out;
        after_ = ids.back();
        Stmt m(db_, "SELECT rp_id, type, bssid, mean, variance, count FROM measurements WHERE rp_id BETWEEN ? AND ? "
                    "ORDER BY rp_id, type, bssid");
        m.bind(1, ids.front()).bind(2, ids.back());
        std::size_t at = 0;
        while (m.step()) {
            const std::int64_t rp_id = m.int64(0);
            while (ids[at] < rp_id) ++at;  // both in id order, and rp_id <= ids.back()
            if (ids[at] != rp_id) continue;
            out[at].measurements.push_back({m.text(1), Bssid::stored(m.text(2)), RssStats{m.real(3), m.real(4), m.int64(5)}});
        }
        return out;
    }

private:
    std::unique_ptr<Db> owned_;
    Db& db_;
    Transaction tx_;  // read only: rolled back when the reader goes
    std::int64_t radiomap_id_;
    Record radiomap_;
    std::vector<Record> transmitters_;
    std::int64_t after_ = 0;  // the last RP id read
};

}  // namespace

RadioMapExport SqlStore::export_radiomap(std::int64_t radiomap_id) {
    std::lock_guard lock(mu_);
    SqlRadioMapReader reader(nullptr, db_, radiomap_id);
    RadioMapExport out{reader.radiomap(), {}, reader.transmitters()};
    for (auto rps = reader.next_rps(1024); !rps.empty(); rps = reader.next_rps(1024))
        for (auto& rp : rps) out.rps.push_back(std::move(rp));
    return out;
}

std::unique_ptr<RadioMapReader> SqlStore::read_radiomap(std::int64_t radiomap_id) {
    auto db = std::make_unique<Db>(db_.url());
    Db& on = *db;
    return std::make_unique<SqlRadioMapReader>(std::move(db), on, radiomap_id);
}

}  // namespace locus::store
