#pragma once
// What a thin client's filter run asks its caller for while it holds the track's filter
// (tracks/fusion_sessions.hpp): the floors' georeferences, for GNSS (docs/tracks.md, "GNSS and
// the phone's offset"). The HTTP layer's georeference cache implements it
// (tracks/thin_client.hpp). Plain declarations, no Eigen: service.hpp includes this.
#include <cstdint>
#include <memory>

namespace locus::geo {
class FloorToEarth;
}

namespace locus::tracks {

class RunSources {
public:
    virtual ~RunSources() = default;
    // The floor's georeference; null when it has none (its GNSS fixes are not used).
    virtual std::shared_ptr<const geo::FloorToEarth> georeference(std::int64_t floor_id) = 0;
};

}  // namespace locus::tracks
