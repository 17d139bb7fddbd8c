// io/arkit_take.cpp: reading face-capture takes (io/arkit_take.h).
#include "io/arkit_take.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "core/file_util.h"
#include "io/arkit_map.h"
#include "io/formats.h"
#include "io/json_reader.h"

namespace mimetic {
namespace {

using namespace json_reader;

const Object kFrame = {"a take frame", {
    Number("time").Min(0).Required().About("seconds; strictly increasing"),
    AnyObject("blendshapes", "an object {\"ARKit name\": weight in [0, 1], ...}").Required()
        .About("ARKit blendshape name -> weight in [0, 1]; other names any number")}};

const Format kTakeFormat = {
    .name = "mimetic-arkit-take",
    .root = Array("", ObjectOf("", kFrame, "a frame {\"time\": ..., \"blendshapes\": {...}}"),
                  "an array of frames [{\"time\": s, \"blendshapes\": {...}}, ...]"),
    .title = "an ARKit face-capture take (JSON frames)"};

std::string Lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string Trim(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

// A whole cell as a finite number.
bool Number(const std::string& cell, double* out) {
  if (cell.empty()) return false;
  char* end = nullptr;
  const double v = std::strtod(cell.c_str(), &end);
  if (end != cell.c_str() + cell.size() || !std::isfinite(v)) return false;
  *out = v;
  return true;
}

// HH:MM:SS:FF[.fff] at fps -> seconds.
bool Timecode(const std::string& cell, double fps, double* out) {
  int part[4] = {0, 0, 0, 0};
  size_t i = 0;
  for (int k = 0; k < 4; ++k) {
    const size_t start = i;
    while (i < cell.size() && std::isdigit(static_cast<unsigned char>(cell[i])) && i - start < 6)
      part[k] = part[k] * 10 + (cell[i++] - '0');
    if (i == start) return false;
    if (k < 3) {
      if (i >= cell.size() || (cell[i] != ':' && cell[i] != ';')) return false;
      ++i;
    }
  }
  double fraction = 0.0;
  if (i < cell.size()) {
    if (cell[i] != '.') return false;
    const std::string rest = cell.substr(i);
    if (rest.size() < 2 || !Number("0" + rest, &fraction)) return false;
  }
  if (part[1] >= 60 || part[2] >= 60 || part[3] >= int(std::ceil(fps))) return false;
  *out = (part[0] * 60.0 + part[1]) * 60.0 + part[2] + (part[3] + fraction) / fps;
  return true;
}

std::vector<std::string> SplitRow(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  for (char c : line) {
    if (c == ',') cells.push_back(Trim(cell)), cell.clear();
    else cell += c;
  }
  cells.push_back(Trim(cell));
  return cells;
}

}  // namespace

const json_reader::Format& ArkitTakeFormat() { return kTakeFormat; }

bool IsArkitName(const std::string& name) {
  if (name.empty()) return false;
  std::string other = name;
  const unsigned char c = static_cast<unsigned char>(other[0]);
  other[0] = char(std::islower(c) ? std::toupper(c) : std::tolower(c));
  for (const char* n : ArkitShapeNames())
    if (name == n || other == n) return true;
  return false;
}

bool ParseArkitCsv(const std::string& text, const std::string& where, double fps,
                   ArkitTake* out, Diagnostics* diag) {
  const size_t errors_before = diag->ErrorCount();
  auto at = [&](size_t line, size_t column, const std::string& header) {
    return where + ":" + std::to_string(line) + ":" + std::to_string(column) +
           (header.empty() ? "" : " (" + header + ")");
  };
  // Lines (CRLF or LF); blank lines are skipped.
  std::vector<std::pair<size_t, std::string>> lines;
  {
    size_t start = 0, number = 1;
    while (start <= text.size()) {
      size_t end = text.find('\n', start);
      if (end == std::string::npos) end = text.size();
      std::string line = text.substr(start, end - start);
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (!Trim(line).empty()) lines.push_back({number, line});
      start = end + 1;
      ++number;
    }
  }
  if (lines.empty()) {
    diag->Error(where, "is empty; expected a header row (Timecode or Time, then ARKit "
                       "blendshape names) and one row per frame");
    return false;
  }
  const std::vector<std::string> header = SplitRow(lines[0].second);
  const size_t header_line = lines[0].first;
  int time_column = -1;
  bool timecode = false;
  std::vector<int> channel_columns;
  ArkitTake take;
  std::set<std::string> seen;
  for (size_t c = 0; c < header.size(); ++c) {
    const std::string h = Lower(header[c]);
    if (h == "timecode" || h == "time" || h == "seconds") {
      if (time_column >= 0) {
        diag->Error(at(header_line, c + 1, header[c]),
                    "a second time column; expected one Timecode, Time or Seconds column");
        continue;
      }
      time_column = int(c);
      timecode = h == "timecode";
    } else if (h == "blendshapecount") {
      continue;
    } else if (header[c].empty()) {
      diag->Error(at(header_line, c + 1, ""), "an empty column header; expected a name");
    } else if (!seen.insert(header[c]).second) {
      diag->Error(at(header_line, c + 1, header[c]), "the column is named twice");
    } else {
      channel_columns.push_back(int(c));
      take.names.push_back(header[c]);
    }
  }
  if (time_column < 0) {
    diag->Error(where + ":" + std::to_string(header_line),
                "the header has no time column; expected Timecode (HH:MM:SS:FF) or Time / "
                "Seconds (seconds)");
    return false;
  }
  std::vector<bool> is_arkit;
  for (const std::string& n : take.names) is_arkit.push_back(IsArkitName(n));
  double first = 0.0, previous = 0.0;
  for (size_t r = 1; r < lines.size(); ++r) {
    const size_t line = lines[r].first;
    const std::vector<std::string> cells = SplitRow(lines[r].second);
    if (cells.size() != header.size()) {
      diag->Error(where + ":" + std::to_string(line),
                  "has " + std::to_string(cells.size()) + " cells; expected " +
                      std::to_string(header.size()) + " (one per header column)");
      continue;
    }
    double t = 0.0;
    const std::string& tc = cells[size_t(time_column)];
    if (timecode ? !Timecode(tc, fps, &t) : !Number(tc, &t)) {
      diag->Error(at(line, size_t(time_column) + 1, header[size_t(time_column)]),
                  "\"" + tc + "\" is not " +
                      (timecode ? "a timecode HH:MM:SS:FF or HH:MM:SS:FF.fff (FF below the "
                                  "--fps " + FormatFloat(float(fps)) + ")"
                                : std::string("a number of seconds")));
      continue;
    }
    if (take.times.empty()) first = t;
    else if (!(t > previous)) {
      diag->Error(at(line, size_t(time_column) + 1, header[size_t(time_column)]),
                  "time " + tc + " is not after the previous row's; expected strictly "
                                 "increasing times");
      continue;
    }
    previous = t;
    std::vector<float> row(take.names.size(), 0.f);
    bool row_ok = true;
    for (size_t k = 0; k < channel_columns.size(); ++k) {
      const size_t c = size_t(channel_columns[k]);
      double v = 0.0;
      if (!Number(cells[c], &v)) {
        diag->Error(at(line, c + 1, header[c]), "\"" + cells[c] + "\" is not a number; expected " +
                        (is_arkit[k] ? "a blendshape weight in [0, 1]" : "a finite number"));
        row_ok = false;
      } else if (is_arkit[k] && !(v >= 0.0 && v <= 1.0)) {
        diag->Error(at(line, c + 1, header[c]),
                    cells[c] + " is outside [0, 1]; expected a blendshape weight in [0, 1]");
        row_ok = false;
      } else {
        row[k] = float(v);
      }
    }
    if (!row_ok) continue;
    take.times.push_back(float(t - first));
    take.weights.insert(take.weights.end(), row.begin(), row.end());
  }
  if (diag->ErrorCount() != errors_before) return false;
  if (take.times.empty()) {
    diag->Error(where, "has a header but no frame rows; expected one row per frame");
    return false;
  }
  *out = std::move(take);
  return true;
}

bool ParseArkitTakeJson(const std::string& text, const std::string& where, ArkitTake* out,
                        Diagnostics* diag) {
  return NoThrow(diag, where + ": internal error while reading the take", [&] {
    Reader r(kTakeFormat, diag, where);
    if (!r.Parse(text)) return false;
    r.Check();
    if (r.failed()) return false;
    const Json& root = r.root();
    if (root.empty()) {
      r.Error("", "is an empty array; expected at least one frame");
      return false;
    }
    ArkitTake take;
    std::map<std::string, size_t> column;
    for (const Json& frame : root)
      for (const auto& [name, value] : frame["blendshapes"].items())
        if (!column.count(name)) column.emplace(name, take.names.size()), take.names.push_back(name);
    double first = 0.0, previous = 0.0;
    for (size_t f = 0; f < root.size(); ++f) {
      const std::string path = Index("", f);
      const double t = root[f]["time"].get<double>();
      if (f > 0 && !(t > previous))
        r.Error(Key(path, "time"), "is " + FormatFloat(float(t)) + "; expected a time after the "
                                   "previous frame's " + FormatFloat(float(previous)));
      if (f == 0) first = t;
      previous = t;
      std::vector<float> row(take.names.size(), 0.f);
      for (const auto& [name, value] : root[f]["blendshapes"].items()) {
        const std::string vpath = Key(Key(path, "blendshapes"), name);
        const bool arkit = IsArkitName(name);
        if (!value.is_number() || !std::isfinite(value.get<double>())) {
          r.Expected(vpath, arkit ? "a blendshape weight in [0, 1]" : "a finite number", value);
          continue;
        }
        const double v = value.get<double>();
        if (arkit && !(v >= 0.0 && v <= 1.0)) {
          r.Expected(vpath, "a blendshape weight in [0, 1]", value);
          continue;
        }
        row[column[name]] = float(v);
      }
      take.times.push_back(float(t - first));
      take.weights.insert(take.weights.end(), row.begin(), row.end());
    }
    if (r.failed()) return false;
    *out = std::move(take);
    return true;
  });
}

bool LoadArkitTake(const std::string& path, double fps, ArkitTake* out, Diagnostics* diag) {
  std::string ext = Lower(path.size() >= 5 ? path.substr(path.size() - 5) : path);
  if (ext.ends_with(".csv")) {
    std::string text;
    if (!ReadFile(path, &text, diag, kMaxJsonFileBytes, "take file (CSV)")) return false;
    return ParseArkitCsv(text, path, fps, out, diag);
  }
  if (ext == ".json") {
    return ParseFile(path, diag, [&](const std::string& text, Diagnostics* local) {
      return ParseArkitTakeJson(text, "", out, local);
    });
  }
  diag->Error(path, "is neither a .csv nor a .json take; expected one of them");
  return false;
}

}  // namespace mimetic
