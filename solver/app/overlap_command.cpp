// `talus overlap`: one pair of posed polyhedra through the three contact computations.
#include <memory>

#include "solver/app/arguments.hpp"
#include "solver/app/commands.hpp"
#include "solver/geometry/gjk.hpp"
#include "solver/geometry/overlap_polyhedra.hpp"
#include "solver/geometry/simple_contact.hpp"
#include "solver/io/json.hpp"
#include "solver/shape/shape_arrays.hpp"

namespace talus {

namespace {

constexpr int kLargestCapacity = 256;

// The workspace is large (tens of kB at 256 planes), hence on the heap.
template <int Capacity>
OverlapResult<double> overlap_with_capacity(const ConvexView<double>& a, const Posed& pose_a,
                                            const ConvexView<double>& b, const Posed& pose_b,
                                            OverlapOptions options) {
  auto workspace = std::make_unique<OverlapWorkspace<double, Capacity>>();
  return overlap_polyhedra(a, pose_a, b, pose_b, *workspace, options);
}

OverlapResult<double> overlap(const ConvexView<double>& a, const Posed& pose_a,
                              const ConvexView<double>& b, const Posed& pose_b,
                              OverlapOptions options = OverlapOptions()) {
  switch (overlap_capacity_for(a.n_faces + b.n_faces)) {
    case 32:
      return overlap_with_capacity<32>(a, pose_a, b, pose_b, options);
    case 64:
      return overlap_with_capacity<64>(a, pose_a, b, pose_b, options);
    case 128:
      return overlap_with_capacity<128>(a, pose_a, b, pose_b, options);
    default:
      return overlap_with_capacity<kLargestCapacity>(a, pose_a, b, pose_b, options);
  }
}

}  // namespace

std::string overlap_json(const std::string& spec_a, const std::string& pose_a_text,
                         const std::string& spec_b, const std::string& pose_b_text) {
  const ShapeTemplate template_a = load_shape_argument("A", spec_a);
  const Posed pose_a = parse_pose("POSE_A", pose_a_text);
  const ShapeTemplate template_b = load_shape_argument("B", spec_b);
  const Posed pose_b = parse_pose("POSE_B", pose_b_text);
  const int planes = static_cast<int>(template_a.faces.size() + template_b.faces.size());
  if (planes > kLargestCapacity) {
    throw UsageError("A '" + spec_a + "' and B '" + spec_b + "' have " + std::to_string(planes) +
                     " faces together; the overlap workspace holds at most " +
                     std::to_string(kLargestCapacity) + " (use coarser shapes)");
  }

  const ShapeArrays<double> arrays_a(template_a);
  const ShapeArrays<double> arrays_b(template_b);
  const ConvexView<double> a = arrays_a.view();
  const ConvexView<double> b = arrays_b.view();
  const OverlapResult<double> exact = overlap(a, pose_a, b, pose_b);
  // The inradius is the Chebyshev LP's value, which the vertex enumeration does not compute (its
  // depth_hint is a lower bound): the LP and the hull run again for it.
  double chebyshev_depth = exact.depth_hint;
  if (exact.enumerated) {
    OverlapOptions hull_only;
    hull_only.enumerate = false;
    chebyshev_depth = overlap(a, pose_a, b, pose_b, hull_only).depth_hint;
  }
  const SimpleContact<double> simple = polyhedron_polyhedron_contact(a, pose_a, b, pose_b);
  const GjkResult<double> gjk = gjk_intersect(a, pose_a, b, pose_b);

  // n = S/|S|, A_n = |S| (docs/design.md, "Contact laws"). No direction without an overlap, nor
  // when S is round-off: two coincident bodies have S = 0 exactly, and each face's share of S is
  // exact to ~eps times its area, at most ~(r_A + r_B)^2.
  const double area = norm(exact.vector_area);
  const double radius_sum = a.bounding_radius + b.bounding_radius;
  const double area_round_off = 64 * Eps<double>::value * radius_sum * radius_sum;
  const bool has_normal = exact.status == OverlapStatus::overlapping && area > area_round_off;
  const Vec3d normal = has_normal ? exact.vector_area / area : Vec3d();

  Json json;
  json["a"] = spec_a;
  json["b"] = spec_b;
  json["status"] = to_string(exact.status);
  json["volume"] = exact.volume;
  json["normal"] = normal;
  json["area"] = area;
  json["vector_area"] = exact.vector_area;
  json["point"] = exact.centroid;
  json["chebyshev_depth"] = chebyshev_depth;
  json["thin_slab"] = exact.thin_slab;
  json["hull_points"] = exact.hull_points;
  json["enumerated"] = exact.enumerated;
  json["workspace_overrun"] = exact.workspace_overrun;
  json["depth"] = simple.depth;
  json["simple_touching"] = simple.touching;
  json["simple_normal"] = simple.normal;
  json["simple_point"] = simple.point;
  json["gjk_intersecting"] = gjk.intersecting;
  return json_text(json);
}

}  // namespace talus
