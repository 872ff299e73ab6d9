#pragma once
// locus_datasets (datasets/): the data set and file readers, a library apart from the CLI so that
// tests, benchmarks and fuzz targets read a file exactly as the commands do.
//
// The survey upload file formats (docs/survey.md), parsed without any I/O:
//
// JSON lines (.jsonl, .json): one scan per line,
//   {"rp": "A1", "x": 1.5, "y": 2.0, "t": 1700000000123,
//    "readings": [{"type": "wifi", "bssid": "AA:BB:CC:DD:EE:01", "rss": -61}, ...]}
//   "rp" or both "x" and "y" are required ("x"/"y" alone name the RP "x<x>_y<y>");
//   "t" (ms) and "type" (default wifi) are optional. Blank lines and '#' lines are skipped.
//
// CSV (.csv): a header naming the columns, in any order, then one reading per line:
//   rp,x,y,t,type,bssid,rss
//   A1,1.5,2.0,1700000000123,wifi,aa:bb:cc:dd:ee:01,-61
//   "rp" or "x","y" as above; "t" is required (the readings of one scan share rp and t);
//   "type" is optional. Blank lines and '#' lines are skipped.
//
// Every cell must be UTF-8 (a line with a byte that is not is malformed: JSON cannot carry it).
// A malformed line is reported (line number and reason) and left out entirely; a CSV line
// that breaks a scan drops only that reading. Nothing half-parsed reaches the result.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "locus/geometry.hpp"
#include "locus/radio_map.hpp"

namespace locus::datasets::survey {

enum class Format { JsonLines, Csv };

// From the file name: .csv is CSV, everything else JSON lines.
Format format_of(std::string_view path);

struct LineError {
    std::size_t line = 0;  // 1-based
    std::string message;
};

struct SurveyRp {
    std::string name;
    std::optional<Point> at;
    std::vector<Scan> scans;  // in file order
};

struct SurveyFile {
    std::vector<SurveyRp> rps;  // in order of first appearance
    std::vector<LineError> errors;
    std::size_t scans = 0;
    std::size_t readings = 0;
};

SurveyFile parse(std::string_view text, Format format);

// Whether `s` is well-formed UTF-8 (no overlong forms, surrogates or code points past U+10FFFF).
bool valid_utf8(std::string_view s);

// The name given to an RP known only by its coordinates.
std::string name_for(Point at);

}  // namespace locus::datasets::survey
