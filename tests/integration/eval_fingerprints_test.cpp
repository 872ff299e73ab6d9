// `locus eval fingerprints DIR` through the real binary on hand-made databases
// (tests/fixtures/fingerprint-dbs): the yardstick gives the answer worked out by hand below,
// every database and method gets its row, and bad input is named.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "server_process.hpp"
#include "build_paths.hpp"

namespace eval_fingerprints_test {
namespace {

using locus::testing::make_temp_dir;
using locus::testing::run_command;
using nlohmann::json;

const std::string kDbs = std::string(LOCUS_TEST_FIXTURES) + "/fingerprint-dbs";

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

json run_json(const std::vector<std::string>& extra) {
    std::vector<std::string> argv{LOCUS_CLI_BIN, "eval", "fingerprints", kDbs, "--json"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    const auto r = run_command(argv);
    EXPECT_EQ(r.status, 0) << r.err;
    return json::parse(r.out);
}

const json& row_of(const json& rows, const std::string& db, const std::string& algorithm) {
    for (const auto& r : rows)
        if (r["database"] == db && r["algorithm"] == algorithm) return r;
    ADD_FAILURE() << "no row for " << db << " / " << algorithm << " in " << rows.dump();
    static const json none;
    return none;
}

// hand/: the query (-50, -80, -70) dBm at (0, 0). The lowest training RSS is -90, so the
// yardstick's min is -91 and powed(r) = ((r + 91) / 91)^e. Sørensen distances to the query:
//   N1 (-51,-80,-70) at (2,0): 0.0280     N2 (-50,-81,-70) at (0,2): 0.0027
//   A  (-50,-70,-70) at (9,0): 0.0534     B  (-46,-80,-70) at (0,12): 0.1079
// so the 3 nearest are N2, N1, A and the answer their mean (11/3, 2/3): 3.727 m from the
// truth. Positive RSS with the Euclidean distance ranks B (4 dB off) before A (10 dB off)
// and answers (2/3, 14/3), 4.714 m away: the representation and distance decide.
TEST(EvalFingerprints, YardstickGivesTheHandComputedAnswer) {
    const json rows = run_json({"--algorithm", "yardstick"});
    ASSERT_EQ(rows.size(), 2u);
    const json& hand = row_of(rows, "hand", "yardstick");
    EXPECT_NEAR(hand["mean_error_m"].get<double>(), std::hypot(11.0 / 3.0, 2.0 / 3.0), 1e-6);
    EXPECT_EQ(hand["floor_hit_rate"].get<double>(), 1.0);
    EXPECT_EQ(hand["rps"].get<int>(), 5);

    const json euclid = run_json({"--algorithm", "knn", "--representation", "positive", "--distance", "euclidean",
                                  "--missing-rss", "-91", "--k", "3"});
    EXPECT_NEAR(row_of(euclid, "hand", "knn")["mean_error_m"].get<double>(), std::hypot(2.0 / 3.0, 14.0 / 3.0), 1e-6);
}

// vote/: the query equals V1's scan at (0,0) on floor 0, but the next two nearest, V2 (5,0)
// and V3 (0,5), are on floor 1, the true one: the yardstick's vote among its 3 gets the floor
// that 1-NN misses. Its position is the mean of all 3, (5/3, 5/3), 1.18 m from the truth
// (2.5, 2.5); the matchers' own rule, the mean of those on the voted floor, would hit it.
TEST(EvalFingerprints, YardstickTakesTheFloorByVoteAmongTheThree) {
    const json rows = run_json({"--algorithm", "yardstick"});
    const json& vote = row_of(rows, "vote", "yardstick");
    EXPECT_EQ(vote["floor_hit_rate"].get<double>(), 1.0);
    EXPECT_NEAR(vote["mean_error_m"].get<double>(), std::hypot(2.5 - 5.0 / 3.0, 2.5 - 5.0 / 3.0), 1e-6);
    const json knn3 = run_json({"--algorithm", "knn", "--k", "3"});
    EXPECT_NEAR(row_of(knn3, "vote", "knn")["mean_error_m"].get<double>(), 0.0, 1e-9);
    EXPECT_EQ(row_of(run_json({"--algorithm", "knn", "--k", "1"}), "vote", "knn")["floor_hit_rate"].get<double>(),
              0.0);
}

TEST(EvalFingerprints, AllGivesEveryMatcherAndTheYardstickPerDatabase) {
    const json rows = run_json({"--algorithm", "all"});
    ASSERT_EQ(rows.size(), 2u * 7u);
    for (const char* db : {"hand", "vote"})
        for (const char* alg : {"bsb", "nn", "bsbnn", "knn", "wknn", "bayes", "yardstick"}) {
            const json& r = row_of(rows, db, alg);
            for (const char* key : {"queries", "building_hit_rate", "floor_hit_rate", "mean_error_m", "median_error_m",
                                    "p75_error_m", "p95_error_m", "mean_error_evaal_m", "us_per_query"})
                EXPECT_TRUE(r.contains(key)) << db << " " << alg << " lacks " << key;
            EXPECT_EQ(r["queries"].get<int>(), 1);
        }
    // `default` is the server's matcher with no options: bayes today.
    const json def = run_json({"--algorithm", "default"});
    ASSERT_EQ(def.size(), 2u);
    EXPECT_EQ(def[0]["mean_error_m"], row_of(rows, def[0]["database"], "bayes")["mean_error_m"]);
}

// The EvAAL-style mean adds 4 m per floor of difference: vote/ with 1-NN answers floor 0 for
// a floor-1 query.
TEST(EvalFingerprints, EvaalMeanAddsFourMetresPerFloorMissed) {
    const json rows = run_json({"--algorithm", "knn", "--k", "1"});
    const json& r = row_of(rows, "vote", "knn");
    EXPECT_NEAR(r["mean_error_evaal_m"].get<double>() - r["mean_error_m"].get<double>(), 4.0, 1e-9);
}

// --cv never reads a test file: a database without one still runs.
TEST(EvalFingerprints, CrossValidationUsesTheTrainingRowsOnly) {
    const std::string dir = make_temp_dir();
    std::filesystem::create_directories(dir + "/only-train");
    std::filesystem::copy_file(kDbs + "/hand/trainingData.csv", dir + "/only-train/trainingData.csv");
    const auto r = run_command({LOCUS_CLI_BIN, "eval", "fingerprints", dir, "--cv", "5", "--algorithm", "wknn", "--json"});
    ASSERT_EQ(r.status, 0) << r.err;
    const json rows = json::parse(r.out);
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_EQ(rows[0]["queries"].get<int>(), 5);  // each training row queried once
    EXPECT_EQ(rows[0]["folds"].get<int>(), 5);

    const auto no_test = run_command({LOCUS_CLI_BIN, "eval", "fingerprints", dir});
    EXPECT_NE(no_test.status, 0);
    EXPECT_TRUE(contains(no_test.err, "only-train")) << no_test.err;
    EXPECT_TRUE(contains(no_test.err, "testData.csv")) << no_test.err;
}

// --cv-blocks deals whole blocks to the folds. hand/'s training positions: (2,0), (0,2),
// (9,0), (0,12) on floor 0 and (30,30) on floor 1. Cells of 100 m: one block per floor, so
// two folds hold rows whatever K; runs of 2 positions in file order: three blocks.
TEST(EvalFingerprints, CvBlocksDealWholeBlocksToTheFolds) {
    const std::string dir = make_temp_dir();
    std::filesystem::create_directories(dir + "/only-train");
    std::filesystem::copy_file(kDbs + "/hand/trainingData.csv", dir + "/only-train/trainingData.csv");
    auto cv = [&](const std::string& blocks) {
        const auto r = run_command(
            {LOCUS_CLI_BIN, "eval", "fingerprints", dir, "--cv", "5", "--cv-blocks", blocks, "--algorithm", "wknn", "--json"});
        EXPECT_EQ(r.status, 0) << r.err;
        return json::parse(r.out).at(0);
    };
    const json position = cv("position"), spatial = cv("spatial:100"), order = cv("order:2");
    EXPECT_EQ(position["folds"].get<int>(), 5);
    EXPECT_EQ(spatial["folds"].get<int>(), 2);
    EXPECT_EQ(order["folds"].get<int>(), 3);
    for (const json* row : {&position, &spatial, &order}) EXPECT_EQ((*row)["queries"].get<int>(), 5);
    EXPECT_EQ(spatial["cv_blocks"], "spatial:100");
    // Floor 1's one position held out against a map of floor 0 only: the floor is missed.
    EXPECT_LT(spatial["floor_hit_rate"].get<double>(), 1.0);
}

TEST(EvalFingerprints, BadInputIsNamed) {
    auto r = run_command({LOCUS_CLI_BIN, "eval", "fingerprints", kDbs, "--algorithm", "knnn"});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(contains(r.err, "knnn")) << r.err;

    for (const char* bad : {"spatial:0", "order:0", "cells:5", "spatial:-1"}) {
        r = run_command({LOCUS_CLI_BIN, "eval", "fingerprints", kDbs, "--cv", "2", "--cv-blocks", bad});
        EXPECT_NE(r.status, 0) << bad;
        EXPECT_TRUE(contains(r.err, "--cv-blocks")) << r.err;
        EXPECT_TRUE(contains(r.err, bad)) << r.err;
    }
    // Without --cv the test files would be read: blocks make no sense there.
    r = run_command({LOCUS_CLI_BIN, "eval", "fingerprints", kDbs, "--cv-blocks", "spatial:10"});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(contains(r.err, "needs --cv")) << r.err;
    r = run_command({LOCUS_CLI_BIN, "eval", "fingerprints", kDbs, "--cv", "2", "--tune-blocks", "spatial:10"});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(contains(r.err, "needs --tune")) << r.err;
    r = run_command({LOCUS_CLI_BIN, "eval", "fingerprints", kDbs, "--cv", "2", "--tune", "--algorithm", "default",
                     "--tune-blocks", "spatial:x"});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(contains(r.err, "--tune-blocks")) << r.err;

    const std::string empty = make_temp_dir();
    r = run_command({LOCUS_CLI_BIN, "eval", "fingerprints", empty});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(contains(r.err, "trainingData.csv")) << r.err;

    const std::string broken = make_temp_dir();
    std::filesystem::create_directories(broken + "/bad");
    std::ofstream(broken + "/bad/trainingData.csv") << "WAP001,LONGITUDE\n-50,1\n";
    std::ofstream(broken + "/bad/testData.csv") << "WAP001,LONGITUDE\n-50,1\n";
    r = run_command({LOCUS_CLI_BIN, "eval", "fingerprints", broken});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(contains(r.err, "bad")) << r.err;
    EXPECT_TRUE(contains(r.err, "line 1")) << r.err;
}

// --tune: the default is what match::tune picks on the training rows alone, and its row is
// that setting's figures (the same as naming it).
TEST(EvalFingerprints, TuneChoosesOnTheTrainingRowsAndReportsTheChoice) {
    const auto r = run_command({LOCUS_CLI_BIN, "eval", "fingerprints", kDbs, "--json", "--algorithm", "default", "--tune"});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(contains(r.err, "hand: tuned default: ")) << r.err;
    const json rows = json::parse(r.out);
    const json& hand = row_of(rows, "hand", "default");
    ASSERT_EQ(hand["tuned"].size(), 1u);
    // "wknn k=5 powed sorensen" → --algorithm wknn --k 5 --representation powed --distance sorensen
    std::istringstream name(hand["tuned"][0].get<std::string>());
    std::string algorithm, k, representation, distance;
    name >> algorithm >> k >> representation >> distance;
    ASSERT_NE(algorithm, "bayes") << "hand/ is made for knn: " << hand.dump();
    ASSERT_EQ(k.rfind("k=", 0), 0u) << hand.dump();
    std::vector<std::string> named{"--algorithm", algorithm, "--k", k.substr(2)};
    if (!representation.empty()) named.insert(named.end(), {"--representation", representation, "--distance", distance});
    EXPECT_DOUBLE_EQ(row_of(run_json(named), "hand", algorithm)["mean_error_m"].get<double>(),
                     hand["mean_error_m"].get<double>());

    EXPECT_FALSE(row_of(run_json({"--algorithm", "default"}), "hand", "default").contains("tuned"));
    // With --cv each split tunes on its own training folds.
    const auto cv = run_command({LOCUS_CLI_BIN, "eval", "fingerprints", kDbs, "--json", "--algorithm", "default", "--tune", "--cv", "2"});
    ASSERT_EQ(cv.status, 0) << cv.err;
    EXPECT_EQ(row_of(json::parse(cv.out), "hand", "default")["tuned"].size(), 2u);
}

// `locus eval uji` shares the tune and its --tune-blocks with eval fingerprints.
TEST(EvalUji, TuneBlocksAreAcceptedAndChecked) {
    const std::string train = kDbs + "/hand/trainingData.csv", test = kDbs + "/hand/testData.csv";
    auto r = run_command({LOCUS_CLI_BIN, "eval", "uji", "--train", train, "--test", test, "--algorithm", "default", "--tune",
                          "--tune-blocks", "spatial:100", "--json"});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(contains(r.err, "tuned default: ")) << r.err;
    EXPECT_EQ(json::parse(r.out)["algorithm"], "default");  // one method: one object
    r = run_command({LOCUS_CLI_BIN, "eval", "uji", "--train", train, "--test", test, "--tune-blocks", "spatial:100"});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(contains(r.err, "needs --tune")) << r.err;
    r = run_command({LOCUS_CLI_BIN, "eval", "uji", "--train", train, "--test", test, "--tune", "--tune-blocks", "order:0"});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(contains(r.err, "--tune-blocks")) << r.err;
    EXPECT_TRUE(contains(r.err, "order:0")) << r.err;
}

}  // namespace
}  // namespace eval_fingerprints_test
