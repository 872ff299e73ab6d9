// `locus survey upload/plan` and `locus export` against the real server: golden exports for
// both file formats, re-uploads that change nothing, an interrupted upload resumed, malformed
// lines skipped or (--strict) the whole file refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "hierarchy.hpp"
#include "server_process.hpp"
#include "text_file.hpp"
#include "build_paths.hpp"

namespace survey_upload_test {
namespace {

using locus::testing::run_command;
using locus::testing::ServerProcess;
using locus::testing::body_of;
using nlohmann::json;

using locus::testing::slurp;

std::string fixture(const std::string& name) { return std::string(LOCUS_TEST_FIXTURES) + "/survey/" + name; }

// Header first, then the lines sorted: RP creation order depends on the upload threads.
std::string sorted_lines(const std::string& text) {
    std::vector<std::string> lines;
    std::stringstream ss(text);
    for (std::string l; std::getline(ss, l);) lines.push_back(l);
    if (lines.size() > 1) std::sort(lines.begin() + 1, lines.end());
    std::string out;
    for (const auto& l : lines) out += l + "\n";
    return out;
}

class SurveyUpload : public ::testing::Test {
protected:
    ServerProcess server{{"--quiet"}};
    std::int64_t floor = 0;

    void SetUp() override {
        const auto map = server.post("/v1/maps", {{"name", "HQ"}});
        ASSERT_EQ(map.status, 201) << map.raw;
        const auto b = server.post("/v1/maps/" + std::to_string(map.body["id"].get<int>()) + "/buildings", {{"name", "Main"}});
        ASSERT_EQ(b.status, 201) << b.raw;
        const auto f = server.post("/v1/buildings/" + std::to_string(b.body["id"].get<int>()) + "/floors",
                                   {{"name", "Ground"}, {"level", 0}, {"width", 10.0}, {"height", 6.0}});
        ASSERT_EQ(f.status, 201) << f.raw;
        floor = f.body["id"].get<std::int64_t>();
    }

    std::string radiomap(const std::string& name) {
        const auto r = server.post("/v1/floors/" + std::to_string(floor) + "/radiomaps", {{"name", name}});
        EXPECT_EQ(r.status, 201) << r.raw;
        return std::to_string(r.body.value("id", 0));
    }

    locus::testing::CommandResult upload(const std::string& rm, std::vector<std::string> extra) {
        std::vector<std::string> argv{LOCUS_CLI_BIN, "survey", "upload", "--server", server.url(), "--radiomap", rm, "--no-progress"};
        argv.insert(argv.end(), extra.begin(), extra.end());
        return run_command(argv);
    }

    std::string export_csv(const std::string& rm) {
        const auto r = run_command({LOCUS_CLI_BIN, "export", "--server", server.url(), "--radiomap", rm, "--format", "csv"});
        EXPECT_EQ(r.status, 0) << r.err;
        return sorted_lines(r.out);
    }
};

TEST_F(SurveyUpload, JsonLinesMatchesGoldenExport) {
    const auto rm = radiomap("jsonl");
    const auto r = upload(rm, {fixture("walk.jsonl")});
    ASSERT_EQ(r.status, 0) << r.err;
    const json s = json::parse(r.out);
    EXPECT_EQ(s["rps"], 3);
    EXPECT_EQ(s["created"], 3);
    EXPECT_EQ(s["applied"], 3);
    EXPECT_EQ(s["scans"], 6);
    EXPECT_EQ(s["readings"], 9);
    EXPECT_EQ(export_csv(rm), sorted_lines(slurp(fixture("walk_export.csv"))));
}

TEST_F(SurveyUpload, CsvMatchesTheSameGoldenExport) {
    const auto rm = radiomap("csv");
    const auto r = upload(rm, {fixture("walk.csv")});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(export_csv(rm), sorted_lines(slurp(fixture("walk_export.csv"))));
}

TEST_F(SurveyUpload, SameFileTwiceDoesNotDoubleCount) {
    const auto rm = radiomap("twice");
    ASSERT_EQ(upload(rm, {fixture("walk.jsonl")}).status, 0);
    const auto again = upload(rm, {fixture("walk.jsonl")});
    ASSERT_EQ(again.status, 0) << again.err;
    const json s = json::parse(again.out);
    EXPECT_EQ(s["created"], 0);
    EXPECT_EQ(s["applied"], 0);
    EXPECT_EQ(s["already_uploaded"], 3);
    EXPECT_EQ(export_csv(rm), sorted_lines(slurp(fixture("walk_export.csv"))));
    // The same scans as CSV are another file: the server merges them (twice the samples).
    ASSERT_EQ(upload(rm, {fixture("walk.csv")}).status, 0);
    const auto rps = body_of(server.get("/v1/radiomaps/" + rm + "/export"))["rps"];
    std::int64_t scans = 0;
    for (const auto& rp : rps) scans += rp["scans"].get<std::int64_t>();
    EXPECT_EQ(scans, 12);
}

TEST_F(SurveyUpload, InterruptedUploadResumesToTheCleanResult) {
    const auto rm = radiomap("resumed");
    const auto cut = upload(rm, {"--concurrency", "1", "--stop-after", "1", fixture("walk.jsonl")});
    EXPECT_EQ(cut.status, 3) << cut.err;
    EXPECT_EQ(json::parse(cut.out)["applied"], 1);
    EXPECT_EQ(body_of(server.get("/v1/radiomaps/" + rm + "/rps"))["total"], 1);
    const auto rest = upload(rm, {fixture("walk.jsonl")});
    ASSERT_EQ(rest.status, 0) << rest.err;
    const json s = json::parse(rest.out);
    EXPECT_EQ(s["applied"], 2);
    EXPECT_EQ(s["already_uploaded"], 1);
    EXPECT_EQ(export_csv(rm), sorted_lines(slurp(fixture("walk_export.csv"))));
}

TEST_F(SurveyUpload, UploadSurvivesAServerRestartMidway) {
    // The server dies after the first RPs; the re-run against the restarted server completes.
    const auto rm = radiomap("killed");
    ASSERT_EQ(upload(rm, {"--concurrency", "1", "--stop-after", "2", fixture("walk.jsonl")}).status, 3);
    server.kill9();
    const auto down = upload(rm, {"--retries", "2", fixture("walk.jsonl")});
    EXPECT_NE(down.status, 0);
    server.start();
    const auto rest = run_command({LOCUS_CLI_BIN, "survey", "upload", "--server", server.url(), "--radiomap", rm, "--no-progress",
                                   fixture("walk.jsonl")});
    ASSERT_EQ(rest.status, 0) << rest.err;
    EXPECT_EQ(export_csv(rm), sorted_lines(slurp(fixture("walk_export.csv"))));
}

TEST_F(SurveyUpload, MalformedLinesAreSkippedWithTheirLineNumbers) {
    const auto rm = radiomap("lenient");
    const auto r = upload(rm, {fixture("walk_malformed.jsonl")});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("walk_malformed.jsonl:3:"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("walk_malformed.jsonl:5:"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("walk_malformed.jsonl:7:"), std::string::npos) << r.err;
    EXPECT_EQ(json::parse(r.out)["malformed_lines"], 3);
    EXPECT_EQ(export_csv(rm), sorted_lines(slurp(fixture("walk_export.csv"))));
}

TEST_F(SurveyUpload, StrictRefusesTheWholeFile) {
    const auto rm = radiomap("strict");
    const auto r = upload(rm, {"--strict", fixture("walk_malformed.jsonl"), fixture("walk.csv")});
    EXPECT_EQ(r.status, 2) << r.err;
    const json s = json::parse(r.out);
    EXPECT_EQ(s["refused_files"], 1);
    EXPECT_TRUE(s["files"][0]["refused"].get<bool>());
    // Only walk.csv went in.
    EXPECT_EQ(export_csv(rm), sorted_lines(slurp(fixture("walk_export.csv"))));
}

TEST_F(SurveyUpload, ExportJsonReimportsToTheSameRadioMap) {
    const auto rm = radiomap("source");
    ASSERT_EQ(upload(rm, {fixture("walk.jsonl")}).status, 0);
    const auto r = run_command({LOCUS_CLI_BIN, "export", "--server", server.url(), "--radiomap", rm, "--format", "json"});
    ASSERT_EQ(r.status, 0) << r.err;
    json doc = json::parse(r.out);
    EXPECT_EQ(doc["format"], "locus-radiomap/1");
    doc["name"] = "copy";
    doc.erase("floor_id");
    const auto imported = server.post("/v1/floors/" + std::to_string(floor) + "/radiomaps/import", doc);
    ASSERT_EQ(imported.status, 201) << imported.raw;
    EXPECT_EQ(export_csv(std::to_string(imported.body["id"].get<int>())), sorted_lines(slurp(fixture("walk_export.csv"))));
}

TEST_F(SurveyUpload, PlanSkipsPointsOutsideRoomsAndCreatesOnce) {
    ASSERT_EQ(server.post("/v1/floors/" + std::to_string(floor) + "/rooms",
                          {{"name", "left"}, {"rects", {{{"xmin", 0}, {"ymin", 0}, {"xmax", 6}, {"ymax", 6}}}}})
                  .status,
              201);
    const auto rm = radiomap("grid");
    std::vector<std::string> argv{LOCUS_CLI_BIN, "survey", "plan", "--server", server.url(), "--floor", std::to_string(floor),
                                  "--cell", "2", "--radiomap", rm, "--create"};
    const auto r = run_command(argv);
    ASSERT_EQ(r.status, 0) << r.err;
    const json p = json::parse(r.out);
    EXPECT_EQ(p["required_points"], 15);  // ceil(10 · 6 / 2²)
    EXPECT_EQ(p["proposed"], 9);
    EXPECT_EQ(p["outside_rooms"], 6);
    EXPECT_EQ(p["created"], 9);
    const auto again = run_command(argv);
    ASSERT_EQ(again.status, 0) << again.err;
    EXPECT_EQ(json::parse(again.out)["created"], 0);
    EXPECT_EQ(body_of(server.get("/v1/radiomaps/" + rm + "/rps"))["total"], 9);
}

TEST_F(SurveyUpload, ApiKeyFromTheEnvironment) {
    ServerProcess secured{{"--quiet", "--api-key", "s3cret"}};
    secured.set_api_key("s3cret");
    const auto map = secured.post("/v1/maps", {{"name", "K"}});
    const auto b = secured.post("/v1/maps/" + std::to_string(map.body["id"].get<int>()) + "/buildings", {{"name", "B"}});
    const auto f = secured.post("/v1/buildings/" + std::to_string(b.body["id"].get<int>()) + "/floors",
                                {{"name", "F"}, {"level", 0}, {"width", 10.0}, {"height", 6.0}});
    const auto rm = secured.post("/v1/floors/" + std::to_string(f.body["id"].get<int>()) + "/radiomaps", {{"name", "R"}});
    ASSERT_EQ(rm.status, 201) << rm.raw;
    const std::vector<std::string> argv{LOCUS_CLI_BIN, "survey", "upload", "--server", secured.url(), "--radiomap",
                                        std::to_string(rm.body["id"].get<int>()), "--no-progress", fixture("walk.jsonl")};
    const auto denied = run_command(argv);
    EXPECT_NE(denied.status, 0);
    EXPECT_NE(denied.err.find("Bearer"), std::string::npos) << denied.err;
    const auto ok = run_command(argv, {"LOCUS_API_KEY=s3cret"});
    EXPECT_EQ(ok.status, 0) << ok.err;
}

// Regression: a CSV cell with a byte that is not UTF-8 is a malformed line like any other
// (before, RP 'X' was created, and its upload failed with a JSON type_error on every run and
// left it empty).
TEST_F(SurveyUpload, ACellThatIsNotUtf8IsAMalformedLine) {
    const std::string dir = locus::testing::make_temp_dir();
    const std::string file = dir + "/bytes.csv";
    {
        std::ofstream out(file, std::ios::binary);
        out << "rp,x,y,t,bssid,rss\n"
               "A,1,1,1,aa:bb:cc:00:00:01,-50\n"
               "X,2,2,1,aa:bb:cc:00:00:\xff\xfe,-60\n"
               "X,2,2,1,aa:bb:cc:00:00:02,-61\n";
    }
    const auto rm = radiomap("bytes");
    const auto r = upload(rm, {file});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find(file + ":3:"), std::string::npos) << r.err;
    const json s = json::parse(r.out);
    EXPECT_EQ(s["malformed_lines"], 1);
    EXPECT_EQ(s["failed"], 0);
    EXPECT_EQ(s["applied"], 2);
    const auto rps = server.get("/v1/radiomaps/" + rm + "/export");
    ASSERT_EQ(rps.status, 200) << rps.raw;
    ASSERT_EQ(rps.body["rps"].size(), 2u);
    for (const auto& rp : rps.body["rps"]) EXPECT_EQ(rp["scans"], 1) << rp.dump();

    // --strict refuses the file, naming the line, and creates nothing.
    const auto strict_rm = radiomap("bytes-strict");
    const auto strict = upload(strict_rm, {"--strict", file});
    EXPECT_EQ(strict.status, 2) << strict.err;
    EXPECT_NE(strict.err.find(file + ":3:"), std::string::npos) << strict.err;
    const auto none = server.get("/v1/radiomaps/" + strict_rm + "/rps");
    ASSERT_EQ(none.status, 200) << none.raw;
    EXPECT_EQ(none.body["total"], 0);
    std::filesystem::remove_all(dir);
}

// An RP is never left created but empty: when its scans cannot be sent (here the server takes
// no body over 1,500 bytes, so the RP is created and its upload refused with 413), the RP this
// run created goes again, and a re-run finds nothing half-done.
TEST_F(SurveyUpload, AFailedUploadLeavesNoEmptyRp) {
    ServerProcess small{{"--quiet", "--max-body-bytes", "1500"}};
    const auto h = locus::testing::make_hierarchy(small);
    const std::string dir = locus::testing::make_temp_dir();
    const std::string file = dir + "/big.csv";
    {
        std::ofstream out(file, std::ios::binary);
        out << "rp,x,y,t,bssid,rss\n";
        for (int t = 0; t < 40; ++t) out << "BIG,1,1," << t << ",aa:bb:cc:00:00:01,-50\n";
    }
    const std::vector<std::string> argv{LOCUS_CLI_BIN, "survey", "upload", "--server", small.url(), "--radiomap",
                                        std::to_string(h.radiomap), "--no-progress", file};
    for (int run = 0; run < 2; ++run) {
        const auto r = run_command(argv);
        EXPECT_NE(r.status, 0) << r.err;
        EXPECT_EQ(json::parse(r.out, nullptr, false).value("failed", -1), 1) << r.out;
        const auto rps = small.get("/v1/radiomaps/" + std::to_string(h.radiomap) + "/rps");
        ASSERT_EQ(rps.status, 200) << rps.raw;
        EXPECT_EQ(rps.body["total"], 0) << "run " << run << " left an empty RP: " << rps.raw;
    }
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace survey_upload_test
