// Shared helpers of the overlap tests: templates with their flat arrays, a heap workspace, the
// production overlap in double or float, and comparisons against the long-double oracle.
#pragma once

#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "solver/geometry/overlap_polyhedra.hpp"
#include "solver/shape/builtins.hpp"
#include "solver/shape/shape_arrays.hpp"
#include "tests/support/oracle.hpp"

namespace talus::testing {

// A template with its double and float arrays, kept together so the views stay valid.
struct TestShape {
  ShapeTemplate shape;
  ShapeArrays<double> arrays_d;
  ShapeArrays<float> arrays_f;
  explicit TestShape(ShapeTemplate s) : shape(std::move(s)), arrays_d(shape), arrays_f(shape) {}
  explicit TestShape(const std::string& spec) : TestShape(make_builtin(spec)) {}
  ConvexView<double> view() const { return arrays_d.view(); }
  ConvexView<float> view_f() const { return arrays_f.view(); }
};

// The built-in specs the tests sweep; sizes differ so that pairs are not all of one scale.
inline std::vector<std::string> builtin_specs() {
  return {"tetrahedron:0.012",     "cube:0.01",         "cuboid:0.004,0.006,0.009",
          "octahedron:0.011",      "dodecahedron:0.01", "icosahedron:0.009",
          "cylinder:0.008,0.0053", "corn:0.01",         "mineral:0.01"};
}

// The template's view, and a pose, in precision Real.
template <class Real>
ConvexView<Real> view_of(const TestShape& s) {
  if constexpr (std::is_same_v<Real, float>)
    return s.view_f();
  else
    return s.view();
}
template <class Real>
Pose<Real> pose_of(const Posed& p) {
  return {Vec3<Real>(p.position), Quat<Real>(p.orientation)};
}

template <class Real>
OverlapResult<Real> overlap(const ConvexView<Real>& a, const Pose<Real>& pa,
                            const ConvexView<Real>& b, const Pose<Real>& pb,
                            OverlapOptions options = OverlapOptions()) {
  // 256 planes covers every pair the tests build; the heap keeps the stack small.
  static thread_local auto ws = std::make_unique<OverlapWorkspace<Real, 256>>();
  return overlap_polyhedra(a, pa, b, pb, *ws, options);
}

inline OverlapResult<double> overlap(const TestShape& a, const Posed& pa, const TestShape& b,
                                     const Posed& pb, OverlapOptions options = OverlapOptions()) {
  return overlap(a.view(), pa, b.view(), pb, options);
}

inline Pose<float> to_float(const Posed& p) {
  return {Vec3f(p.position), Quat<float>(p.orientation)};
}

inline OverlapResult<float> overlap_f(const TestShape& a, const Posed& pa, const TestShape& b,
                                      const Posed& pb) {
  return overlap(a.view_f(), to_float(pa), b.view_f(), to_float(pb));
}

inline OracleResult oracle(const TestShape& a, const Posed& pa, const TestShape& b,
                           const Posed& pb) {
  return oracle_overlap(a.shape, pa, b.shape, pb);
}

// The pose that puts a template's input frame at `offset` (world = input + offset): used to place
// shapes as they were written (axis-aligned cuboids) although templates live in the body frame.
inline Posed input_frame_pose(const ShapeTemplate& s, const Vec3d& offset,
                              const Quatd& extra = Quatd()) {
  return {offset + rotate(extra, s.input_centroid), extra * s.body_to_input};
}

inline Vec3d to_d(const Vec3l& v) {
  return Vec3d(v);
}

// The poured cylinders' wedge (experiments/beds: the paper's 20-sided prism at 10 mm): two of
// them end face on end face, a wedge 2.7e-9 m deep whose planes are 8e-7 rad apart, as the GPU
// step met them at t = 0.16 s. wedge_cylinder_b_gpu() is B as the GPU's message gave it;
// wedge_cylinder_b_retry() is B a few ulps away, where the first dual hull fails and the rounded
// retry computes the overlap (tests/geometry/test_overlap_hard_cases.cpp, test_surface_moment.cpp).
inline const char* wedge_cylinder_spec() {
  return "cylinder:0.00834,0.00552,20";
}
inline Posed wedge_cylinder_a() {
  return {Vec3d(0.0042624655412178058, 0.0046891993036728462, 0.11315625926417291),
          Quatd(-0.061074531028207008, -0.36125367221283361, 0.93020029923548297,
                -0.022205613584075658)};
}
inline Posed wedge_cylinder_b_gpu() {
  return {Vec3d(0.0047950557676911965, 0.0062712608040956849, 0.11853454497013875),
          Quatd(0.064985663825013695, 0.6541004543443335, -0.75361089412863547,
                0.00028173462257318719)};
}
inline Posed wedge_cylinder_b_retry() {
  return {Vec3d(0.0047950557676911948, 0.0062712608040956823, 0.11853454497013875),
          Quatd(0.064985663825014112, 0.65410045434433317, -0.7536108941286358,
                0.00028173462257349261)};
}

}  // namespace talus::testing
