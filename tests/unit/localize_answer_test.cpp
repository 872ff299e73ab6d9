// The localize answer (server/http/localize/localize_answer.hpp): written with the snapshot's pre-rendered
// candidate parts it is byte for byte the answer written field by field, and it is valid JSON
// holding what the matcher found.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "http/localize/localize_answer.hpp"
#include "match_fixture.hpp"

namespace localize_answer_test {
namespace {

using namespace locus;
using namespace locus::http;
using locus::localize::Snapshot;
using locus::match::testing::m;
using locus::match::testing::rp;

Snapshot corridor() {
    Snapshot s;
    // Coordinates whose shortest decimal forms are long, and ids on two floors.
    s.index = match::Index::build({rp(11, {0.1, 1.0 / 3.0}, {m("a", -40), m("b", -70)}, 7, 2),
                                   rp(12, {10.000000000000002, 5.0}, {m("a", -60), m("b", -60)}, 7, 2),
                                   rp(13, {-20.25, 1e-7}, {m("a", -70), m("b", -40)}, 8, 2)});
    s.rooms_by_floor[7] = {Room{5, "Lab \"A\"", {Rect{-1, -1, 1, 1}}}};
    return s;
}

LocalizeRequest request(const char* algorithm) {
    return parse_localize_request(std::string(R"({"algorithm":")") + algorithm +
                                  R"(","scans":[[{"bssid":"a","rss":-42},{"bssid":"b","rss":-69}]]})");
}

TEST(LocalizeAnswer, PreRenderedCandidatesWriteTheSameBytes) {
    Snapshot plain = corridor();
    Snapshot prepared = corridor();
    prepare_answers(prepared);
    ASSERT_EQ(prepared.candidate_json.size(), 3u);
    for (const char* algorithm : {"bsb", "nn", "bsbnn", "knn", "wknn", "bayes"}) {
        const std::string a = answer(plain, request(algorithm));
        EXPECT_EQ(answer(prepared, request(algorithm)), a) << algorithm;
        const auto j = nlohmann::json::parse(a);
        ASSERT_EQ(j.at("candidates").size(), 3u) << algorithm;
        for (const auto& c : j.at("candidates")) {
            const auto id = c.at("rp_id").get<long long>();
            const auto& info = prepared.index.rp(static_cast<std::size_t>(id - 11));
            EXPECT_EQ(info.id, id);
            EXPECT_EQ(c.at("x").get<double>(), info.at.x);  // shortest form, read back exactly
            EXPECT_EQ(c.at("y").get<double>(), info.at.y);
            EXPECT_EQ(c.at("floor_id").get<long long>(), info.floor_id);
            EXPECT_EQ(c.at("matched_aps").get<int>(), 2);
        }
    }
}

TEST(LocalizeAnswer, NearestRpWithItsRoom) {
    Snapshot s = corridor();
    prepare_answers(s);
    const auto j = nlohmann::json::parse(answer(s, request("nn")));
    EXPECT_EQ(j.at("rps"), nlohmann::json::array({11}));
    EXPECT_EQ(j.at("x").get<double>(), 0.1);
    EXPECT_EQ(j.at("floor_id"), 7);
    EXPECT_EQ(j.at("room").at("name"), "Lab \"A\"");  // escaped on the way out, read back whole
    EXPECT_EQ(j.at("candidates").at(0).at("rp_id"), 11);
}

}  // namespace
}  // namespace localize_answer_test
