#include "locus/directory/index.hpp"

#include <algorithm>
#include <limits>
#include <unordered_map>

#include "locus/directory/text.hpp"

namespace locus::directory {

namespace {

constexpr std::uint32_t kNameSource = 0, kCategorySource = 1, kFirstTagSource = 2;
constexpr std::uint32_t kNoWord = std::numeric_limits<std::uint32_t>::max();
constexpr double kWholeNameBonus = 1.0, kWholeTagBonus = 0.5;

double field_weight(std::uint32_t source) {
    if (source == kNameSource) return 1.0;
    if (source == kCategorySource) return 0.6;
    return 0.8;
}

bool has_digit(std::u32string_view w) {
    return std::any_of(w.begin(), w.end(), [](char32_t c) { return c >= U'0' && c <= U'9'; });
}

// How well one query word matches one word of the index; 0 when it does not. Words with a
// digit are room numbers and the like: "3.22" is another room, not a typo of "3.21".
double match_value(std::u32string_view q, std::u32string_view w, bool typos) {
    if (q == w) return 1.0;
    if (w.starts_with(q)) return 0.5 + 0.4 * static_cast<double>(q.size()) / static_cast<double>(w.size());
    if (!typos) return 0.0;
    // Cheap length test first: most words of the index are too long or too short for an edit.
    if (w.size() + 1 >= q.size() && w.size() <= q.size() + 1 && within_one_edit(q, w, false)) return 0.4;
    if (q.size() >= kMinPrefixTypoLength && w.size() + 1 >= q.size() && within_one_edit(q, w, true)) return 0.3;
    return 0.0;
}

// One query word's matches: (word id, value), by word id.
struct QueryWord {
    std::vector<std::pair<std::uint32_t, double>> matches;
    std::uint32_t exact = kNoWord;  // the index's word equal to it, when there is one
    double value_of(std::uint32_t w) const {
        const auto it = std::lower_bound(matches.begin(), matches.end(), std::pair{w, 0.0},
                                         [](const auto& a, const auto& b) { return a.first < b.first; });
        return it != matches.end() && it->first == w ? it->second : 0.0;
    }
};

}  // namespace

Index::Index(const std::vector<Document>& documents) {
    std::unordered_map<std::u32string, std::uint32_t> ids;
    std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> posts;
    doc_begin_.reserve(documents.size() + 1);
    docs_.reserve(documents.size());
    const auto add = [&](std::uint32_t doc, std::uint32_t source, std::string_view text) {
        for (auto& w : words(text)) {
            auto [it, fresh] = ids.try_emplace(w, static_cast<std::uint32_t>(spans_.size()));
            if (fresh) {
                spans_.push_back({static_cast<std::uint32_t>(chars_.size()), static_cast<std::uint32_t>(w.size())});
                chars_ += w;
                posts.emplace_back();
            }
            occurrences_.push_back({it->second, source});
            auto& list = posts[it->second];
            // A word twice in one field is one posting.
            if (list.empty() || list.back() != std::pair{doc, source}) list.emplace_back(doc, source);
        }
    };
    for (std::size_t d = 0; d < documents.size(); ++d) {
        const auto doc = static_cast<std::uint32_t>(d);
        doc_begin_.push_back(static_cast<std::uint32_t>(occurrences_.size()));
        add(doc, kNameSource, documents[d].name);
        add(doc, kCategorySource, documents[d].category);
        for (std::size_t t = 0; t < documents[d].tags.size(); ++t)
            add(doc, kFirstTagSource + static_cast<std::uint32_t>(t), documents[d].tags[t]);
        std::string folded = fold(documents[d].name);
        const std::size_t length = code_points(folded);
        docs_.push_back({std::move(folded), length, static_cast<std::uint32_t>(documents[d].tags.size())});
    }
    doc_begin_.push_back(static_cast<std::uint32_t>(occurrences_.size()));
    post_begin_.reserve(posts.size() + 1);
    for (auto& list : posts) {
        post_begin_.push_back(static_cast<std::uint32_t>(postings_.size()));
        postings_.insert(postings_.end(), list.begin(), list.end());
    }
    post_begin_.push_back(static_cast<std::uint32_t>(postings_.size()));
}

std::vector<Hit> Index::search(std::string_view query, std::size_t limit) const {
    const auto qwords = words(query);
    if (qwords.empty() || limit == 0 || size() == 0) return {};

    std::vector<QueryWord> q(qwords.size());
    for (std::size_t i = 0; i < qwords.size(); ++i) {
        const bool typos = qwords[i].size() >= kMinTypoLength && !has_digit(qwords[i]);
        for (std::uint32_t w = 0; w < spans_.size(); ++w) {
            const double v = match_value(qwords[i], word(w), typos);
            if (v == 0.0) continue;
            q[i].matches.emplace_back(w, v);
            if (v == 1.0) q[i].exact = w;
        }
        if (q[i].matches.empty()) return {};  // every word must be found
    }

    // Each query word in turn: the best of its matches in every document that holds all the
    // words before it.
    const std::size_t n = size();
    std::vector<double> total(n, 0.0), best(n, 0.0);
    std::vector<std::uint32_t> found(n, 0), touched;
    for (std::uint32_t i = 0; i < q.size(); ++i) {
        touched.clear();
        for (const auto& [w, value] : q[i].matches)
            for (std::uint32_t p = post_begin_[w]; p < post_begin_[w + 1]; ++p) {
                const auto [doc, source] = postings_[p];
                if (found[doc] != i) continue;
                const double v = value * field_weight(source);
                if (best[doc] == 0.0) touched.push_back(doc);
                best[doc] = std::max(best[doc], v);
            }
        for (const auto doc : touched) {
            total[doc] += best[doc];
            best[doc] = 0.0;
            ++found[doc];
        }
    }

    // The query is a whole field when that field's words are exactly the query's, in order.
    const auto whole = [&](std::uint32_t doc, std::uint32_t source) {
        std::size_t k = 0;
        for (std::uint32_t o = doc_begin_[doc]; o < doc_begin_[doc + 1]; ++o) {
            if (occurrences_[o].source != source) continue;
            if (k == q.size() || occurrences_[o].word != q[k].exact) return false;
            ++k;
        }
        return k == q.size();
    };
    std::vector<Hit> hits;
    for (std::uint32_t doc = 0; doc < n; ++doc) {
        if (found[doc] != q.size()) continue;
        double score = total[doc] / static_cast<double>(q.size());
        if (whole(doc, kNameSource)) {
            score += kWholeNameBonus;
        } else {
            for (std::uint32_t s = kFirstTagSource; s < kFirstTagSource + docs_[doc].tags; ++s)
                if (whole(doc, s)) {
                    score += kWholeTagBonus;
                    break;
                }
        }
        hits.push_back({doc, score, Field::name, 0});
    }
    const auto better = [&](const Hit& a, const Hit& b) {
        if (a.score != b.score) return a.score > b.score;
        const auto &na = docs_[a.document], &nb = docs_[b.document];
        if (na.length != nb.length) return na.length < nb.length;
        if (na.folded != nb.folded) return na.folded < nb.folded;
        return a.document < b.document;
    };
    const std::size_t keep = std::min(limit, hits.size());
    std::partial_sort(hits.begin(), hits.begin() + static_cast<std::ptrdiff_t>(keep), hits.end(), better);
    hits.resize(keep);

    // Where each kept hit was found: each query word's best field, as ranked above.
    for (auto& hit : hits) {
        const auto doc = static_cast<std::uint32_t>(hit.document);
        for (const auto& word : q) {
            double top = 0.0;
            std::uint32_t where = kNameSource;
            for (std::uint32_t o = doc_begin_[doc]; o < doc_begin_[doc + 1]; ++o) {
                const double v = word.value_of(occurrences_[o].word) * field_weight(occurrences_[o].source);
                if (v > top) {
                    top = v;
                    where = occurrences_[o].source;
                }
            }
            if (where == kNameSource) continue;
            hit.matched = where == kCategorySource ? Field::category : Field::tag;
            if (where >= kFirstTagSource) hit.tag = where - kFirstTagSource;
            break;
        }
    }
    return hits;
}

}  // namespace locus::directory
