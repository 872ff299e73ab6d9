#pragma once
// The SQLite repository: every public call is one transaction, serialised on one connection.
// Rows come back as JSON because their only consumer is the HTTP layer; inputs have already
// been validated there against the same kind descriptors (store/kinds.hpp).
#include <cstdint>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "locus/radio_map.hpp"
#include "store/kinds.hpp"
#include "store/sqlite.hpp"

namespace locus::store {

struct NotFound : std::runtime_error {
    using std::runtime_error::runtime_error;
};
struct Conflict : std::runtime_error {
    using std::runtime_error::runtime_error;
};
// A write that would take a stored count past kMaxCount (the API answers 422 out_of_range).
struct OutOfRange : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct ScanUpload {
    std::optional<std::string> upload_id;
    std::vector<Measurement> measurements;  // already validated and normalised
    std::int64_t scans = 0;                 // raw scans these measurements summarise
};

struct UploadResult {
    bool applied = false;  // false: the upload_id had been applied before; nothing changed
    nlohmann::json rp;     // the RP with its measurements after the call
};

// One RP as the localization index needs it, with its place in the hierarchy.
struct StoredRp {
    ReferencePoint rp;
    std::int64_t radiomap_id = 0;
    std::int64_t floor_id = 0;
    std::int64_t building_id = 0;
};

class Repository {
public:
    explicit Repository(const std::string& path);
    const std::string& path() const { return db_.path(); }

    // Commits a one-row change in its own transaction, so that the commit has to reach the
    // WAL on disk: throws SqliteError when the database cannot really be written (GET /ready).
    void probe_write();

    nlohmann::json create(const Kind& k, std::optional<std::int64_t> parent_id, const nlohmann::json& values);
    nlohmann::json get(const Kind& k, std::int64_t id);
    nlohmann::json list(const Kind& k, std::optional<std::int64_t> parent_id, std::int64_t limit,
                        std::int64_t offset);
    nlohmann::json update(const Kind& k, std::int64_t id, const nlohmann::json& values);
    void remove(const Kind& k, std::int64_t id);

    nlohmann::json rp_with_measurements(std::int64_t rp_id);
    UploadResult merge_scans(std::int64_t rp_id, const ScanUpload& upload);

    // The radio-map exchange format: {"format","name","description","rps":[{name,x,y,scans,measurements}]}.
    nlohmann::json export_radiomap(std::int64_t radiomap_id);
    nlohmann::json import_radiomap(std::int64_t floor_id, const nlohmann::json& doc);
    // A whole map with buildings, floors, rooms, POIs and radio maps (the demo map's format).
    nlohmann::json import_map_bundle(const nlohmann::json& bundle);
    bool has_maps();

    // For the localization index. Each is a consistent snapshot.
    std::vector<StoredRp> rps_of_radiomap(std::int64_t radiomap_id);
    std::vector<StoredRp> rps_of_map(std::int64_t map_id);
    std::vector<Room> rooms_of_floor(std::int64_t floor_id);
    std::int64_t map_of_radiomap(std::int64_t radiomap_id);
    std::vector<std::int64_t> radiomap_ids();

private:
    nlohmann::json row_json(const Kind& k, Stmt& s);
    nlohmann::json get_locked(const Kind& k, std::int64_t id);
    void require_exists(const Kind& k, std::int64_t id);
    void replace_rects(std::int64_t room_id, const nlohmann::json& rects);
    nlohmann::json rects_of(std::int64_t room_id);
    std::int64_t insert_row(const Kind& k, std::optional<std::int64_t> parent_id, const nlohmann::json& values);
    void merge_measurements(std::int64_t rp_id, const std::vector<Measurement>& ms, std::int64_t scans);
    nlohmann::json measurements_of(std::int64_t rp_id);
    std::vector<StoredRp> load_rps(std::string_view where, std::int64_t id);

    std::mutex mu_;
    Db db_;
};

}  // namespace locus::store
