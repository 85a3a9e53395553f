// hipfai — reading a hip's joint angles from an OpenSim motion file (.mot, .sto). A line-by-line
// reader: the header up to `endheader`, the column labels, then one row per line.
#include "anatomy/opensim_motion.h"

#include "core/error.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string_view>

namespace hipfai::anatomy {

namespace {

constexpr std::string_view kBlanks = " \t\r\f\v";

// Angles beyond this (after any conversion) are refused: no hip coordinate goes past half a turn,
// and a file in radians labelled degrees (or the reverse) shows up here.
constexpr double kMaxAbsAngleDeg = 180.0;

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(kBlanks);
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(kBlanks);
  return s.substr(first, last - first + 1);
}

std::string lowercase(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// The text's lines, without their ends ("\n", "\r\n" or a lone "\r", as OpenSim accepts).
std::vector<std::string_view> split_lines(std::string_view text) {
  std::vector<std::string_view> lines;
  std::size_t start = 0;
  for (std::size_t k = 0; k < text.size(); ++k) {
    if (text[k] != '\n' && text[k] != '\r') continue;
    lines.push_back(text.substr(start, k - start));
    if (text[k] == '\r' && k + 1 < text.size() && text[k + 1] == '\n') ++k;
    start = k + 1;
  }
  if (start < text.size()) lines.push_back(text.substr(start));
  return lines;
}

std::vector<std::string_view> split_whitespace(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t k = 0;
  while (true) {
    k = line.find_first_not_of(kBlanks, k);
    if (k == std::string_view::npos) break;
    const auto end = std::min(line.find_first_of(kBlanks, k), line.size());
    fields.push_back(line.substr(k, end - k));
    k = end;
  }
  return fields;
}

// A number as OpenSim's stream extraction reads one (a leading '+' allowed); false if the whole
// field is not one.
bool parse_number(std::string_view field, double& value) {
  if (field.size() > 1 && field[0] == '+' && field[1] != '-' && field[1] != '+') field.remove_prefix(1);
  if (field.empty()) return false;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  return error == std::errc() && end == field.data() + field.size();
}

// A non-negative integer header value (version, row or column count).
bool parse_count(std::string_view field, long long& value) {
  field = trim(field);
  if (field.empty()) return false;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  return error == std::errc() && end == field.data() + field.size() && value >= 0;
}

bool ends_with(std::string_view s, std::string_view tail) {
  return s.size() >= tail.size() && s.substr(s.size() - tail.size()) == tail;
}

// Whether a column label names `coordinate`: the coordinate itself, or an OpenSim 4 state path
// ending in /<coordinate>/value.
bool names_coordinate(std::string_view label, const std::string& coordinate) {
  return label == coordinate || ends_with(label, "/" + coordinate + "/value");
}

struct Header {
  std::string name;
  std::optional<long long> version, rows, columns;
  std::optional<bool> in_degrees;
  std::size_t end_line = 0;  // index of the `endheader` line
};

Header parse_header(const std::vector<std::string_view>& lines, const std::string& file) {
  Header header;
  bool first_line = true;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const std::string_view line = trim(lines[k]);
    const auto where = [&] { return file + ":" + std::to_string(k + 1) + ": "; };
    if (line.empty()) continue;
    const auto delimiter = std::min(line.find_first_of(" \t="), line.size());
    const std::string_view key = line.substr(0, delimiter);
    const auto rest_start = line.find_first_not_of(" \t=", delimiter);
    const std::string_view rest = rest_start == std::string_view::npos ? std::string_view{} : line.substr(rest_start);
    if (key == "endheader") {
      header.end_line = k;
      return header;
    }
    long long count = 0;
    if (key == "name") {
      header.name = std::string(rest);
    } else if (key == "version") {
      if (!parse_count(rest, count)) throw_error(where(), "version: '", rest, "' is not a non-negative integer");
      header.version = count;
    } else if (key == "nRows" || key == "nr" || key == "datarows") {
      if (!parse_count(rest, count)) throw_error(where(), key, ": '", rest, "' is not a non-negative integer");
      header.rows = count;
    } else if (key == "nColumns" || key == "nc" || key == "datacolumns") {
      if (!parse_count(rest, count)) throw_error(where(), key, ": '", rest, "' is not a non-negative integer");
      header.columns = count;
    } else if (key == "inDegrees") {
      const std::string value = lowercase(rest);
      if (value == "yes" || value == "y") {
        header.in_degrees = true;
      } else if (value == "no" || value == "n") {
        header.in_degrees = false;
      } else {
        throw_error(where(), "inDegrees: '", rest, "' is not yes or no");
      }
    } else if (line == "Angles are in degrees.") {
      header.in_degrees = true;
    } else if (line == "Angles are in radians.") {
      header.in_degrees = false;
    } else if (first_line) {
      header.name = std::string(line);
    }
    first_line = false;
  }
  throw_error(file, ": no 'endheader' line (not an OpenSim motion or storage file)");
}

// Whether the angles are in degrees: the header's inDegrees, else degrees for a SIMM motion file.
bool motion_in_degrees(const Header& header, const std::string& file) {
  if (header.in_degrees) return *header.in_degrees;
  if (header.version.value_or(0) < 1 && ends_with(lowercase(file), ".mot")) {
    return true;  // a SIMM motion file: degrees, as OpenSim reads it
  }
  throw_error(file, ": no inDegrees=yes|no line: cannot tell degrees from radians");
}

struct ColumnLabels {
  std::size_t line = 0;  // index into the file's lines
  std::vector<std::string_view> labels;
};

// Column labels: the first non-blank line after endheader; tab-separated labels may hold spaces.
ColumnLabels read_column_labels(const std::vector<std::string_view>& lines, const Header& header,
                                const std::string& file) {
  std::size_t k = header.end_line + 1;
  while (k < lines.size() && trim(lines[k]).empty()) ++k;
  if (k >= lines.size()) throw_error(file, ":", header.end_line + 1, ": no column labels after endheader");
  ColumnLabels result;
  result.line = k;
  const std::size_t label_line = k;
  const std::string_view label_text = trim(lines[k]);
  std::vector<std::string_view>& labels = result.labels;
  if (label_text.find('\t') != std::string_view::npos) {
    std::size_t start = 0;
    while (true) {
      const auto tab = std::min(label_text.find('\t', start), label_text.size());
      labels.push_back(trim(label_text.substr(start, tab - start)));
      if (tab == label_text.size()) break;
      start = tab + 1;
    }
    for (std::size_t c = 0; c < labels.size(); ++c) {
      if (labels[c].empty()) throw_error(file, ":", label_line + 1, ": column ", c + 1, " has no label");
    }
  } else {
    labels = split_whitespace(label_text);
  }
  if (labels.front() != "time") {
    throw_error(file, ":", label_line + 1, ": the first column label is '", labels.front(), "', expected 'time'");
  }
  if (header.columns && *header.columns != static_cast<long long>(labels.size())) {
    throw_error(file, ":", label_line + 1, ": ", labels.size(), " column labels, but the header says nColumns=",
                *header.columns);
  }
  return result;
}

constexpr std::array<const char*, 3> kHipCoordinates{"hip_flexion", "hip_adduction", "hip_rotation"};

// The hip columns of one side (-1: absent); two columns holding one coordinate are an error.
std::array<long long, 3> find_hip_columns(const ColumnLabels& labels, Side s, const std::string& file) {
  std::array<long long, 3> columns{-1, -1, -1};
  for (std::size_t a = 0; a < 3; ++a) {
    const std::string coordinate = std::string(kHipCoordinates[a]) + (s == Side::kRight ? "_r" : "_l");
    for (std::size_t c = 1; c < labels.labels.size(); ++c) {
      if (!names_coordinate(labels.labels[c], coordinate)) continue;
      if (columns[a] >= 0) {
        throw_error(file, ":", labels.line + 1, ": columns ", columns[a] + 1, " and ", c + 1, " both hold ",
                    coordinate);
      }
      columns[a] = static_cast<long long>(c);
    }
  }
  return columns;
}

// The side read: the one asked for (all three columns required), else the only side complete.
Side choose_side(const ColumnLabels& labels, std::optional<Side> side, const std::string& file) {
  const std::size_t label_line = labels.line;
  if (side) {
    const auto columns = find_hip_columns(labels, *side, file);
    for (std::size_t a = 0; a < 3; ++a) {
      if (columns[a] < 0) {
        throw_error(file, ":", label_line + 1, ": no column ", kHipCoordinates[a], *side == Side::kRight ? "_r" : "_l",
                    " (the ", side_name(*side), " hip's angles)");
      }
    }
    return *side;
  }
  const auto complete = [](const std::array<long long, 3>& columns) {
    return std::all_of(columns.begin(), columns.end(), [](long long c) { return c >= 0; });
  };
  const bool right = complete(find_hip_columns(labels, Side::kRight, file));
  const bool left = complete(find_hip_columns(labels, Side::kLeft, file));
  if (right && left) {
    throw_error(file, ":", label_line + 1, ": both hips' angles are present: say which side to read");
  }
  if (!right && !left) {
    throw_error(file, ":", label_line + 1,
                ": no hip_flexion, hip_adduction and hip_rotation columns of either side (_r or _l)");
  }
  return right ? Side::kRight : Side::kLeft;
}

// The data rows after the labels: time increasing, the hip's three angles in degrees.
void read_motion_rows(const std::vector<std::string_view>& lines, const ColumnLabels& column_labels,
                      const std::array<long long, 3>& columns, bool in_degrees, const std::string& file,
                      JointAngleSeries& series) {
  const std::vector<std::string_view>& labels = column_labels.labels;
  const double to_degrees = in_degrees ? 1.0 : geometry::kRadToDeg;
  std::vector<double> values(labels.size());
  for (std::size_t k = column_labels.line + 1; k < lines.size(); ++k) {
    if (trim(lines[k]).empty()) continue;
    const std::size_t line_number = k + 1;
    const std::vector<std::string_view> fields = split_whitespace(lines[k]);
    if (fields.size() != labels.size()) {
      throw_error(file, ":", line_number, ": expected ", labels.size(), " values, found ", fields.size());
    }
    for (std::size_t c = 0; c < fields.size(); ++c) {
      if (!parse_number(fields[c], values[c])) {
        throw_error(file, ":", line_number, ": ", labels[c], ": '", fields[c], "' is not a number");
      }
    }
    const double time = values[0];
    if (!std::isfinite(time)) throw_error(file, ":", line_number, ": time: '", fields[0], "' is not finite");
    if (!series.time_s.empty() && !(time > series.time_s.back())) {
      throw_error(file, ":", line_number, ": time ", time, " s does not come after the previous row's ",
                  series.time_s.back(), " s");
    }
    std::array<double, 3> angles{};
    for (std::size_t a = 0; a < 3; ++a) {
      const auto c = static_cast<std::size_t>(columns[a]);
      if (!std::isfinite(values[c])) {
        throw_error(file, ":", line_number, ": ", labels[c], ": '", fields[c], "' is not finite");
      }
      angles[a] = values[c] * to_degrees;
      if (std::abs(angles[a]) > kMaxAbsAngleDeg) {
        throw_error(file, ":", line_number, ": ", labels[c], " = ", angles[a], " deg is beyond ", kMaxAbsAngleDeg,
                    " deg (the file says its angles are in ", in_degrees ? "degrees" : "radians", ")");
      }
    }
    series.time_s.push_back(time);
    series.poses.push_back({angles[0], angles[1], angles[2]});
  }
}

}  // namespace

JointAngleSeries read_opensim_motion(const std::filesystem::path& path, std::optional<Side> side) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw_error(path.string(), ": cannot open");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_opensim_motion(text.str(), path.string(), side);
}

JointAngleSeries parse_opensim_motion(const std::string& text, const std::string& name_for_messages,
                                      std::optional<Side> side) {
  const std::string& file = name_for_messages;
  const std::vector<std::string_view> lines = split_lines(text);
  const Header header = parse_header(lines, file);
  const bool in_degrees = motion_in_degrees(header, file);
  const ColumnLabels labels = read_column_labels(lines, header, file);
  const Side chosen = choose_side(labels, side, file);

  JointAngleSeries series;
  series.name = header.name;
  series.side = chosen;
  read_motion_rows(lines, labels, find_hip_columns(labels, chosen, file), in_degrees, file, series);
  if (series.poses.empty()) throw_error(file, ":", labels.line + 1, ": no data rows after the column labels");
  if (header.rows && *header.rows != static_cast<long long>(series.poses.size())) {
    throw_error(file, ": ", series.poses.size(), " data rows, but the header says nRows=", *header.rows);
  }
  return series;
}

}  // namespace hipfai::anatomy
