// Scalar helpers usable on host and device (std::min/max are not device functions).
#pragma once

#include <cmath>

#include "solver/core/hd.hpp"

namespace talus {

template <class T>
TALUS_HD inline T min_of(T a, T b) {
  return b < a ? b : a;
}
template <class T>
TALUS_HD inline T max_of(T a, T b) {
  return a < b ? b : a;
}
template <class T>
TALUS_HD inline T abs_of(T a) {
  return a < T(0) ? -a : a;
}
template <class T>
TALUS_HD inline void swap_of(T& a, T& b) {
  T t = a;
  a = b;
  b = t;
}

// True for finite x; written without std::isfinite so that it reads the same on host and device
// (x - x is NaN for an infinity or a NaN).
template <class Real>
TALUS_HD inline bool is_finite(Real x) {
  return (x - x) == Real(0);
}

// a * b rounded once and never fused into a neighbouring addition. nvcc contracts a * b + c into
// one fma by default (a different rounding), so a product that is recomputed where it used to be
// stored and loaded needs this to keep the stored bits. The host's default x86-64 target has no fma
// to contract into.
TALUS_HD inline double product_rn(double a, double b) {
#ifdef __CUDA_ARCH__
  return __dmul_rn(a, b);
#else
  return a * b;
#endif
}
TALUS_HD inline float product_rn(float a, float b) {
#ifdef __CUDA_ARCH__
  return __fmul_rn(a, b);
#else
  return a * b;
#endif
}

// Machine epsilon of the real type, usable in device code.
template <class Real>
struct Eps;
template <>
struct Eps<double> {
  static constexpr double value = 2.220446049250313e-16;
};
template <>
struct Eps<float> {
  static constexpr float value = 1.1920929e-07f;
};

// sqrt(Eps): a relative tolerance for quantities that lose half the digits, or for checks that
// must pass on round-off and fail on a wrong result.
template <class Real>
struct SqrtEps;
template <>
struct SqrtEps<double> {
  static constexpr double value = 1.4901161193847656e-08;
};
template <>
struct SqrtEps<float> {
  static constexpr float value = 3.4526698e-04f;
};

}  // namespace talus
