#include "solver/io/vtk_xml.hpp"

#include <cstring>
#include <stdexcept>

#include "solver/io/output_files.hpp"

namespace talus {
namespace {

const char* type_name(VtkArray::Type type) {
  switch (type) {
    case VtkArray::Type::float64:
      return "Float64";
    case VtkArray::Type::int64:
      return "Int64";
    case VtkArray::Type::int32:
      return "Int32";
  }
  return "?";
}

std::size_t type_size(VtkArray::Type type) {
  return type == VtkArray::Type::int32 ? 4 : 8;
}

const char* byte_order() {
  const std::uint16_t probe = 1;
  unsigned char first = 0;
  std::memcpy(&first, &probe, 1);
  return first == 1 ? "LittleEndian" : "BigEndian";
}

// header_type="UInt64": the array's byte count, then its bytes, encoded together (uncompressed
// inline binary data).
std::string encoded(const std::string& bytes) {
  const std::uint64_t size = bytes.size();
  std::string header(sizeof size, '\0');
  std::memcpy(&header[0], &size, sizeof size);
  return base64(header + bytes);
}

std::string data_array(const VtkArray& array, const std::string& indent) {
  std::string text =
      indent + "<DataArray type=\"" + type_name(array.type()) + "\" Name=\"" + array.name() + "\"";
  if (array.components() != 1)
    text += " NumberOfComponents=\"" + std::to_string(array.components()) + "\"";
  return text + " format=\"binary\">" + encoded(array.bytes()) + "</DataArray>\n";
}

VtkArray int64_array(const std::string& name, const std::vector<std::int64_t>& values) {
  VtkArray array(name, VtkArray::Type::int64);
  for (const std::int64_t v : values) array.add(v);
  return array;
}

// A cell section (Verts, Polys): its connectivity and the end of each cell in it.
std::string cells(const char* section, const std::vector<std::int64_t>& connectivity,
                  const std::vector<std::int64_t>& ends) {
  if (ends.empty()) return "";
  const std::string indent = "        ";
  return std::string("      <") + section + ">\n" +
         data_array(int64_array("connectivity", connectivity), indent) +
         data_array(int64_array("offsets", ends), indent) + "      </" + section + ">\n";
}

std::string arrays(const char* section, const std::vector<VtkArray>& list, std::size_t count) {
  std::string text = std::string("      <") + section + ">\n";
  for (const VtkArray& array : list) {
    if (array.values() != count * std::size_t(array.components()))
      throw std::logic_error(std::string("vtp_text: ") + section + " array '" + array.name() +
                             "' holds " + std::to_string(array.values()) + " values for " +
                             std::to_string(count) + " items");
    text += data_array(array, "        ");
  }
  return text + "      </" + section + ">\n";
}

template <class T>
void append_value(std::string& bytes, T value) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  bytes.append(raw, sizeof(T));
}

}  // namespace

void VtkArray::add(double value) {
  if (type_ != Type::float64) throw std::logic_error("VtkArray '" + name_ + "': not Float64");
  append_value(bytes_, value);
}
void VtkArray::add(std::int64_t value) {
  if (type_ != Type::int64) throw std::logic_error("VtkArray '" + name_ + "': not Int64");
  append_value(bytes_, value);
}
void VtkArray::add(std::int32_t value) {
  if (type_ != Type::int32) throw std::logic_error("VtkArray '" + name_ + "': not Int32");
  append_value(bytes_, value);
}

std::size_t VtkArray::values() const {
  return bytes_.size() / type_size(type_);
}

void VtkPolyData::add_polygon(const std::vector<std::int64_t>& loop) {
  polygon_points.insert(polygon_points.end(), loop.begin(), loop.end());
  polygon_ends.push_back(static_cast<std::int64_t>(polygon_points.size()));
}

std::string vtp_text(const VtkPolyData& data) {
  const std::size_t points = data.point_count();
  const std::size_t cell_count = data.vertex_cells.size() + data.polygon_ends.size();
  std::vector<std::int64_t> vertex_ends;
  for (std::size_t i = 1; i <= data.vertex_cells.size(); ++i)
    vertex_ends.push_back(static_cast<std::int64_t>(i));
  std::string text = std::string("<?xml version=\"1.0\"?>\n") +
                     "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"" + byte_order() +
                     "\" header_type=\"UInt64\">\n  <PolyData>\n    <Piece NumberOfPoints=\"" +
                     std::to_string(points) + "\" NumberOfVerts=\"" +
                     std::to_string(data.vertex_cells.size()) +
                     "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"" +
                     std::to_string(data.polygon_ends.size()) + "\">\n";
  text += arrays("PointData", data.point_data, points);
  text += arrays("CellData", data.cell_data, cell_count);
  text += "      <Points>\n" + data_array(data.points, "        ") + "      </Points>\n";
  text += cells("Verts", data.vertex_cells, vertex_ends);
  text += cells("Polys", data.polygon_points, data.polygon_ends);
  return text + "    </Piece>\n  </PolyData>\n</VTKFile>\n";
}

std::string pvd_text(const std::vector<PvdEntry>& entries) {
  std::string text = std::string("<?xml version=\"1.0\"?>\n") +
                     "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"" + byte_order() +
                     "\">\n  <Collection>\n";
  for (const PvdEntry& e : entries)
    text += "    <DataSet timestep=\"" + exact_decimal(e.time) + "\" part=\"0\" file=\"" + e.file +
            "\"/>\n";
  return text + "  </Collection>\n</VTKFile>\n";
}

std::string base64(const std::string& bytes) {
  static const char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = bytes.size() - i < 3 ? bytes.size() - i : 3;
    std::uint32_t group = 0;
    for (std::size_t k = 0; k < 3; ++k)
      group = group << 8 | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? digits[(group >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

}  // namespace talus
