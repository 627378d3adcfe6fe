#include "solver/io/trajectory.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "solver/io/input_files.hpp"
#include "solver/io/json.hpp"
#include "solver/io/output_files.hpp"

namespace talus {
namespace {

constexpr int kTrajectoryColumns = 15;

bool parse_integer(const std::string& text, long long& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtoll(text.c_str(), &end, 10);
  return end == text.c_str() + text.size();
}

const std::regex& frame_name_pattern() {
  static const std::regex pattern("trajectory_([0-9]+)\\.(csv|h5)");
  return pattern;
}

}  // namespace

std::string trajectory_file_name(long long step, TrajectoryFormat format) {
  return numbered_file_name("trajectory_", step, format == TrajectoryFormat::hdf5 ? ".h5" : ".csv");
}

std::string trajectory_file_name(long long step) {
  return trajectory_file_name(step, TrajectoryFormat::csv);
}

void write_trajectory_frame(const std::string& directory, long long step,
                            const std::vector<TrajectoryRow>& rows) {
  std::string text = std::string(kTrajectoryHeader) + "\n";
  text.reserve(rows.size() * 15 * 24);
  for (const TrajectoryRow& r : rows) {
    text += std::to_string(r.id) + "," + std::to_string(r.template_index);
    const double values[] = {r.position.x,        r.position.y,         r.position.z,
                             r.orientation.w,     r.orientation.x,      r.orientation.y,
                             r.orientation.z,     r.velocity.x,         r.velocity.y,
                             r.velocity.z,        r.angular_velocity.x, r.angular_velocity.y,
                             r.angular_velocity.z};
    for (const double v : values) text += "," + exact_decimal(v);
    text += "\n";
  }
  write_file_atomically(directory + "/" + trajectory_file_name(step), text);
}

TrajectoryFrame read_trajectory_frame(const std::string& path) {
  const std::string name = std::filesystem::path(path).filename().string();
  std::smatch match;
  if (!std::regex_match(name, match, frame_name_pattern()))
    throw std::runtime_error(path + ": expected a file named trajectory_<step>.csv or .h5");
  if (match[2].str() == "h5") return read_trajectory_frame_hdf5(path, std::stoll(match[1].str()));
  TrajectoryFrame frame;
  frame.step = std::stoll(match[1].str());
  std::istringstream in(read_input_file(path));
  std::string line;
  if (!std::getline(in, line) || line != kTrajectoryHeader) {
    // A header cut short: the file ends inside it.
    const bool cut =
        in.eof() && !line.empty() && std::string(kTrajectoryHeader).rfind(line, 0) == 0;
    throw std::runtime_error(path + ":1: expected the header '" + kTrajectoryHeader + "'" +
                             (cut ? ", but the file ends inside it (truncated)" : ""));
  }
  for (int line_number = 2; std::getline(in, line); ++line_number) {
    auto fail = [&](const std::string& what) {
      throw std::runtime_error(path + ":" + std::to_string(line_number) + ": expected " + what);
    };
    const std::vector<std::string> fields = split_csv_line(line);
    if (fields.size() != kTrajectoryColumns)
      fail(std::to_string(kTrajectoryColumns) + " comma-separated values, got " +
           std::to_string(fields.size()));
    TrajectoryRow row;
    long long template_index = 0;
    if (!parse_integer(fields[0], row.id)) fail("an integer id, got '" + fields[0] + "'");
    if (!parse_integer(fields[1], template_index) || template_index < 0)
      fail("a template id (non-negative integer), got '" + fields[1] + "'");
    row.template_index = int(template_index);
    double v[kTrajectoryColumns - 2];
    for (int k = 0; k < kTrajectoryColumns - 2; ++k)
      if (!parse_double(fields[k + 2], v[k])) fail("a number, got '" + fields[k + 2] + "'");
    row.position = {v[0], v[1], v[2]};
    row.orientation = {v[3], v[4], v[5], v[6]};
    row.velocity = {v[7], v[8], v[9]};
    row.angular_velocity = {v[10], v[11], v[12]};
    frame.rows.push_back(row);
  }
  return frame;
}

std::vector<TrajectoryFrame> read_trajectory(const std::string& directory) {
  std::error_code error;
  std::filesystem::directory_iterator it(directory, error);
  if (error)
    throw std::runtime_error("cannot read trajectory directory '" + directory +
                             "': " + error.message());
  std::vector<std::string> paths;
  for (const auto& entry : it) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && std::regex_match(name, frame_name_pattern()))
      paths.push_back(entry.path().string());
  }
  std::vector<TrajectoryFrame> frames;
  for (const std::string& path : paths) frames.push_back(read_trajectory_frame(path));
  std::sort(frames.begin(), frames.end(),
            [](const TrajectoryFrame& a, const TrajectoryFrame& b) { return a.step < b.step; });
  return frames;
}

RunInfo run_info(const Scene& scene, const std::string& solver) {
  RunInfo info;
  info.scene_file = scene.file;
  info.solver = solver;
  info.precision = to_string(scene.precision);
  info.time_step = scene.time_step;
  for (const ParticleTemplate& t : scene.templates) info.templates.push_back(t.name);
  return info;
}

void write_run_info(const std::string& directory, const RunInfo& info) {
  Json json;
  json["scene"] = info.scene_file;
  json["solver"] = info.solver;
  json["precision"] = info.precision;
  json["time_step"] = info.time_step;
  json["trajectory_format"] = info.trajectory_format;
  json["templates"] = Json::array();
  for (std::size_t i = 0; i < info.templates.size(); ++i)
    json["templates"].push_back({{"id", i}, {"name", info.templates[i]}});
  write_file_atomically(directory + "/run.json", json_text(json));
}

RunInfo read_run_info(const std::string& directory) {
  const std::string path = directory + "/run.json";
  std::string text;
  try {
    text = read_input_file(path);
  } catch (const InputFileError& e) {
    throw std::runtime_error(path + ": " + e.problem() +
                             " (expected the run.json that talus run writes beside its "
                             "trajectory frames)");
  }
  const Json json = parse_json(text, path);
  auto fail = [&](const std::string& what) {
    throw std::runtime_error(path + ": expected " + what);
  };
  if (!json.is_object()) fail("an object {\"scene\": ..., \"solver\": ..., ...}");
  const auto member = [&](const char* key, const char* expected) -> const Json& {
    const auto it = json.find(key);
    if (it == json.end()) fail(std::string(expected) + " \"" + key + "\" (missing)");
    return *it;
  };
  RunInfo info;
  const auto string_member = [&](const char* key, std::string& value) {
    const Json& v = member(key, "a string member");
    if (!v.is_string()) fail(std::string("a string member \"") + key + "\", got " + v.dump());
    value = v.get<std::string>();
  };
  string_member("scene", info.scene_file);
  string_member("solver", info.solver);
  string_member("precision", info.precision);
  const Json& time_step = member("time_step", "a positive number");
  if (!time_step.is_number() || !(time_step.get<double>() > 0))
    fail("a positive number \"time_step\" (s), got " + time_step.dump());
  info.time_step = time_step.get<double>();
  if (json.contains("trajectory_format")) {  // absent in run.json of talus before HDF5 frames
    const Json& format = json["trajectory_format"];
    if (!format.is_string() || (format != "csv" && format != "hdf5"))
      fail("\"trajectory_format\" \"csv\" or \"hdf5\", got " + format.dump());
    info.trajectory_format = format.get<std::string>();
  }
  const Json& templates = member("templates", "an array");
  if (!templates.is_array()) fail("an array \"templates\", got " + templates.dump());
  for (std::size_t i = 0; i < templates.size(); ++i) {
    const Json& t = templates[i];
    const std::string where = "templates[" + std::to_string(i) + "]";
    if (!t.is_object() || !t.contains("id") || !t.contains("name") || !t["name"].is_string())
      fail(where + " as {\"id\": " + std::to_string(i) + ", \"name\": \"...\"}, got " + t.dump());
    if (!t["id"].is_number_integer() || t["id"].get<long long>() != static_cast<long long>(i))
      fail(where + ".id = " + std::to_string(i) + " (a template's id is its index), got " +
           t["id"].dump());
    info.templates.push_back(t["name"].get<std::string>());
  }
  return info;
}

}  // namespace talus
