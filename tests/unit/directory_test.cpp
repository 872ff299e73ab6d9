// The directory's text folding, words, one-edit test and ranked search (locus::directory).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "locus/directory/index.hpp"
#include "locus/directory/text.hpp"

namespace directory_test {
namespace {

using namespace locus::directory;

std::vector<std::string> names_of(const std::vector<Document>& docs, const std::vector<Hit>& hits) {
    std::vector<std::string> out;
    for (const auto& h : hits) out.push_back(docs[h.document].name);
    return out;
}

std::vector<std::string> as_utf8(const std::vector<std::u32string>& ws) {
    std::vector<std::string> out;
    for (const auto& w : ws) {
        std::string s;
        for (const char32_t c : w) {
            EXPECT_LT(c, 0x80u) << "test words are ASCII after folding";
            s.push_back(static_cast<char>(c));
        }
        out.push_back(s);
    }
    return out;
}

const std::vector<Document>& building() {
    static const std::vector<Document> docs = {
        {"Café", "cafeteria", {}},                               // 0
        {"Room 3.21", "office", {"Dr. Rossi", "Anna Müller"}},   // 1
        {"Room 3.22", "office", {"José Núñez"}},                 // 2
        {"Meeting room Rossini", "", {}},                        // 3
        {"Toilets", "toilet", {}},                               // 4
        {"Reception", "", {"Information"}},                      // 5
        {"Müller Hall", "hall", {}},                             // 6
        {"Rossi", "", {}},                                       // 7
        {"Library", "", {"Books", "Reading room"}},              // 8
    };
    return docs;
}

std::vector<std::string> search(const std::string& q, std::size_t limit = 20) {
    static const Index index(building());
    return names_of(building(), index.search(q, limit));
}

TEST(DirectoryText, FoldsCaseAccentsAndCompatibilityForms) {
    EXPECT_EQ(fold("Café"), "cafe");
    EXPECT_EQ(fold("MÜLLER"), "muller");
    EXPECT_EQ(fold("Müller"), fold("Mu\xcc\x88ller"));  // precomposed and combining ü fold alike
    EXPECT_EQ(fold("Straße"), "strasse");
    EXPECT_EQ(fold("\xef\xac\x81le"), "file");  // the ﬁ ligature
    EXPECT_EQ(fold("Ñúñez"), "nunez");
    EXPECT_EQ(fold("ΣΟΦΊΑ"), fold("σοφια"));  // not only Latin
    EXPECT_EQ(fold("ab\xff\xfe" "cd"), "abcd");  // bytes that are not UTF-8 are dropped
}

TEST(DirectoryText, WordsSplitOnPunctuationButKeepRoomNumbersWhole) {
    EXPECT_EQ(as_utf8(words("Room 3.21")), (std::vector<std::string>{"room", "3.21"}));
    EXPECT_EQ(as_utf8(words("  Dr. Rossi,  Anna-Maria ")), (std::vector<std::string>{"dr", "rossi", "anna", "maria"}));
    EXPECT_EQ(as_utf8(words("B1.")), (std::vector<std::string>{"b1"}));
    EXPECT_EQ(as_utf8(words("1,5 m")), (std::vector<std::string>{"1,5", "m"}));
    EXPECT_TRUE(words("").empty());
    EXPECT_TRUE(words(" \t\n ").empty());
    EXPECT_TRUE(words("-- / !").empty());
}

TEST(DirectoryText, OneEditIsOneSubstitutionInsertionDeletionOrSwap) {
    EXPECT_TRUE(within_one_edit(U"cafeterja", U"cafeteria", false));   // substitution
    EXPECT_TRUE(within_one_edit(U"cafetria", U"cafeteria", false));    // a letter left out
    EXPECT_TRUE(within_one_edit(U"cafeteriaa", U"cafeteria", false));  // a letter too many
    EXPECT_TRUE(within_one_edit(U"cafeteira", U"cafeteria", false));   // neighbours swapped
    EXPECT_TRUE(within_one_edit(U"xafeteria", U"cafeteria", false));   // at the first letter
    EXPECT_TRUE(within_one_edit(U"cafeteri", U"cafeteria", false));    // at the last
    EXPECT_FALSE(within_one_edit(U"cafetrja", U"cafeteria", false));   // two edits
    EXPECT_FALSE(within_one_edit(U"cafe", U"cafeteria", false));       // a prefix is not a word
    EXPECT_TRUE(within_one_edit(U"cafw", U"cafeteria", true));         // unless a prefix is enough
    EXPECT_TRUE(within_one_edit(U"cfet", U"cafeteria", true));
    EXPECT_FALSE(within_one_edit(U"cxfw", U"cafeteria", true));
}

TEST(DirectorySearch, IgnoresAccentsAndCase) {
    EXPECT_EQ(search("cafe").front(), "Café");
    EXPECT_EQ(search("CAFÉ").front(), "Café");
    EXPECT_EQ(search("muller").front(), "Müller Hall");
    EXPECT_EQ(search("MÜLLER"), search("muller"));
    EXPECT_EQ(search("nunez"), (std::vector<std::string>{"Room 3.22"}));  // a tag with accents
}

TEST(DirectorySearch, FindsPrefixesAndOneTypoButNotTwo) {
    EXPECT_EQ(search("caf").front(), "Café");
    EXPECT_EQ(search("recep"), (std::vector<std::string>{"Reception"}));
    EXPECT_EQ(search("cafeterja"), (std::vector<std::string>{"Café"}));   // its category, one typo
    EXPECT_EQ(search("recpetion"), (std::vector<std::string>{"Reception"}));
    EXPECT_EQ(search("mulle").front(), "Müller Hall");
    EXPECT_EQ(search("mueller").size(), 2u);  // one letter too many: the hall and Anna's office
    EXPECT_TRUE(search("recpetoin").empty());  // two edits
    EXPECT_TRUE(search("cafetrja").empty());
}

TEST(DirectorySearch, ShortWordsAndNumbersGetNoTypos) {
    // Three letters have too many neighbours; "3.23" is another room, not a typo of 3.21.
    EXPECT_TRUE(search("cax").empty());
    EXPECT_EQ(search("caxe"), (std::vector<std::string>{"Café"}));
    EXPECT_TRUE(search("room 3.23").empty());
    EXPECT_EQ(search("room 3.2"), (std::vector<std::string>{"Room 3.21", "Room 3.22"}));
}

TEST(DirectorySearch, EveryWordMustBeFoundInNameOrTags) {
    EXPECT_EQ(search("room 3.21"), (std::vector<std::string>{"Room 3.21"}));
    EXPECT_EQ(search("dr rossi"), (std::vector<std::string>{"Room 3.21"}));
    EXPECT_EQ(search("rossi 3.21"), (std::vector<std::string>{"Room 3.21"}));  // a tag and the name
    EXPECT_TRUE(search("rossi toilet").empty());
}

TEST(DirectorySearch, RanksWholeNameThenNameThenTagThenPrefixThenTypo) {
    // "Rossi" is a whole name; "Dr. Rossi" a tag; "Rossini" only a prefix.
    EXPECT_EQ(search("rossi"), (std::vector<std::string>{"Rossi", "Room 3.21", "Meeting room Rossini"}));
    // A word of the name before the same word in a tag.
    EXPECT_EQ(search("room"), (std::vector<std::string>{"Room 3.21", "Room 3.22", "Meeting room Rossini", "Library"}));
    // Exact and whole, exact, a typo, a typo in a word still being typed.
    const std::vector<Document> docs = {{"Librarian", "", {}}, {"Library annex", "", {}}, {"Librxry", "", {}}, {"Library", "", {}}};
    const Index index(docs);
    const auto hits = index.search("library", 10);
    EXPECT_EQ(names_of(docs, hits), (std::vector<std::string>{"Library", "Library annex", "Librxry", "Librarian"}));
    for (std::size_t i = 1; i < hits.size(); ++i) EXPECT_GT(hits[i - 1].score, hits[i].score);
    // Of two prefixes, the word more of which was typed.
    EXPECT_EQ(names_of(docs, index.search("libr", 10)),
              (std::vector<std::string>{"Library", "Librxry", "Library annex", "Librarian"}));
}

TEST(DirectorySearch, TiesGoToTheShorterNameThenTheName) {
    const std::vector<Document> docs = {{"Lab Zed", "", {}}, {"Lab Abe", "", {}}, {"Lab B", "", {}}, {"Lab Abe", "", {}}};
    const Index index(docs);
    const auto hits = index.search("lab", 10);
    ASSERT_EQ(hits.size(), 4u);
    EXPECT_EQ(hits[0].document, 2u);
    EXPECT_EQ(hits[1].document, 1u);  // the first of two equal names
    EXPECT_EQ(hits[2].document, 3u);
    EXPECT_EQ(hits[3].document, 0u);
}

TEST(DirectorySearch, SaysWhereTheQueryWasFound) {
    const Index index(building());
    auto hits = index.search("anna muller", 10);
    ASSERT_EQ(hits.size(), 1u);
    EXPECT_EQ(hits[0].document, 1u);
    EXPECT_EQ(hits[0].matched, Field::tag);
    EXPECT_EQ(hits[0].tag, 1u);
    hits = index.search("toilet", 10);
    ASSERT_EQ(hits.size(), 1u);
    EXPECT_EQ(hits[0].matched, Field::name);  // "toilets" in the name beats "toilet" the category
    hits = index.search("cafeteria", 10);
    ASSERT_EQ(hits.size(), 1u);
    EXPECT_EQ(hits[0].matched, Field::category);
    hits = index.search("room 3.21", 10);
    ASSERT_EQ(hits.size(), 1u);
    EXPECT_EQ(hits[0].matched, Field::name);
}

TEST(DirectorySearch, KeepsTheLimit) {
    EXPECT_EQ(search("room", 2), (std::vector<std::string>{"Room 3.21", "Room 3.22"}));
    EXPECT_TRUE(search("room", 0).empty());
}

TEST(DirectorySearch, AQueryWithoutWordsFindsNothing) {
    EXPECT_TRUE(search("").empty());
    EXPECT_TRUE(search("   ").empty());
    EXPECT_TRUE(search(".,;!").empty());
    EXPECT_TRUE(Index().search("room", 10).empty());
}

}  // namespace
}  // namespace directory_test
