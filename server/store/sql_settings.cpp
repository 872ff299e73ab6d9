// A radio map's stored matcher settings (schema/007_radiomap_settings.sql).
#include "store/sql_store.hpp"

namespace locus::store {

namespace {
std::optional<RadiomapSettings> read_settings(Db& db, std::int64_t radiomap_id) {
    Stmt s(db, "SELECT settings, tune, updated_at FROM radiomap_settings WHERE radiomap_id = ?");
    s.bind(1, radiomap_id);
    if (!s.step()) return std::nullopt;
    return RadiomapSettings{s.text(0), s.text(1), s.text(2)};
}
}  // namespace

std::optional<RadiomapSettings> SqlStore::settings_of_radiomap(std::int64_t radiomap_id) {
    std::lock_guard lock(mu_);
    Transaction tx(db_, Transaction::Mode::read);
    require_exists(kind("radiomaps"), radiomap_id);
    auto out = read_settings(db_, radiomap_id);
    tx.commit();
    return out;
}

RadiomapSettings SqlStore::put_radiomap_settings(std::int64_t radiomap_id, const RadiomapSettings& settings) {
    return write([&](std::vector<Change>& changes) {
        require_exists(kind("radiomaps"), radiomap_id);
        Stmt s(db_,
               "INSERT INTO radiomap_settings (radiomap_id, settings, tune) VALUES (?, ?, ?) "
               "ON CONFLICT (radiomap_id) DO UPDATE SET settings = excluded.settings, tune = excluded.tune, "
               "updated_at = strftime('%Y-%m-%dT%H:%M:%fZ', 'now')");
        s.bind(1, radiomap_id).bind(2, std::string_view(settings.settings)).bind(3, std::string_view(settings.tune)).run();
        changes.push_back(change_of(kind("radiomaps"), radiomap_id, false));
        return read_settings(db_, radiomap_id).value();
    });
}

}  // namespace locus::store
