#pragma once
// Branch-free exp and erfc for the screened real-space kernel. std::erfc has no vector
// version and std::exp has one only under -ffast-math, so a loop calling them runs one
// point at a time; these inline polynomials let the compiler vectorise the whole kernel
// (and run unchanged on a GPU). Both are accurate to a few 1e-14 relative, far below any
// Ewald tolerance a user can ask for (tested against the standard library).
#include "common/hd.hpp"

#include <cstdint>
#include <cstring>

namespace capsim {

// Horner's rule on every Step-th coefficient a[I], a[I + Step], ... (a[0] the highest
// power), unrolled at compile time: a loop left inside would stop the callers' loops
// vectorising.
template <int I, int Step, int N, class T>
CAPSIM_HD_INLINE T horner(const T* a, T w, T p) {
  if constexpr (I >= N)
    return p;
  else
    return horner<I + Step, Step, N>(a, w, p * w + a[I]);
}

// The polynomial a[0] z^(N-1) + ... + a[N-1] (N a multiple of 4) as four interleaved
// Horner chains in w = z^4: sum_j z^j Q_j(z^4). A vectorised kernel is limited by the
// latency of its longest chain of dependent FMAs, which this cuts fourfold.
template <int N, class T> CAPSIM_HD_INLINE T polynomial4(const T* a, T z) {
  static_assert(N % 4 == 0, "polynomial4 needs a multiple of 4 coefficients");
  const T z2 = z * z, w = z2 * z2;
  const T q3 = horner<4, 4, N>(a, w, a[0]); // powers 3 mod 4
  const T q2 = horner<5, 4, N>(a, w, a[1]);
  const T q1 = horner<6, 4, N>(a, w, a[2]);
  const T q0 = horner<7, 4, N>(a, w, a[3]);
  return (q0 + z * q1) + z2 * (q2 + z * q3);
}

// exp(y) for y <= 0 by Cody-Waite reduction y = n ln 2 + r, |r| <= ln2/2, a Taylor
// polynomial in r and 2^n built in the exponent bits; the constants of one precision:
template <class T, class Bits, int N> struct ExpReduction {
  T lowest;    // y is raised to this (0-ish results below it)
  T shifter;   // 1.5 * 2^mantissa: adding it rounds to an integer
  T ln2_hi;    // ln 2 in few enough bits that n ln2_hi is exact
  T ln2_lo;    // the rest of ln 2
  Bits offset; // the bits of the shifter, less the exponent bias
  int mantissa;
  T taylor[N]; // 1/(N-1)!, ..., 1/1!, 1/0!
};

template <class T, class Bits, int N>
CAPSIM_HD_INLINE T exp_reduced(T y, const ExpReduction<T, Bits, N>& c) {
  y = y < c.lowest ? c.lowest : y;
  const T t = y * T(1.4426950408889634) + c.shifter;
  const T n = t - c.shifter;
  const T r = (y - n * c.ln2_hi) - n * c.ln2_lo;
  const T p = polynomial4<N>(c.taylor, r);
  // 2^n: the low bits of t hold n (two's complement); move n + bias into the exponent.
  Bits bits;
  std::memcpy(&bits, &t, sizeof bits);
  bits = (bits - c.offset) << c.mantissa;
  T scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return p * scale;
}

// Double: y below -700 gives 0-ish values (exp(-700) ~ 1e-304); degree 15 (truncation
// 0.35^16/16! = 2e-21).
CAPSIM_HD_INLINE double exp_nonpositive(double y) {
  constexpr ExpReduction<double, std::int64_t, 16> c{
      -700.0,
      6755399441055744.0,
      0.6931471803691238,
      1.9082149292705877e-10,
      std::int64_t(0x4338000000000000) - 1023,
      52,
      {1.0 / 1307674368000.0, 1.0 / 87178291200.0, 1.0 / 6227020800.0, 1.0 / 479001600.0,
       1.0 / 39916800.0, 1.0 / 3628800.0, 1.0 / 362880.0, 1.0 / 40320.0, 1.0 / 5040.0,
       1.0 / 720.0, 1.0 / 120.0, 1.0 / 24.0, 1.0 / 6.0, 0.5, 1.0, 1.0}};
  return exp_reduced(y, c);
}

// Single: y below -87 gives 0-ish values; degree 7 (truncation 0.35^8/8! = 5e-9, below
// the float rounding of 6e-8).
CAPSIM_HD_INLINE float exp_nonpositive(float y) {
  constexpr ExpReduction<float, std::int32_t, 8> c{-87.0f,
                                                   12582912.0f,
                                                   0.693145751953125f,
                                                   1.42860677e-06f,
                                                   std::int32_t(0x4B400000) - 127,
                                                   23,
                                                   {1.0f / 5040.0f, 1.0f / 720.0f,
                                                    1.0f / 120.0f, 1.0f / 24.0f,
                                                    1.0f / 6.0f, 0.5f, 1.0f, 1.0f}};
  return exp_reduced(y, c);
}

// The scaled complementary error function erfcx(x) = exp(x^2) erfc(x) for x >= 0, by
// Weideman's rational expansion (SIAM J. Numer. Anal. 31, 1994, eq. for w(z) at z = i x):
//   erfcx(x) = 2 p(Z)/(K + x)^2 + 1/(sqrt(pi) (K + x)),  Z = (K - x)/(K + x),
// p of degree 31, K = sqrt(N/sqrt 2) with N = 32. The coefficients are Weideman's FFT
// recipe evaluated once in double precision; relative error < 4e-14 on [0, 6].
constexpr double kErfcxK = 4.756828460010884;

// erfcx(x) given inv = 1/(K + x): callers that also need another reciprocal can share one
// division between the two (the divider, not the FMAs, limits vectorised kernels).
CAPSIM_HD_INLINE double erfcx_nonnegative(double x, double inv) {
  constexpr double a[32] = {
      -1.3031797863050087e-12, 3.7408812931653625e-12,  8.0303678999638894e-12,
      -2.1543632077838769e-11, -5.5442359481664624e-11, 1.1658251093523774e-10,
      4.1537430918334532e-10,  -5.2310204811963288e-10, -3.2080150917233689e-09,
      8.1248894568466516e-10,  2.3797556779897417e-08,  2.2930439065099966e-08,
      -1.4813078915120977e-07, -4.1840763702169776e-07, 4.2558331375750085e-07,
      4.4015317315785499e-06,  6.8210319440019849e-06,  -2.140961920171075e-05,
      -0.00013075449254615346, -0.00024532980270021432, 0.00039259136070070311,
      0.0045195411053492174,   0.019006155784845408,    0.05730440352983722,
      0.14060716226893769,     0.29544451071508732,     0.54601397206393409,
      0.90192548936479988,     1.3455441692345449,      1.8256696296324815,
      2.2635372999002676,      2.5722534081245696};
  const double z = (kErfcxK - x) * inv;
  const double p = polynomial4<32>(a, z);
  return (2.0 * p * inv + 0.56418958354775628) * inv; // 0.5641... = 1/sqrt(pi)
}

// erfcx in single precision: Weideman's expansion with N = 16 (p of degree 15, K =
// sqrt(16/sqrt 2)); relative error about 4e-7 on [0, 6] evaluated in float (1.3e-7 of
// it the expansion's).
constexpr float kErfcxKSingle = 3.363585661014858f;

CAPSIM_HD_INLINE float erfcx_nonnegative(float x, float inv) {
  constexpr float a[16] = {
      9.93932254e-07f,  3.98128758e-06f, -5.58423341e-06f, -2.73464046e-05f,
      2.17098679e-05f,  2.10710564e-04f, 8.70315843e-05f,  -1.52765974e-03f,
      -3.88101519e-03f, 3.68256732e-03f, 5.18224024e-02f,  1.91241727e-01f,
      4.69290901e-01f,  8.86447830e-01f, 1.36224082e+00f,  1.74839589e+00f};
  const float z = (kErfcxKSingle - x) * inv;
  const float p = polynomial4<16>(a, z);
  return (2.0f * p * inv + 0.56418958f) * inv;
}

CAPSIM_HD double erfcx_nonnegative(double x) {
  return erfcx_nonnegative(x, 1.0 / (kErfcxK + x));
}

} // namespace capsim
