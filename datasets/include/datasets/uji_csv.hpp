#pragma once
// locus_datasets (datasets/): the data set and file readers, a library apart from the CLI so that
// tests, benchmarks and fuzz targets read a file exactly as the commands do.
//
// Reader for the UJIIndoorLoc CSV (Torres-Sospedra et al., IPIN 2014): 520 WAP columns of
// RSS (100 = not detected), then LONGITUDE, LATITUDE, FLOOR, BUILDINGID, SPACEID,
// RELATIVEPOSITION, USERID, PHONEID, TIMESTAMP. Shared by `locus eval uji` and
// `locus import uji`.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "locus/match/index.hpp"
#include "locus/radio_map.hpp"

namespace locus::datasets::uji {

inline constexpr int kNotDetected = 100;

struct Row {
    // (column of the WAP, RSS dBm) for every WAP heard with a valid RSS, by column.
    std::vector<std::pair<std::uint16_t, double>> heard;
    double longitude = 0.0;  // projected metres
    double latitude = 0.0;
    int floor = 0;
    int building = 0;
    int space_id = 0;
    int relative_position = 0;
    int user_id = 0;
    int phone_id = 0;
    long long timestamp = 0;
};

struct Data {
    std::vector<std::string> waps;  // header names of the WAP columns, e.g. "WAP001"
    std::vector<Row> rows;
};

// Throws std::runtime_error naming the line on a malformed file.
Data parse(std::string_view csv);
Data read_file(const std::string& path);

// The AP id the rest of Locus uses for a WAP column: the normalised header ("wap001").
std::string bssid_of(const Data& data, std::uint16_t column);

// One online scan per row.
Scan scan_of(const Data& data, const Row& row);

// Rows sharing (building, floor, longitude, latitude) are repeated scans at one RP.
struct ReferencePointGroup {
    int building = 0;
    int floor = 0;
    double longitude = 0.0;
    double latitude = 0.0;
    std::vector<std::size_t> rows;  // indices into Data::rows
    std::vector<Measurement> measurements;  // per WAP heard: mean, population variance, count
};

// Groups the given rows (all rows when `rows` is empty) into RPs, ordered by
// (building, floor, longitude, latitude); measurements are in WAP column order.
std::vector<ReferencePointGroup> group_reference_points(const Data& data, const std::vector<std::size_t>& rows = {});

// The floor id the in-process matchers give a (building, floor): building · 100 + floor.
inline long long floor_id(int building, int floor) { return building * 100LL + floor; }

// The groups of `rows` (all when empty) as matcher RPs, ids 1, 2, … in group order, with
// floor_id(building, floor) and the building as building id.
std::vector<match::IndexedRp> indexed_rps(const Data& data, const std::vector<std::size_t>& rows = {});

// The given rows (all when empty) as one-scan matcher RPs, one per row in the given order
// (ids 1, 2, …): the raw fingerprints, with nothing averaged away.
std::vector<match::IndexedRp> raw_rps(const Data& data, const std::vector<std::size_t>& rows = {});

// The lowest valid RSS heard in the given rows (all when empty), or nullopt if none is.
std::optional<double> min_rss(const Data& data, const std::vector<std::size_t>& rows = {});

}  // namespace locus::datasets::uji
