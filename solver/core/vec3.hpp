// A small 3-vector for host and device code, templated on the real type (float or double).
#pragma once

#include <cmath>

#include "solver/core/hd.hpp"
#include "solver/core/math.hpp"

namespace talus {

template <class Real>
struct Vec3 {
  Real x, y, z;

  TALUS_HD Vec3() : x(0), y(0), z(0) {}
  TALUS_HD Vec3(Real x_, Real y_, Real z_) : x(x_), y(y_), z(z_) {}
  template <class Other>
  TALUS_HD explicit Vec3(const Vec3<Other>& o) : x(Real(o.x)), y(Real(o.y)), z(Real(o.z)) {}

  TALUS_HD Real operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  TALUS_HD Real& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }

  TALUS_HD Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  TALUS_HD Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  TALUS_HD Vec3 operator-() const { return {-x, -y, -z}; }
  TALUS_HD Vec3 operator*(Real s) const { return {x * s, y * s, z * s}; }
  TALUS_HD Vec3 operator/(Real s) const { return {x / s, y / s, z / s}; }
  TALUS_HD Vec3& operator+=(const Vec3& o) {
    x += o.x;
    y += o.y;
    z += o.z;
    return *this;
  }
  TALUS_HD Vec3& operator-=(const Vec3& o) {
    x -= o.x;
    y -= o.y;
    z -= o.z;
    return *this;
  }
  TALUS_HD Vec3& operator*=(Real s) {
    x *= s;
    y *= s;
    z *= s;
    return *this;
  }
};

template <class Real>
TALUS_HD inline Vec3<Real> operator*(Real s, const Vec3<Real>& v) {
  return v * s;
}

template <class Real>
TALUS_HD inline Real dot(const Vec3<Real>& a, const Vec3<Real>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

template <class Real>
TALUS_HD inline Vec3<Real> cross(const Vec3<Real>& a, const Vec3<Real>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

template <class Real>
TALUS_HD inline Real norm2(const Vec3<Real>& a) {
  return dot(a, a);
}

template <class Real>
TALUS_HD inline Real norm(const Vec3<Real>& a) {
  return std::sqrt(dot(a, a));
}

// Signed volume times 6 of the tetrahedron (o, a, b, c).
template <class Real>
TALUS_HD inline Real triple(const Vec3<Real>& a, const Vec3<Real>& b, const Vec3<Real>& c) {
  return dot(a, cross(b, c));
}

template <class Real>
TALUS_HD inline bool is_finite(const Vec3<Real>& v) {
  return is_finite(v.x) && is_finite(v.y) && is_finite(v.z);
}

using Vec3d = Vec3<double>;
using Vec3f = Vec3<float>;

}  // namespace talus
