#pragma once
// The web viewer's files, served read-only from two directories: the viewer itself (web/ of
// the repository, installed as share/locus/web) and Debian's Leaflet. Only plain file names
// under those roots are answered; a path that could leave a root is refused before any file
// is looked at.
#include <httplib.h>

#include <optional>
#include <string>

namespace locus::http {

struct StaticRoots {
    std::string web;      // the viewer; empty: not served
    std::string leaflet;  // Leaflet's dist files; empty: not served
};

// share/locus/web beside the running binary (bin/../share/locus/web), which is where both the
// install tree and the build tree (build/bin, build/share) keep it.
std::string default_web_root();
// Where Debian's libjs-leaflet puts Leaflet.
inline constexpr const char* default_leaflet_root = "/usr/share/javascript/leaflet";

// The Content-Type for a file name, or nothing when the viewer has no business serving it.
std::optional<std::string> content_type_of(const std::string& name);

// Adds GET / (the viewer's index.html), /web/... and /vendor/leaflet/....
void install_static_routes(httplib::Server& server, const StaticRoots& roots);

}  // namespace locus::http
