// Unit quaternions (w, x, y, z) for orientation: body frame -> world frame.
#pragma once

#include <cmath>

#include "solver/core/vec3.hpp"

namespace talus {

template <class Real>
struct Quat {
  Real w, x, y, z;

  TALUS_HD Quat() : w(1), x(0), y(0), z(0) {}
  TALUS_HD Quat(Real w_, Real x_, Real y_, Real z_) : w(w_), x(x_), y(y_), z(z_) {}
  template <class Other>
  TALUS_HD explicit Quat(const Quat<Other>& o)
      : w(Real(o.w)), x(Real(o.x)), y(Real(o.y)), z(Real(o.z)) {}

  TALUS_HD Quat operator*(const Quat& q) const {
    return {w * q.w - x * q.x - y * q.y - z * q.z, w * q.x + x * q.w + y * q.z - z * q.y,
            w * q.y - x * q.z + y * q.w + z * q.x, w * q.z + x * q.y - y * q.x + z * q.w};
  }
  TALUS_HD Quat conjugate() const { return {w, -x, -y, -z}; }
  TALUS_HD Real norm() const { return std::sqrt(w * w + x * x + y * y + z * z); }
  TALUS_HD Quat normalized() const {
    const Real inv = Real(1) / norm();
    return {w * inv, x * inv, y * inv, z * inv};
  }

  // Rotation about a unit axis by an angle in radians.
  TALUS_HD static Quat from_axis_angle(const Vec3<Real>& unit_axis, Real angle) {
    const Real s = std::sin(angle / 2);
    return {std::cos(angle / 2), unit_axis.x * s, unit_axis.y * s, unit_axis.z * s};
  }
};

template <class Real>
TALUS_HD inline bool is_finite(const Quat<Real>& q) {
  return is_finite(q.w) && is_finite(q.x) && is_finite(q.y) && is_finite(q.z);
}

// Rotate v by the unit quaternion q: q v q*, written out (Rodrigues form, 2 cross products).
template <class Real>
TALUS_HD inline Vec3<Real> rotate(const Quat<Real>& q, const Vec3<Real>& v) {
  const Vec3<Real> u{q.x, q.y, q.z};
  const Vec3<Real> t = cross(u, v) * Real(2);
  return v + t * q.w + cross(u, t);
}

// Inverse rotation (world -> body) by the unit quaternion q.
template <class Real>
TALUS_HD inline Vec3<Real> rotate_inverse(const Quat<Real>& q, const Vec3<Real>& v) {
  return rotate(q.conjugate(), v);
}

// Row-major 3x3 rotation matrix of a unit quaternion.
template <class Real>
struct Mat3 {
  Real m[3][3];
  TALUS_HD Vec3<Real> operator*(const Vec3<Real>& v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
            m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }
  // Transpose times v (inverse of a rotation).
  TALUS_HD Vec3<Real> transpose_times(const Vec3<Real>& v) const {
    return {m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z,
            m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z,
            m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z};
  }
};

// a * b rounded on its own. A GPU compiler may fuse a product into the sum it feeds (one rounding
// instead of two), and whether it does for a product with several uses depends on the code
// around it: the same quaternion could then give two kernels rotations that differ in the last
// bit. Rounded products leave nothing to fuse (a product by 2 is exact, fused or not). The host
// compiler fuses nothing without FMA instructions, so the host gives the same rotation.
template <class Real>
TALUS_HD inline Real rounded_product(Real a, Real b) {
#ifdef __CUDA_ARCH__
  if constexpr (sizeof(Real) == sizeof(float))
    return __fmul_rn(a, b);
  else
    return __dmul_rn(a, b);
#else
  return a * b;
#endif
}

template <class Real>
TALUS_HD inline Mat3<Real> rotation_matrix(const Quat<Real>& q) {
  const Real w = q.w, x = q.x, y = q.y, z = q.z;
  const Real xx = rounded_product(x, x), yy = rounded_product(y, y), zz = rounded_product(z, z);
  const Real xy = rounded_product(x, y), xz = rounded_product(x, z), yz = rounded_product(y, z);
  const Real wx = rounded_product(w, x), wy = rounded_product(w, y), wz = rounded_product(w, z);
  Mat3<Real> r;
  r.m[0][0] = 1 - 2 * (yy + zz);
  r.m[0][1] = 2 * (xy - wz);
  r.m[0][2] = 2 * (xz + wy);
  r.m[1][0] = 2 * (xy + wz);
  r.m[1][1] = 1 - 2 * (xx + zz);
  r.m[1][2] = 2 * (yz - wx);
  r.m[2][0] = 2 * (xz - wy);
  r.m[2][1] = 2 * (yz + wx);
  r.m[2][2] = 1 - 2 * (xx + yy);
  return r;
}

// A rigid placement: world = position + R(orientation) * body.
template <class Real>
struct Pose {
  Vec3<Real> position;
  Quat<Real> orientation;
};

using Quatd = Quat<double>;
using Posed = Pose<double>;

}  // namespace talus
