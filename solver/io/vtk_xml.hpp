// VTK's XML file formats, the subset ParaView needs from talus: PolyData (.vtp) pieces of points,
// vertex cells and polygons with named point and cell arrays, and the .pvd collection that makes
// a time series of them. Arrays are written inline as base64 "binary" (an UInt64 byte count, then
// the values in this machine's byte order, as the file's byte_order says), so every value reads
// back with the bits it was written with and a frame of a million particles stays a fraction of
// its ASCII size. Reference: "VTK File Formats", the XML section (VTK User's Guide).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace talus {

// One named array of `components` values per point or cell, its bytes in host order.
class VtkArray {
 public:
  enum class Type { float64, int64, int32 };
  VtkArray(std::string name, Type type, int components = 1)
      : name_(std::move(name)), type_(type), components_(components) {}

  // A value of the array's type (std::logic_error for another type: a bug in the caller).
  void add(double value);
  void add(std::int64_t value);
  void add(std::int32_t value);

  const std::string& name() const { return name_; }
  Type type() const { return type_; }
  int components() const { return components_; }
  const std::string& bytes() const { return bytes_; }
  std::size_t values() const;  // bytes / value size

 private:
  template <class T>
  void append(T value, Type expected);

  std::string name_;
  Type type_;
  int components_;
  std::string bytes_;
};

// Points, then cells: vertex cells (one point each, so that ParaView draws bare points) or
// polygons (a loop of point indices each), with arrays per point and per cell (cells ordered
// vertices first, then polygons, as VTK numbers them).
struct VtkPolyData {
  VtkArray points{"Points", VtkArray::Type::float64, 3};
  std::vector<std::int64_t> vertex_cells;    // point index of each vertex cell
  std::vector<std::int64_t> polygon_points;  // the polygons' loops, one after another
  std::vector<std::int64_t> polygon_ends;    // end of each loop in polygon_points
  std::vector<VtkArray> point_data, cell_data;

  std::size_t point_count() const { return points.values() / 3; }
  // Appends one polygon over the given point indices.
  void add_polygon(const std::vector<std::int64_t>& loop);
};

// The .vtp file's text. Throws std::logic_error when an array's length does not match its points
// or cells (a bug in the caller, not a user error).
std::string vtp_text(const VtkPolyData& data);

// One file of a .pvd time series.
struct PvdEntry {
  double time = 0;   // s
  std::string file;  // relative to the .pvd's directory
};

// A .pvd collection listing `entries` in order (times printed with 17 digits).
std::string pvd_text(const std::vector<PvdEntry>& entries);

// RFC 4648 base64 of `bytes`, padded with '='.
std::string base64(const std::string& bytes);

}  // namespace talus
