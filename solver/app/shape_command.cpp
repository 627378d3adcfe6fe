// `talus shape`: a template as JSON, for checking what a spec or a mesh file turns into.
#include "solver/app/arguments.hpp"
#include "solver/app/commands.hpp"
#include "solver/app/json_writer.hpp"

namespace talus {

std::string shape_json(const std::string& spec) {
  const ShapeTemplate shape = load_shape_argument("A", spec);
  using Layout = JsonWriter::Layout;

  JsonWriter json;
  json.begin_object();
  json.member("spec", spec);
  json.member("name", shape.name);
  json.member("volume", shape.volume);
  json.member("bounding_radius", shape.bounding_radius);
  json.member("principal_moments", shape.principal_moments);  // per unit density, m^5
  json.member("input_centroid", shape.input_centroid);
  json.member("body_to_input", shape.body_to_input);  // [w, x, y, z]
  json.member("vertex_count", static_cast<int>(shape.vertices.size()));
  json.member("face_count", static_cast<int>(shape.faces.size()));
  json.member("triangle_count", static_cast<int>(shape.triangles.size()));
  json.member("edge_count", static_cast<int>(shape.edges.size()));
  json.key("vertices");
  json.begin_array(Layout::multi_line);
  for (const Vec3d& v : shape.vertices) json.value(v);
  json.end_array();
  json.key("faces");
  json.begin_array(Layout::multi_line);
  for (const Face& face : shape.faces) {
    json.begin_object(Layout::one_line);
    json.member("normal", face.normal);
    json.member("offset", face.offset);
    json.key("loop");
    json.begin_array();
    for (const int index : face.loop) json.value(index);
    json.end_array();
    json.end_object();
  }
  json.end_array();
  json.end_object();
  return json.str();
}

}  // namespace talus
