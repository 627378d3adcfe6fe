// `talus shape`: a template as JSON, for checking what a spec or a mesh file turns into.
#include "solver/app/arguments.hpp"
#include "solver/app/commands.hpp"
#include "solver/io/json.hpp"

namespace talus {

std::string shape_json(const std::string& spec) {
  const ShapeTemplate shape = load_shape_argument("A", spec);
  Json json;
  json["spec"] = spec;
  json["name"] = shape.name;
  json["volume"] = shape.volume;
  json["bounding_radius"] = shape.bounding_radius;
  json["principal_moments"] = shape.principal_moments;  // per unit density, m^5
  json["input_centroid"] = shape.input_centroid;
  json["body_to_input"] = shape.body_to_input;  // [w, x, y, z]
  json["vertex_count"] = shape.vertices.size();
  json["face_count"] = shape.faces.size();
  json["triangle_count"] = shape.triangles.size();
  json["edge_count"] = shape.edges.size();
  json["vertices"] = shape.vertices;
  json["faces"] = Json::array();
  for (const Face& face : shape.faces)
    json["faces"].push_back(
        {{"normal", face.normal}, {"offset", face.offset}, {"loop", face.loop}});
  return json_text(json);
}

}  // namespace talus
