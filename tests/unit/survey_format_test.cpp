// The survey upload formats (datasets/survey_format.hpp): both read the same walk into the same
// RPs and scans, and every kind of malformed line is reported with its number and left out.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "datasets/survey_format.hpp"
#include "build_paths.hpp"

namespace survey_format_test {
namespace {

using namespace locus;
using namespace locus::datasets::survey;

std::string fixture(const std::string& name) {
    std::ifstream in(std::string(LOCUS_TEST_FIXTURES) + "/survey/" + name);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

const SurveyRp* find(const SurveyFile& f, const std::string& name) {
    for (const auto& rp : f.rps)
        if (rp.name == name) return &rp;
    return nullptr;
}

// The walk in tests/fixtures/survey: A (3 scans), B (2 scans), an unnamed point at (3, 4).
void expect_walk(const SurveyFile& f) {
    ASSERT_EQ(f.rps.size(), 3u);
    EXPECT_EQ(f.scans, 6u);
    EXPECT_EQ(f.readings, 9u);
    const SurveyRp* a = find(f, "A");
    ASSERT_NE(a, nullptr);
    ASSERT_TRUE(a->at.has_value());
    EXPECT_DOUBLE_EQ(a->at->x, 1.0);
    ASSERT_EQ(a->scans.size(), 3u);
    ASSERT_EQ(a->scans[0].size(), 2u);
    EXPECT_EQ(a->scans[0][0].bssid, "aa:bb:cc:00:00:01");  // upper case normalised
    EXPECT_EQ(a->scans[0][1].bssid, "aa:bb:cc:00:00:02");  // '-' separated normalised
    EXPECT_DOUBLE_EQ(a->scans[2][1].rss, -72.0);
    const SurveyRp* b = find(f, "B");
    ASSERT_NE(b, nullptr);
    EXPECT_EQ(b->scans.size(), 2u);
    const SurveyRp* p = find(f, "x3.00_y4.00");
    ASSERT_NE(p, nullptr);
    ASSERT_EQ(p->scans.size(), 1u);
    EXPECT_EQ(p->scans[0][0].type, "ble");
    EXPECT_EQ(p->scans[0][0].bssid, "beacon-1");
}

TEST(SurveyFormat, JsonLinesWalk) {
    const auto f = parse(fixture("walk.jsonl"), Format::JsonLines);
    EXPECT_TRUE(f.errors.empty()) << f.errors.front().line << ": " << f.errors.front().message;
    expect_walk(f);
}

TEST(SurveyFormat, CsvWalkReadsLikeJsonLines) {
    const auto f = parse(fixture("walk.csv"), Format::Csv);
    EXPECT_TRUE(f.errors.empty()) << f.errors.front().line << ": " << f.errors.front().message;
    expect_walk(f);
}

TEST(SurveyFormat, MalformedJsonLinesAreReportedAndLeftOut) {
    const auto f = parse(fixture("walk_malformed.jsonl"), Format::JsonLines);
    ASSERT_EQ(f.errors.size(), 3u);
    EXPECT_EQ(f.errors[0].line, 3u);  // rss +100 (the UJI "not heard" code)
    EXPECT_NE(f.errors[0].message.find("rss"), std::string::npos);
    EXPECT_EQ(f.errors[1].line, 5u);  // truncated JSON
    EXPECT_EQ(f.errors[2].line, 7u);  // B moved
    EXPECT_NE(f.errors[2].message.find("other coordinates"), std::string::npos);
    // Line 3 carried one good reading: it must not reach A half-parsed.
    expect_walk(f);
}

TEST(SurveyFormat, FormatFromFileName) {
    EXPECT_EQ(format_of("a/b/walk.csv"), Format::Csv);
    EXPECT_EQ(format_of("walk.jsonl"), Format::JsonLines);
    EXPECT_EQ(format_of("walk"), Format::JsonLines);
}

TEST(SurveyFormat, JsonLineErrors) {
    const std::string text =
        "[1,2]\n"                                                                 // 1 not an object
        "{\"rp\":\"A\",\"readings\":[]}\n"                                        // 2 empty readings
        "{\"x\":1,\"readings\":[{\"bssid\":\"a\",\"rss\":-50}]}\n"                 // 3 x without y
        "{\"rp\":\"A\",\"readings\":[{\"bssid\":\"a\",\"rss\":-50,\"snr\":3}]}\n"  // 4 unknown field
        "{\"rp\":\"A\",\"readings\":[{\"bssid\":\"a\",\"rss\":-50},{\"bssid\":\"A\",\"rss\":-51}]}\n"  // 5 twice
        "{\"rp\":\"A\",\"readings\":[{\"type\":\"lte\",\"bssid\":\"a\",\"rss\":-50}]}\n"               // 6 type
        "{\"rp\":\"A\",\"readings\":[{\"bssid\":\"a\",\"rss\":-121}]}\n"                              // 7 range
        "{\"readings\":[{\"bssid\":\"a\",\"rss\":-50}]}\n"                                             // 8 no place
        "{\"rp\":\"A\",\"readings\":[{\"bssid\":\"a\",\"rss\":-50}]}\n";                               // 9 good
    const auto f = parse(text, Format::JsonLines);
    ASSERT_EQ(f.errors.size(), 8u);
    for (std::size_t i = 0; i < 8; ++i) EXPECT_EQ(f.errors[i].line, i + 1);
    ASSERT_EQ(f.rps.size(), 1u);
    EXPECT_FALSE(f.rps[0].at.has_value());
    EXPECT_EQ(f.scans, 1u);
}

TEST(SurveyFormat, CsvErrorsAndColumnOrder) {
    const std::string text =
        "bssid,rss,t,rp\n"
        "a,-50,1,A\n"
        "b,-60,1,A\n"
        "a,-52,1,A\n"  // 4: a twice in the scan at t=1
        "a,x,2,A\n"    // 5: rss not a number
        "a,-50,2\n"    // 6: a cell short
        "a,-54,2,A\n";
    const auto f = parse(text, Format::Csv);
    ASSERT_EQ(f.errors.size(), 3u);
    EXPECT_EQ(f.errors[0].line, 4u);
    EXPECT_EQ(f.errors[1].line, 5u);
    EXPECT_EQ(f.errors[2].line, 6u);
    ASSERT_EQ(f.rps.size(), 1u);
    ASSERT_EQ(f.rps[0].scans.size(), 2u);
    EXPECT_EQ(f.rps[0].scans[0].size(), 2u);
    EXPECT_EQ(f.rps[0].scans[1].size(), 1u);
    EXPECT_DOUBLE_EQ(f.rps[0].scans[1][0].rss, -54.0);
}

TEST(SurveyFormat, CsvWithoutUsableHeaderReadsNothing) {
    const auto f = parse("rp,rss\nA,-50\n", Format::Csv);
    ASSERT_FALSE(f.errors.empty());
    EXPECT_EQ(f.errors[0].line, 1u);
    EXPECT_TRUE(f.rps.empty());
}

TEST(SurveyFormat, ACsvHeaderWithoutTheNeededColumnsStopsTheFile) {
    const auto f = parse("# comment\n\nrp,bssid,rss\nA,aa:bb:cc:00:00:01,-50\n", Format::Csv);
    ASSERT_EQ(f.errors.size(), 1u);  // the lines after it are not read, and not reported one by one
    EXPECT_EQ(f.errors[0].line, 3u);
    EXPECT_NE(f.errors[0].message.find("header needs"), std::string::npos);
    EXPECT_TRUE(f.rps.empty());
}

TEST(SurveyFormat, ACsvFileOfCommentsHasNoHeader) {
    const auto f = parse("# only\n# comments\n\n", Format::Csv);
    ASSERT_EQ(f.errors.size(), 1u);
    EXPECT_EQ(f.errors[0].line, 3u);  // the last line read
    EXPECT_EQ(f.errors[0].message, "no header line");
}

// Regression: a byte that is not UTF-8 in a CSV cell passed the parser, and the upload of
// the whole RP then failed in the JSON writer on every run. Such a line is malformed.
TEST(SurveyFormat, ACsvCellThatIsNotUtf8MakesItsLineMalformed) {
    const std::string text =
        "rp,x,y,t,type,bssid,rss\n"
        "A,1,1,1,wifi,aa:bb:cc:00:00:01,-50\n"
        "A,1,1,1,wifi,aa:bb:cc:00:00:\xff\xfe,-60\n"           // 3: bssid
        "B\xc3,2,2,1,wifi,aa:bb:cc:00:00:01,-50\n"             // 4: rp, a lead byte without its tail
        "C,3,3,1,wifi,aa:bb:cc:00:00:\xc0\xaf,-50\n"           // 5: an overlong '/'
        "D,4,4,1,wifi,aa:bb:cc:00:00:\xed\xa0\x80,-50\n"       // 6: a UTF-16 surrogate
        "E,5,5,1,w\xe9ifi,aa:bb:cc:00:00:01,-50\n"             // 7: Latin-1, not UTF-8
        "Caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x93\xa1,6,6,1,wifi,aa:bb:cc:00:00:01,-40\n";  // UTF-8: fine
    const auto f = parse(text, Format::Csv);
    ASSERT_EQ(f.errors.size(), 5u);
    for (std::size_t i = 0; i < 5; ++i) {
        EXPECT_EQ(f.errors[i].line, i + 3);
        EXPECT_NE(f.errors[i].message.find("not UTF-8"), std::string::npos) << f.errors[i].message;
    }
    EXPECT_NE(f.errors[0].message.find("'bssid'"), std::string::npos) << f.errors[0].message;
    EXPECT_NE(f.errors[1].message.find("'rp'"), std::string::npos) << f.errors[1].message;
    ASSERT_EQ(f.rps.size(), 2u);  // nothing of B, C, D, E
    EXPECT_EQ(f.rps[0].name, "A");
    ASSERT_EQ(f.rps[0].scans.size(), 1u);
    EXPECT_EQ(f.rps[0].scans[0].size(), 1u);
    EXPECT_EQ(f.rps[1].name, "Caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x93\xa1");
    EXPECT_EQ(f.readings, 2u);
}

TEST(SurveyFormat, AJsonLineThatIsNotUtf8IsMalformed) {
    const auto f = parse("{\"rp\":\"A\",\"readings\":[{\"bssid\":\"aa:bb:\xff\",\"rss\":-50}]}\n", Format::JsonLines);
    ASSERT_EQ(f.errors.size(), 1u);
    EXPECT_EQ(f.errors[0].line, 1u);
    EXPECT_TRUE(f.rps.empty());
}

}  // namespace
}  // namespace survey_format_test
