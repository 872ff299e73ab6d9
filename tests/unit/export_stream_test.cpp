// A radio map's export written out piece by piece (http/radiomaps/export_stream.hpp) from the store's
// reader: the same bytes as the whole document written at once, whatever the piece size, and
// one snapshot however long it is read, without holding a writer back (SQLite file).
#include <gtest/gtest.h>

#include "http/radiomaps/export_stream.hpp"
#include "http/json_text.hpp"
#include "http/crud/store_json.hpp"
#include "store/sql_store.hpp"
#include "temp_dir.hpp"

namespace export_stream_test {
namespace {

using locus::RssStats;
using locus::http::ExportStream;
using locus::store::kind;
using locus::store::ScanBatch;
using locus::store::SqlStore;
using nlohmann::json;

using locus::testing::TempDir;

std::string drain(ExportStream& s) {
    std::string out;
    for (std::string piece = s.next(); !piece.empty(); piece = s.next()) out += piece;
    return out;
}

std::string streamed(SqlStore& repo, std::int64_t radiomap, std::size_t per_piece) {
    ExportStream s(repo.read_radiomap(radiomap), per_piece);
    return drain(s);
}

std::string whole(SqlStore& repo, std::int64_t radiomap) { return locus::http::json_text(locus::http::export_json(repo.export_radiomap(radiomap))); }

struct Surveyed {
    std::int64_t floor = 0, radiomap = 0, other = 0;
    std::vector<std::int64_t> rps;
};

// Two radio maps on one floor whose RP ids interleave, names that would confuse a writer
// cutting the document by hand, an RP with no measurement, and the floor's transmitters.
Surveyed survey(SqlStore& repo) {
    Surveyed s;
    const auto map = repo.create(kind("maps"), std::nullopt, {{"name", "M"}}).id;
    const auto building = repo.create(kind("buildings"), map, {{"name", "B"}}).id;
    s.floor = repo.create(kind("floors"), building, {{"name", "F"}, {"level", 0}, {"width", 40.0}, {"height", 20.0}}).id;
    s.radiomap = repo.create(kind("radiomaps"), s.floor, {{"name", "R \"rps\":[] \u00e9\u6f22"}, {"description", "],\"rps\":[]}"}}).id;
    s.other = repo.create(kind("radiomaps"), s.floor, {{"name", "other"}}).id;
    repo.create(kind("transmitters"), s.floor, {{"type", "wifi"}, {"bssid", "aa:00:00:00:00:01"}, {"x", 1.0}, {"y", 2.0}, {"tx_power", -30.0}});
    repo.create(kind("transmitters"), s.floor, {{"name", "beacon"}, {"type", "ble"}, {"bssid", "bb:00:00:00:00:02"}, {"x", 3.5}, {"y", 0.1}, {"tx_power", -59.0}, {"path_loss_exponent", 2.2}});
    for (int i = 0; i < 7; ++i) {
        const double x = 0.1 * i + 1.0 / 3.0;
        const auto rp = repo.create(kind("rps"), s.radiomap, {{"name", "p" + std::to_string(i) + (i == 3 ? "\"\\\n" : "")}, {"x", x}, {"y", 2.5}}).id;
        s.rps.push_back(rp);
        repo.create(kind("rps"), s.other, {{"name", "q" + std::to_string(i)}, {"x", 1.0}, {"y", 1.0}});
        if (i == 4) continue;  // no measurement
        std::vector<locus::Measurement> ms;
        for (int k = 0; k <= i % 3; ++k)
            ms.push_back({k == 2 ? "ble" : "wifi", locus::Bssid::stored("aa:00:00:00:00:0" + std::to_string(k + 1)), RssStats{-40.0 - i - k / 7.0, 1.5, 3}});
        repo.merge_scans(rp, ScanBatch{std::nullopt, ms, 3});
    }
    return s;
}

TEST(ExportStream, WritesTheBytesOfTheWholeDocument) {
    TempDir t("export");
    SqlStore repo(t.path());
    const auto s = survey(repo);
    const std::string expected = whole(repo, s.radiomap);
    ASSERT_EQ(json::parse(expected)["rps"].size(), 7u);
    for (const std::size_t per_piece : {1, 2, 3, 7, 256}) EXPECT_EQ(streamed(repo, s.radiomap, per_piece), expected) << per_piece;
    // A radio map with no RP, and its pieces: the head, then the tail.
    const auto empty = repo.create(kind("radiomaps"), s.floor, {{"name", "empty"}}).id;
    EXPECT_EQ(streamed(repo, empty, 2), whole(repo, empty));
    EXPECT_EQ(json::parse(streamed(repo, empty, 2))["rps"], json::array());
}

TEST(ExportStream, AnUnknownRadioMapIsNotFound) {
    TempDir t("export");
    SqlStore repo(t.path());
    EXPECT_THROW(repo.read_radiomap(4242), locus::store::NotFound);
}

TEST(ExportStream, ReadsOneSnapshotAndHoldsNoWriterBack) {
    TempDir t("export");
    SqlStore repo(t.path());
    const auto s = survey(repo);
    const std::string before = whole(repo, s.radiomap);
    ExportStream stream(repo.read_radiomap(s.radiomap), 2);
    std::string out = stream.next();  // the head: the snapshot is taken
    out += stream.next();             // the first two RPs
    // Writes while the export is half written: none waits for it (a writer held back would
    // throw SQLITE_BUSY after the busy timeout), and none shows in it.
    repo.update(kind("radiomaps"), s.radiomap, {{"name", "renamed"}});
    repo.merge_scans(s.rps.back(), ScanBatch{std::nullopt, {{"wifi", locus::Bssid::stored("cc:00:00:00:00:09"), RssStats{-70.0, 0.0, 1}}}, 1});
    repo.create(kind("rps"), s.radiomap, {{"name", "late"}, {"x", 9.0}, {"y", 9.0}});
    repo.remove(kind("rps"), s.rps[5]);
    out += drain(stream);
    EXPECT_EQ(out, before);
    const json after = json::parse(whole(repo, s.radiomap));
    EXPECT_EQ(after["name"], "renamed");
    EXPECT_EQ(after["rps"].size(), 7u);  // one added, one removed
    EXPECT_EQ(after["rps"].back()["name"], "late");
}

}  // namespace
}  // namespace export_stream_test
