#ifndef BOUNCECAL_DEM_SCENE_VEC_H_
#define BOUNCECAL_DEM_SCENE_VEC_H_

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace bouncecal::dem::scene {

// A plain fixed-size vector for the force loop. (Eigen's expression templates were not always
// inlined in the large force kernels, costing about a fifth of the step; this type always is.)
template <int Dim>
struct Vec {
  static_assert(Dim == 2 || Dim == 3);
  double v[Dim];

  static Vec Zero() {
    Vec r;
    for (int d = 0; d < Dim; ++d) r.v[d] = 0;
    return r;
  }
  double& operator[](int d) { return v[d]; }
  double operator[](int d) const { return v[d]; }
  double x() const { return v[0]; }
  double y() const { return v[1]; }
  double z() const { return v[Dim - 1]; }
  void setZero() { *this = Zero(); }

  Vec& operator+=(const Vec& o) {
    for (int d = 0; d < Dim; ++d) v[d] += o.v[d];
    return *this;
  }
  Vec& operator-=(const Vec& o) {
    for (int d = 0; d < Dim; ++d) v[d] -= o.v[d];
    return *this;
  }
  Vec& operator*=(double s) {
    for (int d = 0; d < Dim; ++d) v[d] *= s;
    return *this;
  }
  friend Vec operator+(Vec a, const Vec& b) { return a += b; }
  friend Vec operator-(Vec a, const Vec& b) { return a -= b; }
  friend Vec operator-(Vec a) { return a *= -1.0; }
  friend Vec operator*(double s, Vec a) { return a *= s; }
  friend Vec operator*(Vec a, double s) { return a *= s; }
  friend Vec operator/(Vec a, double s) { return a *= (1.0 / s); }
  friend bool operator==(const Vec& a, const Vec& b) {
    for (int d = 0; d < Dim; ++d) {
      if (a.v[d] != b.v[d]) return false;
    }
    return true;
  }

  double dot(const Vec& o) const {
    double s = 0;
    for (int d = 0; d < Dim; ++d) s += v[d] * o.v[d];
    return s;
  }
  double squaredNorm() const { return dot(*this); }
  double norm() const { return std::sqrt(squaredNorm()); }
  Vec cwiseMin(const Vec& o) const {
    Vec r;
    for (int d = 0; d < Dim; ++d) r.v[d] = std::min(v[d], o.v[d]);
    return r;
  }
  Vec cwiseMax(const Vec& o) const {
    Vec r;
    for (int d = 0; d < Dim; ++d) r.v[d] = std::max(v[d], o.v[d]);
    return r;
  }
  bool allFinite() const {
    for (int d = 0; d < Dim; ++d) {
      if (!std::isfinite(v[d])) return false;
    }
    return true;
  }
};

// Angular quantities are a 3-vector in 3D and a scalar (about z) in 2D, so one templated engine
// serves spheres and disks.
template <int Dim>
using Spin = std::conditional_t<Dim == 3, Vec<3>, double>;

template <int Dim>
inline Spin<Dim> ZeroSpin() {
  if constexpr (Dim == 3) {
    return Vec<3>::Zero();
  } else {
    return 0.0;
  }
}

inline Vec<3> Cross(const Vec<3>& a, const Vec<3>& b) {
  return Vec<3>{{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}

// omega x r: the velocity of a point at r on a body spinning with omega.
inline Vec<3> SpinCross(const Vec<3>& omega, const Vec<3>& r) { return Cross(omega, r); }
inline Vec<2> SpinCross(double omega, const Vec<2>& r) {
  return Vec<2>{{-omega * r.y(), omega * r.x()}};
}

// r x f: the torque of a force f applied at r.
inline Vec<3> TorqueCross(const Vec<3>& r, const Vec<3>& f) { return Cross(r, f); }
inline double TorqueCross(const Vec<2>& r, const Vec<2>& f) {
  return r.x() * f.y() - r.y() * f.x();
}

inline double SpinSquaredNorm(const Vec<3>& w) { return w.squaredNorm(); }
inline double SpinSquaredNorm(double w) { return w * w; }

}  // namespace bouncecal::dem::scene

#endif  // BOUNCECAL_DEM_SCENE_VEC_H_
