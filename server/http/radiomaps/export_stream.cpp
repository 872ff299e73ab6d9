#include "http/radiomaps/export_stream.hpp"

#include <stdexcept>
#include <string_view>
#include <utility>

#include "http/json_text.hpp"
#include "http/crud/store_json.hpp"

namespace locus::http {

ExportStream::ExportStream(std::unique_ptr<store::RadioMapReader> reader, std::size_t rps_per_piece)
    : reader_(std::move(reader)), rps_per_piece_(rps_per_piece) {
    // The document written once with no RP, cut where its RPs go: the framing (key order,
    // number and string spelling) is then nlohmann's own, as when the whole document was
    // written. No string value can hold the marker: its quotes would be escaped.
    const std::string whole = json_text(export_json_without_rps(reader_->radiomap(), reader_->transmitters()));
    constexpr std::string_view marker = "\"rps\":[]";
    const auto at = whole.find(marker);
    if (at == std::string::npos) throw std::logic_error("an export without its \"rps\" array");
    head_ = whole.substr(0, at + marker.size() - 1);
    tail_ = whole.substr(at + marker.size() - 1);
}

std::string ExportStream::next() {
    switch (part_) {
        case Part::head:
            part_ = Part::rps;
            return std::move(head_);
        case Part::rps: {
            const auto rps = reader_->next_rps(rps_per_piece_);
            if (rps.empty()) {
                reader_.reset();
                part_ = Part::done;
                return std::move(tail_);
            }
            std::string out;
            for (const auto& rp : rps) {
                if (!first_rp_) out += ',';
                first_rp_ = false;
                out += json_text(export_rp_json(rp));
            }
            return out;
        }
        case Part::done: break;
    }
    return {};
}

}  // namespace locus::http
