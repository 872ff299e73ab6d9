#include "sim/walk_io.hpp"

#include <fstream>
#include <istream>
#include <nlohmann/json.hpp>
#include <ostream>
#include <stdexcept>

namespace locus::sim {

namespace {

using nlohmann::json;

json vec(const pdr::Vec3& v) { return json::array({v.x, v.y, v.z}); }
pdr::Vec3 vec3(const json& j) { return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()}; }
json point(Point p) { return json::array({p.x, p.y}); }
Point point_of(const json& j) { return {j.at(0).get<double>(), j.at(1).get<double>()}; }

json scan_json(const Scan& s) {
    json o = json::object();
    for (const Reading& r : s) o[r.bssid] = r.rss;
    return o;
}

Scan scan_of(const json& o) {
    Scan s;
    for (const auto& [bssid, rss] : o.items()) s.push_back({"wifi", bssid, rss.get<double>()});
    return s;
}

json floor_json(const fusion::Walkable& w) {
    json rooms = json::array();
    for (const Room& r : w.plan.rooms) {
        json rects = json::array();
        for (const Rect& q : r.rects) rects.push_back({q.xmin, q.ymin, q.xmax, q.ymax});
        rooms.push_back({{"id", r.id}, {"name", r.name}, {"rects", rects}});
    }
    json doors = json::array();
    for (const Segment& d : w.doors) doors.push_back({d.a.x, d.a.y, d.b.x, d.b.y});
    return {{"width", w.plan.width}, {"height", w.plan.height}, {"rooms", rooms}, {"doors", doors},
            {"walls_between_rooms", w.walls_between_rooms}};
}

fusion::Walkable floor_of(const json& j) {
    fusion::Walkable w;
    w.plan.width = j.value("width", 0.0);
    w.plan.height = j.value("height", 0.0);
    for (const json& r : j.at("rooms")) {
        Room room;
        room.id = r.value("id", 0LL);
        room.name = r.value("name", "");
        for (const json& q : r.at("rects")) room.rects.push_back({q.at(0), q.at(1), q.at(2), q.at(3)});
        w.plan.rooms.push_back(std::move(room));
    }
    for (const json& d : j.value("doors", json::array())) w.doors.push_back({{d.at(0), d.at(1)}, {d.at(2), d.at(3)}});
    w.walls_between_rooms = j.value("walls_between_rooms", !w.doors.empty());
    return w;
}

}  // namespace

void write_walk(std::ostream& out, const Walk& walk) {
    json header = {{"type", "header"},
                   {"format", "locus-walk"},
                   {"version", 1},
                   {"scenario", walk.scenario},
                   {"seed", walk.seed},
                   {"rate_hz", walk.rate_hz},
                   {"start", point(walk.start)},
                   {"start_heading_rad", walk.start_heading_rad},
                   {"north_offset_deg", walk.north_offset_deg}};
    if (walk.map) header["floor"] = floor_json(*walk.map);
    if (walk.earth_field_ut) header["earth_field_ut"] = *walk.earth_field_ut;
    if (!walk.anchors.empty()) {
        json anchors = json::array();
        for (const Anchor& a : walk.anchors)
            anchors.push_back({{"type", a.type}, {"id", a.id}, {"x", a.tx.at.x}, {"y", a.tx.at.y}, {"dz", a.tx.dz},
                               {"tx_power", a.tx.model.tx_power}, {"path_loss_exponent", a.tx.model.exponent}});
        header["anchors"] = anchors;
    }
    out << header.dump() << '\n';
    for (const SurveyPoint& sp : walk.survey) {
        json scans = json::array();
        for (const Scan& s : sp.scans) scans.push_back(scan_json(s));
        out << json{{"type", "survey"}, {"rp", sp.name}, {"x", sp.at.x}, {"y", sp.at.y}, {"scans", scans}}.dump() << '\n';
    }
    // IMU and scans interleaved in time order, as a phone would log them.
    std::size_t j = 0, b = 0;
    auto flush_scans = [&](double until) {
        for (; j < walk.scans.size() && walk.scans[j].t_s <= until; ++j) {
            json o = {{"type", "wifi"}, {"t", walk.scans[j].t_s}, {"rss", scan_json(walk.scans[j].readings)}};
            if (walk.scans[j].truth) o["truth"] = point(*walk.scans[j].truth);
            out << o.dump() << '\n';
        }
        for (; b < walk.anchor_scans.size() && walk.anchor_scans[b].t_s <= until; ++b) {
            const WifiScan& s = walk.anchor_scans[b];
            json o = {{"type", "anchors"}, {"t", s.t_s}, {"rss", scan_json(s.readings)}};
            if (s.truth) o["truth"] = point(*s.truth);
            out << o.dump() << '\n';
        }
    };
    for (const ImuSample& s : walk.imu) {
        flush_scans(s.t_s);
        json o = {{"type", "imu"}, {"t", s.t_s}, {"acc", vec(s.acc)}, {"gyro", vec(s.gyro)}, {"mag", vec(s.mag)}};
        if (s.truth) o["truth"] = point(*s.truth);
        out << o.dump() << '\n';
    }
    flush_scans(1e300);
}

Walk read_walk(std::istream& in) {
    Walk walk;
    std::string line;
    long number = 0;
    bool header = false;
    while (std::getline(in, line)) {
        ++number;
        if (line.empty()) continue;
        try {
            const json o = json::parse(line);
            const std::string type = o.at("type").get<std::string>();
            if (type == "header") {
                if (o.value("format", "") != "locus-walk") throw std::runtime_error("not a locus-walk file");
                walk.scenario = o.value("scenario", "");
                walk.seed = o.value("seed", std::uint64_t{0});
                walk.rate_hz = o.value("rate_hz", 50.0);
                if (o.contains("start")) walk.start = point_of(o.at("start"));
                walk.start_heading_rad = o.value("start_heading_rad", 0.0);
                walk.north_offset_deg = o.value("north_offset_deg", 0.0);
                if (o.contains("floor")) walk.map = floor_of(o.at("floor"));
                if (o.contains("earth_field_ut")) walk.earth_field_ut = o.at("earth_field_ut").get<double>();
                for (const json& a : o.value("anchors", json::array()))
                    walk.anchors.push_back({a.at("type").get<std::string>(), a.at("id").get<std::string>(),
                                            {{a.at("x").get<double>(), a.at("y").get<double>()}, a.value("dz", 0.0),
                                             {a.at("tx_power").get<double>(), a.value("path_loss_exponent", 2.0)}}});
                header = true;
            } else if (!header) {
                throw std::runtime_error("the first line must be the header");
            } else if (type == "survey") {
                SurveyPoint sp{o.at("rp").get<std::string>(), {o.at("x").get<double>(), o.at("y").get<double>()}, {}};
                for (const json& s : o.at("scans")) sp.scans.push_back(scan_of(s));
                walk.survey.push_back(std::move(sp));
            } else if (type == "imu") {
                ImuSample s;
                s.t_s = o.at("t").get<double>();
                s.acc = vec3(o.at("acc"));
                s.gyro = vec3(o.at("gyro"));
                s.mag = vec3(o.at("mag"));
                if (o.contains("truth")) s.truth = point_of(o.at("truth"));
                walk.imu.push_back(s);
            } else if (type == "wifi" || type == "anchors") {
                WifiScan s;
                s.t_s = o.at("t").get<double>();
                s.readings = scan_of(o.at("rss"));
                if (o.contains("truth")) s.truth = point_of(o.at("truth"));
                (type == "wifi" ? walk.scans : walk.anchor_scans).push_back(std::move(s));
            }
        } catch (const std::exception& e) {
            throw std::runtime_error("walk file line " + std::to_string(number) + ": " + e.what());
        }
    }
    if (!header) throw std::runtime_error("walk file has no header line");
    return walk;
}

void save_walk(const std::string& path, const Walk& walk) {
    std::ofstream out(path);
    if (!out) throw std::runtime_error("cannot write " + path);
    out.precision(17);
    write_walk(out, walk);
    if (!out) throw std::runtime_error("error writing " + path);
}

Walk load_walk(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read " + path);
    return read_walk(in);
}

}  // namespace locus::sim
