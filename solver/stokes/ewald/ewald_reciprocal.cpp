#include "stokes/ewald/ewald_reciprocal.hpp"

#include "stokes/kernels/ewald_kernel.hpp"
#include "stokes/kernels/stokeslet.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <omp.h>

namespace capsim {

namespace {

// Half of the wave vectors 0 < |k| < k_cut: k and -k add the same to a real field, so one
// of each pair is summed, twice. They come in rows of consecutive m2 at fixed (m1, m3),
// k = m1 b1 + m2 b2 + m3 b3, whose phase factor at x is E1^m1 E2^m2 E3^m3 with
// E_d = exp(i b_d . x): along a row each wave vector costs one complex product instead of
// a sine and a cosine, and the loop vectorises.
struct WaveRows {
  struct Row {
    int m1, m3, m2_first, count, offset;
  };
  std::vector<Row> rows;
  std::vector<Vec3> k;
  int m = 0;                  // |m1| <= m, 0 <= m3 <= m
  int m2_min = 0, m2_max = 0; // m2 of all rows
};

// The wave vectors of for_each_wave_vector in the upper half space.
WaveRows half_wave_rows(const ShearedLattice& g, double k_cut) {
  WaveRows w;
  w.m2_min = INT_MAX;
  w.m2_max = INT_MIN;
  for_each_wave_vector(g, k_cut, [&](int m1, int m2, int m3, Vec3 k) {
    if (!(m3 > 0 || (m3 == 0 && (m1 > 0 || (m1 == 0 && m2 > 0)))))
      return;
    if (w.rows.empty() || w.rows.back().m1 != m1 || w.rows.back().m3 != m3)
      w.rows.push_back({m1, m3, m2, 0, int(w.k.size())});
    ++w.rows.back().count;
    w.k.push_back(k);
    w.m = std::max({w.m, std::abs(m1), m3});
    w.m2_min = std::min(w.m2_min, m2);
    w.m2_max = std::max(w.m2_max, m2);
  });
  return w;
}

// exp(i n theta) for n = first, ..., first + count - 1, by recurrence from the first.
void phase_powers(double theta, int first, int count, double* c, double* s) {
  const double c1 = std::cos(theta), s1 = std::sin(theta);
  c[0] = std::cos(first * theta);
  s[0] = std::sin(first * theta);
  for (int n = 1; n < count; ++n) {
    c[n] = c[n - 1] * c1 - s[n - 1] * s1;
    s[n] = c[n - 1] * s1 + s[n - 1] * c1;
  }
}

// E1^m1, E2^m2, E3^m3 at one point, over the ranges of the rows.
struct PhaseTables {
  std::vector<double> c1, s1, c2, s2, c3, s3;

  explicit PhaseTables(const WaveRows& w)
      : c1(2 * w.m + 1), s1(2 * w.m + 1), c2(w.m2_max - w.m2_min + 1),
        s2(w.m2_max - w.m2_min + 1), c3(w.m + 1), s3(w.m + 1) {}

  void fill(const WaveRows& w, const ShearedLattice& g, Vec3 x) {
    const double c = 2.0 * kPi / g.L; // b_d . x, with b1 = c (1, -s, 0)
    phase_powers(c * (x.x - g.s * x.y), -w.m, 2 * w.m + 1, c1.data(), s1.data());
    phase_powers(c * x.y, w.m2_min, int(c2.size()), c2.data(), s2.data());
    phase_powers(c * x.z, 0, w.m + 1, c3.data(), s3.data());
  }

  // Calls visit(row, a_re, a_im, e_re, e_im): a = E1^m1 E3^m3 and e = E2^m2 from the
  // row's first m2 on.
  template <class Visit> void for_rows(const WaveRows& w, Visit visit) const {
    for (const WaveRows::Row& r : w.rows) {
      const double xr = c1[r.m1 + w.m], xi = s1[r.m1 + w.m], zr = c3[r.m3], zi = s3[r.m3];
      const int e = r.m2_first - w.m2_min;
      visit(r, xr * zr - xi * zi, xr * zi + xi * zr, c2.data() + e, s2.data() + e);
    }
  }
};

// Channels x 3 components of a complex field over the half wave vectors, as real and
// imaginary parts: data[(2 (3 channel + component) + part) K + k].
struct Spectrum {
  int K = 0;
  std::vector<double> data;
  Spectrum(int channels, int K) : K(K), data(size_t(6 * channels) * K, 0.0) {}
  double* at(int channel, int component, int part) {
    return data.data() + offset(channel, component, part);
  }
  const double* at(int channel, int component, int part) const {
    return data.data() + offset(channel, component, part);
  }
  size_t offset(int channel, int component, int part) const {
    return size_t(2 * (3 * channel + component) + part) * K;
  }
};

// S_c(k) = sum_j f_cj exp(-i k . y_j) for C weight vectors (channels) per point, in
// parallel over the points with one spectrum per thread, added in thread order
// (deterministic for a fixed thread count).
template <int C>
Spectrum structure_factors(const ShearedLattice& g, const WaveRows& w,
                           const std::vector<Vec3>& y, const std::vector<Vec3>* f) {
  const int K = int(w.k.size());
  std::vector<Spectrum> partial(omp_get_max_threads(), Spectrum(C, K));
#pragma omp parallel
  {
    Spectrum& s = partial[omp_get_thread_num()];
    double* re[C][3];
    double* im[C][3];
    for (int c = 0; c < C; ++c)
      for (int d = 0; d < 3; ++d) {
        re[c][d] = s.at(c, d, 0);
        im[c][d] = s.at(c, d, 1);
      }
    PhaseTables e(w);
#pragma omp for schedule(static)
    for (size_t j = 0; j < y.size(); ++j) {
      e.fill(w, g, y[j]);
      double fj[C][3];
      for (int c = 0; c < C; ++c) {
        fj[c][0] = f[c][j].x;
        fj[c][1] = f[c][j].y;
        fj[c][2] = f[c][j].z;
      }
      e.for_rows(w, [&](const WaveRows::Row& r, double ar, double ai, const double* er,
                        const double* ei) {
        const int o = r.offset;
#pragma omp simd
        for (int t = 0; t < r.count; ++t) {
          const double pr = ar * er[t] - ai * ei[t], pi = ar * ei[t] + ai * er[t];
          for (int c = 0; c < C; ++c)
            for (int d = 0; d < 3; ++d) { // exp(-i k.y) = pr - i pi
              re[c][d][o + t] += fj[c][d] * pr;
              im[c][d][o + t] -= fj[c][d] * pi;
            }
        }
      });
    }
  }
  for (size_t t = 1; t < partial.size(); ++t)
    for (size_t i = 0; i < partial[0].data.size(); ++i)
      partial[0].data[i] += partial[t].data[i];
  return std::move(partial[0]);
}

// u_i += 2 sum_{half k} Re[exp(i k . x_i) A(k)] at every target.
void add_field(const ShearedLattice& g, const WaveRows& w, const Spectrum& a,
               const std::vector<Vec3>& x, std::vector<Vec3>& u) {
  const double *ar[3], *ai[3];
  for (int d = 0; d < 3; ++d) {
    ar[d] = a.at(0, d, 0);
    ai[d] = a.at(0, d, 1);
  }
#pragma omp parallel
  {
    PhaseTables e(w);
#pragma omp for schedule(static)
    for (size_t i = 0; i < x.size(); ++i) {
      e.fill(w, g, x[i]);
      double sum[3] = {0, 0, 0};
      e.for_rows(w, [&](const WaveRows::Row& r, double pr0, double pi0, const double* er,
                        const double* ei) {
        const int o = r.offset;
        double s0 = 0, s1 = 0, s2 = 0;
#pragma omp simd reduction(+ : s0, s1, s2)
        for (int t = 0; t < r.count; ++t) {
          const double pr = pr0 * er[t] - pi0 * ei[t], pi = pr0 * ei[t] + pi0 * er[t];
          s0 += pr * ar[0][o + t] - pi * ai[0][o + t];
          s1 += pr * ar[1][o + t] - pi * ai[1][o + t];
          s2 += pr * ar[2][o + t] - pi * ai[2][o + t];
        }
        sum[0] += s0;
        sum[1] += s1;
        sum[2] += s2;
      });
      u[i] += 2.0 * Vec3{sum[0], sum[1], sum[2]};
    }
  }
}

Vec3 component_vector(const Spectrum& s, int channel, int part, int k) {
  return {s.at(channel, 0, part)[k], s.at(channel, 1, part)[k],
          s.at(channel, 2, part)[k]};
}

void set_component_vector(Spectrum& s, int channel, int part, int k, Vec3 v) {
  s.at(channel, 0, part)[k] = v.x;
  s.at(channel, 1, part)[k] = v.y;
  s.at(channel, 2, part)[k] = v.z;
}

// A(k) = (8 pi / V) J^EII(k) S(k) in place, real and imaginary parts alike.
void apply_weights(const ShearedLattice& g, const WaveRows& w, double xi, Spectrum& s) {
  const double c = 8.0 * kPi / (g.L * g.L * g.L);
#pragma omp parallel for schedule(static)
  for (int k = 0; k < s.K; ++k)
    for (int part = 0; part < 2; ++part)
      set_component_vector(
          s, 0, part, k,
          c * ewald_recip_apply(w.k[k], component_vector(s, 0, part, k), xi));
}

} // namespace

void ewald_reciprocal_direct(const ShearedLattice& g, const std::vector<Vec3>& x,
                             const FarSources& s, const EwaldParameters& p,
                             std::vector<Vec3>& u) {
  const WaveRows w = half_wave_rows(g, p.k_cut);
  std::vector<Vec3> y(s.size()), f(s.size());
  for (size_t j = 0; j < s.size(); ++j) {
    y[j] = {s.y[0][j], s.y[1][j], s.y[2][j]};
    f[j] = {s.f[0][j], s.f[1][j], s.f[2][j]};
  }
  Spectrum a = structure_factors<1>(g, w, y, &f);
  apply_weights(g, w, p.xi, a);
  add_field(g, w, a, x, u);
}

void ewald_reciprocal_patches(const ShearedLattice& g, const std::vector<Vec3>& x,
                              const std::vector<PatchMoments>& patches,
                              const EwaldParameters& p, std::vector<Vec3>& u) {
  // A patch's structure-factor term is exp(-i k.c) (F - i D k): channel 0 carries F,
  // channels 1-3 the columns D_.l, combined per wave vector below.
  const WaveRows w = half_wave_rows(g, p.k_cut);
  std::vector<Vec3> c(patches.size());
  std::vector<Vec3> f[4];
  for (auto& v : f)
    v.resize(patches.size());
  for (size_t j = 0; j < patches.size(); ++j) {
    c[j] = patches[j].centre;
    f[0][j] = patches[j].force;
    for (int l = 0; l < 3; ++l)
      f[1 + l][j] = {patches[j].dipole.m[0][l], patches[j].dipole.m[1][l],
                     patches[j].dipole.m[2][l]};
  }
  Spectrum s = structure_factors<4>(g, w, c, f);
  for (int k = 0; k < s.K; ++k) { // -i (a + i b) k_l = (b - i a) k_l
    Vec3 re = component_vector(s, 0, 0, k), im = component_vector(s, 0, 1, k);
    const double kl[3] = {w.k[k].x, w.k[k].y, w.k[k].z};
    for (int l = 0; l < 3; ++l) {
      re += kl[l] * component_vector(s, 1 + l, 1, k);
      im -= kl[l] * component_vector(s, 1 + l, 0, k);
    }
    set_component_vector(s, 0, 0, k, re);
    set_component_vector(s, 0, 1, k, im);
  }
  apply_weights(g, w, p.xi, s);
  add_field(g, w, s, x, u);
}

} // namespace capsim
