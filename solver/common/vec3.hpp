#pragma once
// A plain 3-vector: layout-compatible with double[3], usable in host-device kernels.
#include "common/hd.hpp"

#include <cmath>

namespace capsim {

struct Vec3 {
  double x = 0, y = 0, z = 0;
};

// Exact equality, component by component (the same state, bit for bit but for -0 = 0).
CAPSIM_HD bool operator==(Vec3 a, Vec3 b) {
  return a.x == b.x && a.y == b.y && a.z == b.z;
}
CAPSIM_HD bool operator!=(Vec3 a, Vec3 b) {
  return !(a == b);
}
CAPSIM_HD Vec3 operator+(Vec3 a, Vec3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
CAPSIM_HD Vec3 operator-(Vec3 a, Vec3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
CAPSIM_HD Vec3 operator-(Vec3 a) {
  return {-a.x, -a.y, -a.z};
}
CAPSIM_HD Vec3 operator*(double s, Vec3 a) {
  return {s * a.x, s * a.y, s * a.z};
}
CAPSIM_HD Vec3 operator*(Vec3 a, double s) {
  return s * a;
}
CAPSIM_HD Vec3& operator+=(Vec3& a, Vec3 b) {
  a.x += b.x;
  a.y += b.y;
  a.z += b.z;
  return a;
}
CAPSIM_HD Vec3& operator-=(Vec3& a, Vec3 b) {
  a.x -= b.x;
  a.y -= b.y;
  a.z -= b.z;
  return a;
}
CAPSIM_HD double dot(Vec3 a, Vec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
CAPSIM_HD Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
CAPSIM_HD double norm(Vec3 a) {
  return std::sqrt(dot(a, a));
}

// Symmetric 3x3 tensor stored as full row-major array (stresslets, second moments).
struct Mat3 {
  double m[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
};
CAPSIM_HD Vec3 operator*(const Mat3& a, Vec3 v) {
  return {a.m[0][0] * v.x + a.m[0][1] * v.y + a.m[0][2] * v.z,
          a.m[1][0] * v.x + a.m[1][1] * v.y + a.m[1][2] * v.z,
          a.m[2][0] * v.x + a.m[2][1] * v.y + a.m[2][2] * v.z};
}

} // namespace capsim
