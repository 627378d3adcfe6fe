#include "solver/io/probes.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

#include "solver/io/checkpoint.hpp"
#include "solver/io/input_files.hpp"
#include "solver/io/output_files.hpp"

namespace talus {

const std::vector<std::string>& energy_probe_columns() {
  static const std::vector<std::string> columns = {"kinetic_translational",
                                                   "kinetic_rotational",
                                                   "gravitational",
                                                   "elastic_normal",
                                                   "elastic_tangential",
                                                   "dissipated",
                                                   "wall_work",
                                                   "fed",
                                                   "removed",
                                                   "energy_balance"};
  return columns;
}

std::vector<std::string> probe_columns(const ProbeOutput& probes,
                                       const std::vector<WallSpec>& walls) {
  std::vector<std::string> columns;
  for (const Probe probe : probes.quantities) {
    if (probe == Probe::energy) {
      columns.insert(columns.end(), energy_probe_columns().begin(), energy_probe_columns().end());
      continue;
    }
    if (probe != Probe::wall_forces) {
      columns.push_back(to_string(probe));
      continue;
    }
    for (const WallSpec& wall : walls)
      for (const char* part : {"fx", "fy", "fz", "tx", "ty", "tz"})
        columns.push_back("wall_" + wall.name + "_" + part);
  }
  return columns;
}

ProbeWriter::ProbeWriter(const std::string& path, std::vector<std::string> columns)
    : path_(path), columns_(std::move(columns)), hash_(fnv1a64(nullptr, 0)) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (!parent.empty())
    create_output_directory(parent.string(), "directory of the probe file (outputs.probes.file)");
  file_ = std::fopen(path.c_str(), "wb");
  if (!file_)
    throw std::runtime_error("cannot write probe file '" + path + "': " + std::strerror(errno));
  std::string header = "time,step";
  for (const std::string& column : columns_) header += "," + column;
  header += "\n";
  if (std::fputs(header.c_str(), file_) < 0 || std::fflush(file_) != 0)
    throw std::runtime_error("cannot write probe file '" + path + "': " + std::strerror(errno));
  count(header);
}

ProbeWriter::ProbeWriter(const std::string& path, std::vector<std::string> columns,
                         const ProbeResume& resume)
    : path_(path), columns_(std::move(columns)), hash_(fnv1a64(nullptr, 0)) {
  // Each refusal is the checkpoint's: the file does not continue the run it saved.
  const std::string refused = (resume.checkpoint.empty() ? "" : resume.checkpoint + ": ") +
                              "cannot resume probe file '" + path + "': ";
  std::string text;
  try {
    text = read_input_file(path);
  } catch (const InputFileError& e) {
    throw CheckpointError(refused + "it " + e.problem() + "; the run wrote its rows up to step " +
                          std::to_string(resume.step) + " there");
  }
  const std::string at = " (the checkpoint of step " + std::to_string(resume.step) + " counts " +
                         std::to_string(resume.bytes) + " bytes of rows written by then)";
  if (resume.bytes >= 0 && static_cast<long long>(text.size()) < resume.bytes)
    throw CheckpointError(refused + "it holds " + std::to_string(text.size()) +
                          " bytes, so it ends before the checkpoint's step" + at +
                          "; it was cut or replaced since, and a resumed run would leave a gap");
  std::string header = "time,step";
  for (const std::string& column : columns_) header += "," + column;
  if (text.compare(0, header.size() + 1, header + "\n") != 0)
    throw CheckpointError(refused + "its header is not '" + header +
                          "', the one of the checkpoint's run");
  std::string kept;
  if (resume.bytes >= 0) {
    kept = text.substr(0, static_cast<std::size_t>(resume.bytes));
    if (fnv1a64(kept.data(), kept.size()) != resume.hash)
      throw CheckpointError(refused +
                            "its rows up to the checkpoint's step are not the ones the "
                            "checkpoint's run wrote" +
                            at + "; another run has written it since");
  } else {
    // Whole rows (a newline at the end) of steps up to the checkpoint's, in order.
    std::size_t begin = header.size() + 1;
    kept = text.substr(0, begin);
    for (std::size_t end; (end = text.find('\n', begin)) != std::string::npos; begin = end + 1) {
      const std::string line = text.substr(begin, end - begin);
      const std::vector<std::string> fields = split_csv_line(line);
      double step = 0;
      if (fields.size() < 2 || !parse_double(fields[1], step) || step > double(resume.step)) break;
      kept += line + "\n";
    }
  }
  if (kept.size() != text.size()) write_file_atomically(path, kept);
  file_ = std::fopen(path.c_str(), "ab");
  if (!file_)
    throw std::runtime_error("cannot write probe file '" + path + "': " + std::strerror(errno));
  count(kept);
}

ProbeWriter::~ProbeWriter() {
  if (file_) std::fclose(file_);
}

void ProbeWriter::count(const std::string& text) {
  bytes_ += static_cast<long long>(text.size());
  hash_ = fnv1a64(text.data(), text.size(), hash_);
}

void ProbeWriter::sync() {
  if (std::fflush(file_) != 0 || ::fsync(fileno(file_)) != 0)
    throw std::runtime_error("cannot write probe file '" + path_ + "': " + std::strerror(errno));
}

void ProbeWriter::write_row(double time, long long step, const std::vector<double>& values) {
  if (values.size() != columns_.size())
    throw std::invalid_argument("probe file '" + path_ + "': a row needs " +
                                std::to_string(columns_.size()) + " values, got " +
                                std::to_string(values.size()));
  std::string row = exact_decimal(time) + "," + std::to_string(step);
  for (const double v : values) row += "," + exact_decimal(v);
  row += "\n";
  // One write and a flush per row: what reached the file is whole rows, up to the last one.
  if (std::fwrite(row.data(), 1, row.size(), file_) != row.size() || std::fflush(file_) != 0)
    throw std::runtime_error("cannot write probe file '" + path_ + "': " + std::strerror(errno));
  count(row);
}

ProbeTable read_probe_file(const std::string& path) {
  std::istringstream in(read_input_file(path));
  ProbeTable table;
  std::string line;
  if (!std::getline(in, line) || line.rfind("time,step", 0) != 0)
    throw std::runtime_error(path + ":1: expected a header starting with 'time,step'");
  table.header = split_csv_line(line);
  for (int line_number = 2; std::getline(in, line); ++line_number) {
    const std::vector<std::string> fields = split_csv_line(line);
    const std::string where = path + ":" + std::to_string(line_number) + ": ";
    if (fields.size() != table.header.size())
      throw std::runtime_error(where + "expected " + std::to_string(table.header.size()) +
                               " values, got " + std::to_string(fields.size()));
    std::vector<double> row(fields.size());
    for (std::size_t k = 0; k < fields.size(); ++k)
      if (!parse_double(fields[k], row[k]))
        throw std::runtime_error(where + "expected a number, got '" + fields[k] + "'");
    table.rows.push_back(std::move(row));
  }
  return table;
}

}  // namespace talus
