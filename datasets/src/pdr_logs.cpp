#include "datasets/pdr_logs.hpp"

#include <charconv>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

namespace locus::datasets {

namespace {

std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> out;
    std::string cell;
    std::istringstream in(line);
    while (std::getline(in, cell, ',')) {
        const auto b = cell.find_first_not_of(" \t\r");
        const auto e = cell.find_last_not_of(" \t\r");
        out.push_back(b == std::string::npos ? std::string() : cell.substr(b, e - b + 1));
    }
    return out;
}

double number(const std::string& s, const std::string& path, long line_no) {
    double v = 0.0;
    const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || p != s.data() + s.size())
        throw std::runtime_error(path + ":" + std::to_string(line_no) + ": not a number: '" + s + "'");
    return v;
}

std::ifstream open(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot open " + path);
    return in;
}

bool is_number(const std::string& s) {
    double v;
    const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    return ec == std::errc() && p == s.data() + s.size();
}

}  // namespace

std::vector<AccelSample> read_accel_log(const std::string& path) {
    auto in = open(path);
    std::vector<AccelSample> out;
    std::string line;
    long line_no = 0;
    int ct = -1, cx = -1, cy = -1, cz = -1;
    bool oxford = false, first = true;
    while (std::getline(in, line)) {
        ++line_no;
        if (line.empty() || line[0] == '#' || line.find_first_not_of(" \t\r") == std::string::npos) continue;
        const auto cells = split(line);
        if (first) {
            first = false;
            if (!cells.empty() && is_number(cells[0])) {
                if (cells.size() < 5) throw std::runtime_error(path + ": expected timestamp_ns,accuracy,ax,ay,az");
                oxford = true;
            } else {
                for (int i = 0; i < static_cast<int>(cells.size()); ++i) {
                    const auto& c = cells[static_cast<std::size_t>(i)];
                    if (c == "t" || c == "t_s") ct = i;
                    if (c == "ax") cx = i;
                    if (c == "ay") cy = i;
                    if (c == "az") cz = i;
                }
                if (ct < 0 || cx < 0 || cy < 0 || cz < 0)
                    throw std::runtime_error(path + ": header must name t, ax, ay, az");
                continue;
            }
        }
        if (oxford) {
            if (cells.size() < 5) throw std::runtime_error(path + ":" + std::to_string(line_no) + ": expected 5 fields");
            out.push_back({number(cells[0], path, line_no) * 1e-9, number(cells[2], path, line_no),
                           number(cells[3], path, line_no), number(cells[4], path, line_no)});
        } else {
            const int need = std::max(std::max(ct, cx), std::max(cy, cz));
            if (static_cast<int>(cells.size()) <= need)
                throw std::runtime_error(path + ":" + std::to_string(line_no) + ": too few fields");
            auto at = [&](int i) { return number(cells[static_cast<std::size_t>(i)], path, line_no); };
            out.push_back({at(ct), at(cx), at(cy), at(cz)});
        }
    }
    return out;
}

std::vector<ImuSample> read_imu_log(const std::string& path) {
    auto in = open(path);
    std::vector<ImuSample> out;
    std::string line;
    long line_no = 0;
    bool header = false;
    while (std::getline(in, line)) {
        ++line_no;
        if (line.empty() || line[0] == '#' || line.find_first_not_of(" \t\r") == std::string::npos) continue;
        const auto cells = split(line);
        if (!header) {
            if (cells.size() < 5 || cells[0] != "t" || cells[1] != "sensor")
                throw std::runtime_error(path + ": header must be t,sensor,x,y,z");
            header = true;
            continue;
        }
        if (cells.size() < 2) throw std::runtime_error(path + ":" + std::to_string(line_no) + ": too few fields");
        ImuSample s{number(cells[0], path, line_no), ImuSensor::acc, {}};
        const auto& k = cells[1];
        if (k == "acc") s.sensor = ImuSensor::acc;
        else if (k == "gyro") s.sensor = ImuSensor::gyro;
        else if (k == "mag") s.sensor = ImuSensor::mag;
        else if (k == "step") s.sensor = ImuSensor::step;
        else throw std::runtime_error(path + ":" + std::to_string(line_no) + ": unknown sensor '" + k + "'");
        if (s.sensor != ImuSensor::step) {
            if (cells.size() < 5) throw std::runtime_error(path + ":" + std::to_string(line_no) + ": expected x,y,z");
            s.v = {number(cells[2], path, line_no), number(cells[3], path, line_no), number(cells[4], path, line_no)};
        }
        out.push_back(s);
    }
    if (!header) throw std::runtime_error(path + ": empty log");
    return out;
}

FloorPlan read_floor_plan(const std::string& path, int building, int floor, double& north_offset_deg) {
    auto in = open(path);
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
        throw std::runtime_error(path + ": " + e.what());
    }
    try {
        if (j.contains("buildings")) j = j.at("buildings").at(static_cast<std::size_t>(building)).at("floors").at(static_cast<std::size_t>(floor));
        FloorPlan plan;
        plan.width = j.value("width", 0.0);
        plan.height = j.value("height", 0.0);
        north_offset_deg = j.value("north_offset_deg", 0.0);
        long long id = 0;
        for (const auto& r : j.value("rooms", nlohmann::json::array())) {
            Room room;
            room.id = r.value("id", ++id);
            room.name = r.value("name", "");
            for (const auto& q : r.at("rects")) {
                if (q.is_array())  // [xmin, ymin, xmax, ymax], as the simulator writes floors
                    room.rects.push_back({q.at(0).get<double>(), q.at(1).get<double>(), q.at(2).get<double>(),
                                          q.at(3).get<double>()});
                else
                    room.rects.push_back({q.at("xmin").get<double>(), q.at("ymin").get<double>(),
                                          q.at("xmax").get<double>(), q.at("ymax").get<double>()});
            }
            plan.rooms.push_back(std::move(room));
        }
        id = 0;
        for (const auto& p : j.value("pois", nlohmann::json::array()))
            plan.pois.push_back({p.value("id", ++id), p.value("name", ""), p.value("kind", ""),
                                 {p.at("x").get<double>(), p.at("y").get<double>()}});
        return plan;
    } catch (const nlohmann::json::exception& e) {
        throw std::runtime_error(path + ": not a floor description: " + e.what());
    }
}

}  // namespace locus::datasets
