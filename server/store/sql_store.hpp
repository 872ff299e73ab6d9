#pragma once
// The backend over store::Db: one SQLite connection, or one PostgreSQL connection (a
// postgresql:// URL), every public call serialised by a mutex. On PostgreSQL a write also
// takes one advisory lock for its transaction, so writes from every server sharing the
// database run one at a time as they do on SQLite (read-modify-write such as a Welford merge
// stays exact), and announces its changes to the other servers (pg_changes.hpp). A
// write, and a read of several statements, is one transaction (BEGIN IMMEDIATE; a read: BEGIN); a read of
// one statement is its own. Reads of one call see one snapshot; the SQL is built from
// the kind descriptors, so a new field in kinds.cpp needs a migration and nothing here.
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "store/pg_changes.hpp"
#include "store/db.hpp"
#include "store/store.hpp"

namespace locus::store {

// One AP of an upload merged into what the RP holds (RssStats::merge); throws OutOfRange when
// the count would pass kMaxCount. Both backends' uploads merge through it.
RssStats merged_or_refused(RssStats stored, const Measurement& m);
// Throws OutOfRange when adding `scans` to the RP's stored scan count would pass kMaxCount.
void refuse_scans_past_max(std::optional<std::int64_t> stored, std::int64_t scans);

// The columns a Kind's row is selected with, for read_row.
std::string column_list(const Kind& k);
// A row selected with column_list(k); a room's rectangles are read on `db` too.
Record read_row(Db& db, const Kind& k, Stmt& s);

class SqlStore final : public Store {
public:
    // Opens (creating if missing) and migrates the database file.
    explicit SqlStore(const std::string& path);

    const std::string& location() const override { return db_.path(); }
    const std::string& connection() const override { return db_.url(); }
    std::string change_origin() const override { return origin_; }
    void probe_write() override;
    // PostgreSQL: the round trips this store's connection has made (Db::pg_round_trips).
    std::int64_t round_trips() {
        std::lock_guard lock(mu_);
        return db_.pg_round_trips();
    }

    Record create(const Kind& k, std::optional<std::int64_t> parent_id, const Fields& values) override;
    Record get(const Kind& k, std::int64_t id) override;
    RecordPage list(const Kind& k, std::optional<std::int64_t> parent_id, std::int64_t limit,
                    std::int64_t offset) override;
    Record update(const Kind& k, std::int64_t id, const Fields& values) override;
    void remove(const Kind& k, std::int64_t id) override;
    std::vector<Record> write_rows(const Kind& k, std::optional<std::int64_t> parent_id,
                                   const std::vector<RowWrite>& rows) override;

    RpRecord rp_with_measurements(std::int64_t rp_id) override;
    UploadResult merge_scans(std::int64_t rp_id, const ScanBatch& batch) override;

    RadioMapExport export_radiomap(std::int64_t radiomap_id) override;
    std::unique_ptr<RadioMapReader> read_radiomap(std::int64_t radiomap_id) override;  // sql_export.cpp
    ImportedRadioMap import_radiomap(std::int64_t floor_id, const RadioMapDocument& doc) override;
    ImportedRadioMap add_rps(std::int64_t radiomap_id, const std::vector<RpDocument>& rps) override;
    Record import_map_bundle(const MapBundle& bundle) override;
    bool has_maps() override;

    std::optional<StoredPlan> plan_of_floor(std::int64_t floor_id) override;
    StoredPlan put_plan(std::int64_t floor_id, const plan::Plan& plan, const PlanCheck& check) override;
    void remove_plan(std::int64_t floor_id) override;
    std::vector<FloorWithPlan> plans_of_map(std::int64_t map_id) override;
    std::vector<FloorDirectory> directory_of_map(std::int64_t map_id) override;  // sql_directory.cpp

    std::optional<FloorImage> image_of_floor(std::int64_t floor_id) override;
    std::optional<std::pair<FloorImage, std::string>> image_with_bytes(std::int64_t floor_id) override;
    std::pair<FloorImage, bool> put_image(const FloorImage& image, std::string_view bytes) override;
    FloorImage change_placement(std::int64_t floor_id, const PlacementChange& change) override;
    void remove_image(std::int64_t floor_id) override;

    std::optional<RadiomapSettings> settings_of_radiomap(std::int64_t radiomap_id) override;  // sql_settings.cpp
    RadiomapSettings put_radiomap_settings(std::int64_t radiomap_id, const RadiomapSettings& settings) override;
    std::vector<StoredRp> rps_of_radiomap(std::int64_t radiomap_id) override;
    std::vector<StoredRp> rps_of_map(std::int64_t map_id) override;
    std::vector<Room> rooms_of_floor(std::int64_t floor_id) override;
    std::int64_t map_of_radiomap(std::int64_t radiomap_id) override;
    std::vector<std::int64_t> radiomap_ids() override;

private:
    // Runs body(changes) in one write transaction under the lock, commits, then publishes the
    // changes it listed (none when it threw: nothing was written).
    template <typename Body>
    auto write(Body&& body);
    Record row(const Kind& k, Stmt& s);
    Record get_locked(const Kind& k, std::int64_t id);
    void require_exists(const Kind& k, std::int64_t id);
    void replace_rects(std::int64_t room_id, const std::vector<Rect>& rects);
    std::vector<Rect> rects_of(std::int64_t room_id);
    std::int64_t insert_row(const Kind& k, std::optional<std::int64_t> parent_id, const Fields& values);
    void update_row(const Kind& k, std::int64_t id, const Fields& values);
    std::int64_t insert_radiomap(std::int64_t floor_id, const RadioMapDocument& doc, std::int64_t* measurements);
    void insert_rps(std::int64_t radiomap_id, const std::vector<RpDocument>& rps, std::int64_t* measurements);
    // A radio map document's transmitters on its floor: (created, kept as already stored).
    std::pair<std::int64_t, std::int64_t> insert_transmitters(std::int64_t floor_id, const std::vector<Fields>& txs,
                                                              std::vector<Change>& changes);
    void merge_measurements(std::int64_t rp_id, const std::vector<Measurement>& ms, std::int64_t scans);
    // merge_scans on PostgreSQL, inside write()'s transaction: one statement reads the RP and
    // records the upload_id, one writes every merged AP and the RP (sql_upload_pg.cpp).
    UploadResult pg_merge_scans(std::int64_t rp_id, const ScanBatch& batch, std::vector<Change>& changes);
    std::vector<Measurement> measurements_of(std::int64_t rp_id);
    std::vector<StoredRp> load_rps(std::string_view where, std::int64_t id);
    std::optional<std::int64_t> map_of_radiomap_locked(std::int64_t radiomap_id);
    // sql_plan.cpp: a plan's rows, read and written inside a caller's transaction.
    std::optional<StoredPlan> read_plan(std::int64_t floor_id);
    void write_plan_features(std::int64_t floor_id, const plan::Plan& plan);
    // sql_plan_keep.cpp: inside put_plan's transaction, sets every room_id and poi_id of
    // `plan` and writes the rooms and POIs to match (Store::put_plan).
    void keep_rooms(std::int64_t floor_id, plan::Plan& plan, std::vector<Change>& changes);
    void keep_pois(std::int64_t floor_id, plan::Plan& plan, std::vector<Change>& changes);
    // Throws KeptByPlan when a room or POI is kept by a plan (no-op for other kinds).
    void refuse_if_kept(const Kind& k, std::int64_t id);
    // sql_image.cpp: the metadata row, inside a caller's transaction.
    std::optional<FloorImage> read_image(std::int64_t floor_id);
    // Where a row of `k` sits, for its Change (documents.hpp).
    Change change_of(const Kind& k, std::int64_t id, bool deleted);

    // PostgreSQL only (sql_store_pg.cpp): the write lock, taken with BEGIN, and the change
    // announcement, sent with COMMIT (each one round trip with its neighbour).
    void pg_start_watching();
    static std::string_view pg_write_lock();
    std::string pg_announcement(const std::vector<Change>& changes);

    std::mutex mu_;
    Db db_;
    std::string origin_;  // this server, in its change announcements
    std::unique_ptr<ChangeWatcher> watcher_;
};

template <typename Body>
auto SqlStore::write(Body&& body) {
    std::vector<Change> changes;
    if constexpr (std::is_void_v<decltype(body(changes))>) {
        {
            std::lock_guard lock(mu_);
            Transaction tx(db_, Transaction::Mode::write, db_.is_postgres() ? pg_write_lock() : "");
            body(changes);
            tx.commit(db_.is_postgres() && !changes.empty() ? pg_announcement(changes) : std::string());
        }
        publish(changes);
    } else {
        auto result = [&] {
            std::lock_guard lock(mu_);
            Transaction tx(db_, Transaction::Mode::write, db_.is_postgres() ? pg_write_lock() : "");
            auto r = body(changes);
            tx.commit(db_.is_postgres() && !changes.empty() ? pg_announcement(changes) : std::string());
            return r;
        }();
        publish(changes);
        return result;
    }
}

}  // namespace locus::store
