// Physics of the BRDF (pbr/brdf.h, pbr/shading.h): each term against its closed form,
// normalisation of D, reciprocity, the white furnace, and no NaN/Inf at the edges.
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <doctest/doctest.h>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "softpbr/pbr/brdf.h"
#include "softpbr/pbr/light.h"
#include "softpbr/pbr/material.h"
#include "softpbr/pbr/shading.h"

namespace pbr = softpbr::pbr;

namespace {

constexpr double kPi = 3.141592653589793238462643383279502884;

// Relative comparison for float results against double references.
bool close_rel(double got, double want, double rel) { return std::fabs(got - want) <= rel * std::fabs(want) + 1e-30; }

pbr::ShadingMaterial material(glm::vec3 base, float metallic, float roughness) {
  pbr::Material m;
  m.base_color = base;
  m.metallic = metallic;
  m.roughness = roughness;
  return pbr::prepare_material(m);
}

// A unit vector at polar angle theta from +z (the normal) and azimuth phi.
glm::dvec3 polar(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// An orthonormal frame around unit w (Frisvad/Duff et al. 2017 branchless construction).
void frame(const glm::dvec3& w, glm::dvec3& t, glm::dvec3& b) {
  const double sign = std::copysign(1.0, w.z);
  const double a = -1.0 / (sign + w.z);
  const double bb = w.x * w.y * a;
  t = {1.0 + sign * w.x * w.x * a, sign * bb, -sign * w.x};
  b = {bb, sign + w.y * w.y * a, -w.y};
}

softpbr::simd::Vec3<float> lanes(const glm::vec3& v) { return {v.x, v.y, v.z}; }
glm::vec3 to_glm(const softpbr::simd::Vec3<float>& v) { return {v.x, v.y, v.z}; }

bool finite_nonneg(const glm::vec3& c) {
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(c[i]) || c[i] < 0.0f) return false;
  return true;
}

}  // namespace

TEST_CASE("BRDF terms equal their closed forms at fixed angles (float vs double)") {
  const double degrees[] = {0, 10, 25, 45, 60, 75, 85, 89, 90};
  const double roughnesses[] = {0.045, 0.1, 0.3, 0.5, 0.8, 1.0};
  for (double r : roughnesses) {
    const double alpha = r * r;
    const double k = (r + 1) * (r + 1) / 8;  // Karis 2013, direct lights
    CAPTURE(r);
    CHECK(close_rel(pbr::k_direct(static_cast<float>(r)), k, 1e-6));
    CHECK(pbr::k_direct(r) == doctest::Approx(k).epsilon(1e-15));
    for (double deg : degrees) {
      CAPTURE(deg);
      const double c = std::cos(deg * kPi / 180);
      const auto cf = static_cast<float>(c);
      const double cd = cf;  // the float argument, exactly, for the double references
      // D_GGX: α² / (π ((n·h)²(α² − 1) + 1)²)
      const double a2 = alpha * alpha;
      const double den = cd * cd * (a2 - 1) + 1;
      const double D = a2 / (kPi * den * den);
      // In float, d = (n·h)²(α² − 1) + 1 carries an absolute error of about 2⁻²⁴ (α² − 1
      // rounds near 1), which is large against d ≈ α² at the peak of a sharp lobe.
      CHECK(close_rel(pbr::D_GGX(cf, static_cast<float>(alpha)), D, 4e-6 + 2.4e-7 / den));
      // Schlick-GGX G1 and the separable Smith G.
      const double G1 = cd / (cd * (1 - k) + k);
      CHECK(close_rel(pbr::G_SchlickGGX(cf, static_cast<float>(k)), G1, 1e-6));
      const double c2 = std::cos((90 - deg) * kPi / 360);  // another angle for the l side
      const double G = G1 * (c2 / (c2 * (1 - k) + k));
      CHECK(close_rel(pbr::G_Smith(cf, static_cast<float>(c2), static_cast<float>(k)), G, 2e-6));
    }
    // Landmarks of D: peak 1/(π α²) at n·h = 1, α²/π at n·h = 0.
    // The double instantiation is double-precise (up to the same cancellation, 2⁻⁵³/α²).
    CHECK(close_rel(pbr::D_GGX(1.0, alpha), 1 / (kPi * alpha * alpha), 1e-15 + 4.5e-16 / (alpha * alpha)));
    CHECK(close_rel(pbr::D_GGX(0.0, alpha), alpha * alpha / kPi, 1e-14));
    CHECK(pbr::G_SchlickGGX(1.0, k) == doctest::Approx(1.0).epsilon(1e-15));
    CHECK(pbr::G_SchlickGGX(0.0f, static_cast<float>(k)) == 0.0f);
  }

  // F_Schlick = F0 + (1 − F0)(1 − v·h)^5, f0_of = mix(0.04, base, metallic), Lambert 1/π.
  const glm::vec3 f0s[] = {{0.04f, 0.04f, 0.04f}, {1.0f, 0.71f, 0.29f}, {0.95f, 0.64f, 0.54f}, {0, 0, 0}, {1, 1, 1}};
  const double vohs[] = {0.0, 0.05, 0.2, 0.5, 0.7071, 0.9, 1.0};
  for (const glm::vec3& f0 : f0s)
    for (double voh : vohs) {
      const auto vf = static_cast<float>(voh);
      const glm::vec3 F = to_glm(pbr::F_Schlick(lanes(f0), vf));
      const softpbr::simd::Vec3<double> Fd = pbr::F_Schlick<double>({f0.x, f0.y, f0.z}, vf);
      for (int i = 0; i < 3; ++i) {
        const double want = f0[i] + (1.0 - f0[i]) * std::pow(1.0 - static_cast<double>(vf), 5);
        CHECK(std::fabs(F[i] - want) <= 2e-7);
        CHECK(std::fabs(std::array<double, 3>{Fd.x, Fd.y, Fd.z}[i] - want) <= 1e-15);
      }
    }
  CHECK(pbr::Fd_Lambert<double>() == doctest::Approx(1 / kPi).epsilon(1e-16));
  CHECK(pbr::Fd_Lambert<float>() == pbr::kInvPi);
  struct F0Case {
    glm::vec3 base;
    float metallic;
  };
  for (const F0Case& t : {F0Case{{0.8f, 0.1f, 0.1f}, 0.0f}, F0Case{{1.0f, 0.71f, 0.29f}, 1.0f},
                          F0Case{{0.5f, 0.25f, 0.9f}, 0.5f}, F0Case{{0.0f, 0.0f, 0.0f}, 0.25f}}) {
    const glm::vec3 f0 = pbr::f0_of(t.base, t.metallic);
    for (int i = 0; i < 3; ++i) CHECK(close_rel(f0[i], 0.04 + (t.base[i] - 0.04) * t.metallic, 1e-6));
  }
  // Exactly 0.04 for a dielectric and exactly the base colour for a metal.
  CHECK(pbr::f0_of({0.3f, 0.6f, 0.9f}, 0.0f) == glm::vec3(0.04f));
  CHECK(pbr::f0_of({0.3f, 0.6f, 0.9f}, 1.0f) == glm::vec3(0.3f, 0.6f, 0.9f));
}

TEST_CASE("Fresnel: F = F0 exactly at normal incidence and F = 1 at grazing (v·h = 0)") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 1000; ++i) {
    const glm::vec3 f0(u(rng), u(rng), u(rng));
    CHECK(to_glm(pbr::F_Schlick(lanes(f0), 1.0f)) == f0);
    const glm::vec3 g = to_glm(pbr::F_Schlick(lanes(f0), 0.0f));
    for (int c = 0; c < 3; ++c) CHECK(std::fabs(g[c] - 1.0f) <= 6e-8f);  // one float ulp below 1
  }
}

TEST_CASE("D_GGX is normalised: the integral of D(h)(n.h) over the hemisphere is 1") {
  // ∫ D (n·h) dω = 2π ∫_0^{π/2} D(cos θ) cos θ sin θ dθ by composite Simpson in θ. The lobe
  // has width ≈ α in θ; 2·10⁵ steps put > 100 nodes across it even at kMinRoughness
  // (α = 0.002), so the quadrature error (< 1e-10, seen with D_GGX<double>) is far below
  // the tolerances.
  constexpr int kSteps = 200000;
  const double h = (kPi / 2) / kSteps;
  double worst_double = 0, worst_float = 0;
  for (double r : {0.045, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0}) {
    const double alpha = r * r;
    double sum_d = 0, sum_f = 0;
    for (int i = 0; i <= kSteps; ++i) {
      const double theta = i * h;
      const double w = (i == 0 || i == kSteps) ? 1 : (i % 2 ? 4 : 2);
      const double c = std::cos(theta), s = std::sin(theta);
      sum_d += w * pbr::D_GGX(c, alpha) * c * s;
      sum_f += w * static_cast<double>(pbr::D_GGX(static_cast<float>(c), static_cast<float>(alpha))) * c * s;
    }
    const double integral_d = 2 * kPi * sum_d * h / 3;
    const double integral_f = 2 * kPi * sum_f * h / 3;
    CAPTURE(r);
    CHECK(std::fabs(integral_d - 1) < 1e-6);
    // Float: 1e-3 from roughness 0.1 on; 3e-3 at kMinRoughness, where
    // α² − 1 cancels in float (see D_GGX) and the whole lobe is 0.25% low.
    CHECK(std::fabs(integral_f - 1) < (r < 0.1 ? 3e-3 : 1e-3));
    worst_double = std::max(worst_double, std::fabs(integral_d - 1));
    worst_float = std::max(worst_float, std::fabs(integral_f - 1));
  }
  MESSAGE("D normalisation, roughness 0.045..1: worst |integral - 1| = " << worst_double << " (D_GGX<double>), "
                                                                        << worst_float << " (D_GGX<float>)");
}

TEST_CASE("brdf() is kD c/pi + D G F / (4 (n.l)(n.v)) term by term, for random directions and materials") {
  // shading.h folds D, G and the 4 (n·l)(n·v) into one division and reads h only through
  // n·h and v·h; this checks the folded form against the textbook one in double.
  std::mt19937 rng(20261123);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0;
  int compared = 0;
  for (int i = 0; i < 20000; ++i) {
    const glm::vec3 base(u(rng), u(rng), u(rng));
    const float metallic = i % 3 == 0 ? 0.0f : (i % 3 == 1 ? 1.0f : static_cast<float>(u(rng)));
    const pbr::ShadingMaterial m = material(base, metallic, static_cast<float>(0.05 + 0.95 * u(rng)));
    const glm::dvec3 n = polar(std::acos(2 * u(rng) - 1), 2 * kPi * u(rng));
    glm::dvec3 t, b;
    frame(n, t, b);
    auto around_n = [&](double min_cos, double max_cos) {
      const glm::dvec3 d = polar(std::acos(min_cos + (max_cos - min_cos) * u(rng)), 2 * kPi * u(rng));
      return glm::vec3(glm::normalize(d.x * t + d.y * b + d.z * n));
    };
    // Every tenth light grazes the surface, below the n·l = kMinNoV floor of the divisor.
    const glm::vec3 nf(n), l = i % 10 == 0 ? around_n(1e-6, 3e-4) : around_n(0.001, 1.0), v = around_n(0.001, 1.0);
    // The reference, in double from the float inputs.
    const glm::dvec3 nd(nf), ld(l), vd(v), hd = glm::normalize(ld + vd);
    const double NoL = std::clamp(glm::dot(nd, ld), 0.0, 1.0), NoV = std::clamp(glm::dot(nd, vd), 1e-4, 1.0);
    const double NoH = std::clamp(glm::dot(nd, hd), 0.0, 1.0), VoH = std::clamp(glm::dot(vd, hd), 0.0, 1.0);
    const double a2 = static_cast<double>(m.alpha) * m.alpha, k = m.k;
    const double den = NoH * NoH * (a2 - 1) + 1;
    const double D = a2 / (kPi * den * den);
    const double G = NoV / (NoV * (1 - k) + k) * (NoL / (NoL * (1 - k) + k));
    // brdf.h's textbook terms in double are these formulas, operation for operation.
    CHECK(pbr::D_GGX(NoH, static_cast<double>(m.alpha)) == D);
    CHECK(pbr::G_Smith(NoV, NoL, k) == G);
    const glm::vec3 got = pbr::brdf(m, nf, l, v);
    for (int c = 0; c < 3; ++c) {
      const double F = m.f0[c] + (1.0 - m.f0[c]) * std::pow(1.0 - VoH, 5);
      const double want = std::max(1.0 - F, 0.0) * (1.0 - m.metallic) * m.albedo[c] / kPi +
                          F * D * G / (4 * NoV * std::max(NoL, 1e-4));
      // Float rounding of d = (n·h)²(α² − 1) + 1 (absolute ~2⁻²⁴, large against a sharp
      // lobe's d ≈ α²) and of n·h itself (squared into d), and the absolute error of the
      // float n·l (large against a grazing light's n·l), bound the agreement.
      const double tolerance = 2e-5 + 1e-6 / den + 2e-7 / std::max(NoL, 1e-30);
      const double rel = std::fabs(got[c] - want) / std::max(want, 1e-30);
      worst = std::max(worst, rel / tolerance);
      CHECK_MESSAGE(rel <= tolerance, "sample " << i << " channel " << c << ": " << got[c] << " vs " << want);
      ++compared;
    }
  }
  MESSAGE("brdf() vs the textbook form in double: " << compared << " values, worst error " << worst
                                                     << " of its tolerance");
}

TEST_CASE("DV_GGX_SchlickSmith, the folded term the shader runs, is D_GGX G_Smith / (4 n.l n.v) in double, "
          "and lanes give the float bits") {
  // The grid covers the sharpest lobe (roughness kMinRoughness), grazing n·v at the
  // kMinNoV clamp, and n·l below the divisor's floor (where the term is the textbook form
  // with max(n·l, kMinNoV) in the divisor).
  const float roughnesses[] = {pbr::kMinRoughness, 0.1f, 0.3f, 0.5f, 0.8f, 1.0f};
  const float cosines[] = {0.0f, 1e-6f, pbr::kMinNoV, 3e-4f, 0.01f, 0.2f, 0.5f, 0.7071f, 0.9f, 0.999f, 0.99999f, 1.0f};
  double worst = 0;
  std::vector<float> nohs, nols, novs, alphas, ks, got;
  for (float r : roughnesses)
    for (float NoH : cosines)
      for (float NoL : cosines)
        for (float cv : cosines) {
          const float NoV = std::max(cv, pbr::kMinNoV);
          const float alpha = r * r, k = pbr::k_direct(r);
          const float dv = pbr::DV_GGX_SchlickSmith(NoH, NoL, NoV, alpha, k);
          const double a = alpha, kd = k, nol = NoL, nov = NoV, den = pbr::D_GGX_denominator<double>(NoH, a * a);
          const double want = pbr::D_GGX<double>(NoH, a) * pbr::G_Smith(nov, nol, kd) /
                              (4 * nov * std::max(nol, static_cast<double>(pbr::kMinNoV)));
          // D's float denominator carries ~2⁻²⁴ absolute error (see D_GGX_denominator).
          const double tolerance = 1e-5 + 3e-7 / den;
          const double rel = std::fabs(dv - want) / std::max(want, 1e-30);
          worst = std::max(worst, rel / tolerance);
          CHECK_MESSAGE(rel <= tolerance, "r " << r << " n.h " << NoH << " n.l " << NoL << " n.v " << NoV << ": "
                                               << dv << " vs " << want);
          nohs.push_back(NoH), nols.push_back(NoL), novs.push_back(NoV), alphas.push_back(alpha), ks.push_back(k);
          got.push_back(dv);
        }
  MESSAGE("DV_GGX_SchlickSmith vs D_GGX G_Smith / (4 n.l n.v) in double: worst error " << worst
                                                                                        << " of its tolerance");
  // Eight lanes at a time, each lane the same bits as the float evaluation.
  using V = softpbr::simd::Vec<8>;
  int mismatches = 0;
  for (std::size_t i = 0; i + 8 <= got.size(); i += 8) {
    const V dv = pbr::DV_GGX_SchlickSmith(V::load(&nohs[i]), V::load(&nols[i]), V::load(&novs[i]),
                                          V::load(&alphas[i]), V::load(&ks[i]));
    for (int j = 0; j < 8; ++j) mismatches += std::bit_cast<std::uint32_t>(dv[j]) != std::bit_cast<std::uint32_t>(got[i + j]);
  }
  CHECK(mismatches == 0);
}

TEST_CASE("DV_GGX_SchlickSmith_t, the h-free form the shader runs, matches the textbook D G / (4 n.l n.v) in double "
          "to 1e-5 at the sharpest peak, where the (n.h)^2 (a^2 - 1) + 1 form is off by percents, and lanes give the "
          "float bits") {
  // Normals at and near the half vector of random l, v: within a few lobe widths (α) of
  // the peak, where the textbook denominator cancels. Both float forms get the same float
  // unit vectors; the reference is the textbook form in double from their directions.
  std::mt19937 rng(20261203);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const float roughnesses[] = {pbr::kMinRoughness, 0.07f, 0.1f, 0.2f, 0.5f, 1.0f};
  double worst_t = 0, worst_peak_t = 0, worst_peak_old = 0;
  std::vector<float> ts, nols, novs, alphas, ks, dts, got;
  for (float r : roughnesses) {
    const float alpha = r * r, k = pbr::k_direct(r);
    for (int i = 0; i < 4000; ++i) {
      const glm::dvec3 l = polar(std::acos(u(rng)), 2 * kPi * u(rng)), v = polar(std::acos(u(rng)), 2 * kPi * u(rng));
      const glm::dvec3 h = glm::normalize(l + v);
      glm::dvec3 t, b;
      frame(h, t, b);
      // Tilt n from h by up to 3α (i % 4 == 0: exactly h).
      const double tilt = i % 4 == 0 ? 0.0 : 3.0 * alpha * u(rng), phi = 2 * kPi * u(rng);
      const glm::vec3 nf(glm::normalize(h * std::cos(tilt) + (t * std::cos(phi) + b * std::sin(phi)) * std::sin(tilt)));
      const glm::vec3 lf(l), vf(v);
      // The reference from the directions of the float vectors (a float unit vector's
      // length is 1 ± ~1e-7: taken as the length of n in (n·h)² (α² − 1) + 1, that alone
      // moves a sharp peak's d ≈ α² by ~2%).
      const glm::dvec3 nd = glm::normalize(glm::dvec3(nf)), ld = glm::normalize(glm::dvec3(lf)),
                       vd = glm::normalize(glm::dvec3(vf)), hd = glm::normalize(ld + vd);
      const double NoL = glm::dot(nd, ld), NoV = glm::dot(nd, vd);
      if (NoL <= 1e-3 || NoV <= 1e-3) continue;
      const double a2 = static_cast<double>(alpha) * alpha;
      const double want = pbr::D_GGX<double>(glm::dot(nd, hd), alpha) * pbr::G_Smith<double>(NoV, NoL, k) / (4 * NoL * NoV);
      // The shader's float steps (shading.h brdf_times).
      const glm::vec3 uf = lf + vf;
      const float tf = glm::dot(uf, uf), sf = glm::dot(nf, uf);
      const float nol = std::clamp(glm::dot(nf, lf), 0.0f, 1.0f), nov = std::clamp(glm::dot(nf, vf), pbr::kMinNoV, 1.0f);
      const glm::vec3 c = glm::cross(nf, uf);
      const float dt = pbr::D_GGX_denominator_t(sf, softpbr::simd::Vec3<float>(c.x, c.y, c.z), alpha * alpha);
      const float dv = pbr::DV_GGX_SchlickSmith_t(dt, tf, nol, nov, alpha, k);
      // The textbook-denominator float form, for comparison.
      const float old = pbr::DV_GGX_SchlickSmith(std::clamp(glm::dot(nf, glm::normalize(uf)), 0.0f, 1.0f), nol, nov, alpha, k);
      // Off the peak D is ill-conditioned in the angle θ between n and h: a direction error
      // δ moves it by 4θ / (α² + θ²) δ relative (≤ 2/α), and float vectors carry δ of a few
      // 10⁻⁸ rad (their components, l + v, the cross product). At the peak θ ≈ 0.
      const double theta = std::acos(std::min(glm::dot(nd, hd), 1.0));
      const double tolerance = 1e-5 + 4e-7 * 4 * theta / (a2 + theta * theta);
      const double rel = std::fabs(dv - want) / want, rel_old = std::fabs(old - want) / want;
      worst_t = std::max(worst_t, rel / tolerance);
      if (i % 4 == 0) worst_peak_t = std::max(worst_peak_t, rel), worst_peak_old = std::max(worst_peak_old, rel_old);
      CAPTURE(r);
      CAPTURE(i);
      CHECK(rel <= tolerance);
      ts.push_back(tf), nols.push_back(nol), novs.push_back(nov), alphas.push_back(alpha);
      ks.push_back(k), dts.push_back(dt), got.push_back(dv);
    }
  }
  MESSAGE("DV_GGX_SchlickSmith_t vs the textbook form in double near the peak: worst error "
          << worst_t << " of its tolerance; at the peak (n = h) worst relative error " << worst_peak_t
          << ", the (n.h)^2 (a^2 - 1) + 1 form's " << worst_peak_old);
  CHECK(worst_peak_t <= 1e-5);
  CHECK(worst_peak_old > 100 * worst_peak_t);  // the reason for the form
  // Eight lanes at a time give the float bits.
  using V = softpbr::simd::Vec<8>;
  int mismatches = 0;
  for (std::size_t i = 0; i + 8 <= got.size(); i += 8) {
    const V dv = pbr::DV_GGX_SchlickSmith_t(V::load(&dts[i]), V::load(&ts[i]), V::load(&nols[i]), V::load(&novs[i]),
                                            V::load(&alphas[i]), V::load(&ks[i]));
    for (int j = 0; j < 8; ++j) mismatches += std::bit_cast<std::uint32_t>(dv[j]) != std::bit_cast<std::uint32_t>(got[i + j]);
  }
  CHECK(mismatches == 0);
}

TEST_CASE("BRDF reciprocity: f(l, v) = f(v, l) for random directions, materials and roughness") {
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0;
  for (int i = 0; i < 20000; ++i) {
    const glm::vec3 base(u(rng), u(rng), u(rng));
    const float metallic = i % 3 == 0 ? 0.0f : (i % 3 == 1 ? 1.0f : static_cast<float>(u(rng)));
    const pbr::ShadingMaterial m = material(base, metallic, static_cast<float>(u(rng)));
    // Random normal; l and v in its hemisphere, above the n·x = kMinNoV clamp.
    const glm::dvec3 n = polar(std::acos(2 * u(rng) - 1), 2 * kPi * u(rng));
    glm::dvec3 t, b;
    frame(n, t, b);
    auto around_n = [&] {
      const glm::dvec3 d = polar(std::acos(0.001 + 0.999 * u(rng)), 2 * kPi * u(rng));
      return glm::vec3(glm::normalize(d.x * t + d.y * b + d.z * n));
    };
    const glm::vec3 nf(n), l = around_n(), v = around_n();
    if (glm::dot(nf, l) <= 2 * pbr::kMinNoV || glm::dot(nf, v) <= 2 * pbr::kMinNoV) continue;
    const glm::vec3 a = pbr::brdf(m, nf, l, v), c = pbr::brdf(m, nf, v, l);
    for (int k = 0; k < 3; ++k) {
      const double rel = std::fabs(a[k] - c[k]) / std::max(std::fabs(static_cast<double>(c[k])), 1e-30);
      worst = std::max(worst, rel);
      CHECK_MESSAGE(rel < 1e-4, "sample " << i << " channel " << k << ": " << a[k] << " vs " << c[k]);
    }
  }
  MESSAGE("reciprocity: worst relative difference " << worst);
}

namespace {

// ∫ f(l) dω_l over the whole sphere in spherical coordinates (θ', φ') around `pole`:
// θ' = π s³ grades the nodes towards the pole, where the specular lobe sits (width ≈ 2α),
// so that even α = 0.002 has > 30 of them across the lobe; Simpson in s, the periodic
// trapezoid rule in φ'. Accumulated in double.
template <class F>
double sphere_integral(const glm::dvec3& pole, F&& f) {
  constexpr int kS = 1000, kPhi = 256;
  glm::dvec3 t, b;
  frame(pole, t, b);
  double sum = 0;
  for (int i = 1; i <= kS; ++i) {  // s = 0 contributes sin θ' = 0
    const double s = static_cast<double>(i) / kS;
    const double theta = kPi * s * s * s;
    const double w = (i == kS ? 1 : (i % 2 ? 4 : 2)) * std::sin(theta) * 3 * kPi * s * s;
    double ring = 0;
    for (int j = 0; j < kPhi; ++j) {
      const double phi = 2 * kPi * (j + 0.5) / kPhi;
      const glm::dvec3 d = polar(theta, phi);
      ring += f(d.x * t + d.y * b + d.z * pole);
    }
    sum += w * ring;
  }
  return sum * (1.0 / (3 * kS)) * (2 * kPi / kPhi);
}

// Directional albedo A(v) = ∫ f(l, v) (n·l) dω_l of pbr::brdf (red channel), n = +z,
// integrated around the mirror direction of v.
double albedo(const pbr::ShadingMaterial& m, double view_theta) {
  const glm::dvec3 n(0, 0, 1), v = polar(view_theta, 0.0);
  return sphere_integral(2 * v.z * n - v, [&](const glm::dvec3& l) {
    if (l.z <= 0) return 0.0;
    return static_cast<double>(pbr::brdf(m, glm::vec3(n), glm::vec3(l), glm::vec3(v)).r) * l.z;
  });
}

}  // namespace

TEST_CASE("white furnace: the directional albedo of a white metal is <= 1 at every view angle and roughness") {
  // The quadrature resolves the sharpest lobe: ∫ D(h)(n·h) / (4 v·h) dω_l = ∫ D (n·h) dω_h
  // = 1 (dω_h = dω_l / (4 v·h)) at kMinRoughness, for views where no h has v·h ≤ 0.
  for (double view_deg : {0.0, 60.0}) {
    const double alpha = double(pbr::kMinRoughness) * pbr::kMinRoughness;
    const glm::dvec3 n(0, 0, 1), v = polar(view_deg * kPi / 180, 0.0);
    const double one = sphere_integral(2 * v.z * n - v, [&](const glm::dvec3& l) {
      const glm::dvec3 h = glm::normalize(l + v);
      return h.z > 0 ? pbr::D_GGX(h.z, alpha) * h.z / (4 * glm::dot(v, h)) : 0.0;
    });
    CAPTURE(view_deg);
    CHECK(std::fabs(one - 1) < 1e-4);
  }
  // Analytic landmark: at roughness 1 (α = 1, D = 1/π, k = 1/2, G1(x) = 2x/(1 + x)) a white
  // metal seen head-on reflects ∫ (n·l)/(2π(1 + n·l)) dω_l = 1 − ln 2.
  CHECK(albedo(material({1, 1, 1}, 1.0f, 1.0f), 0.0) == doctest::Approx(1 - std::log(2.0)).epsilon(1e-4));

  // Tolerance: 1e-3 for the quadrature and float shading; 5e-3 at roughness < 0.1, where
  // n·h of the float shading vectors is quantised (2⁻²⁴ against 1 − n·h ≈ α²) across the
  // whole lobe and the head-on albedo comes out up to 0.4% high (in double it is 0.99998).
  const double view_degrees[] = {0, 30, 60, 70, 75, 80, 85, 89, 89.9, 90};
  const float roughnesses[] = {0.0f, 0.05f, 0.1f, 0.25f, 0.5f, 0.75f, 1.0f};
  double worst = 0, normal_r1 = 0, grazing_r1 = 0;
  for (float r : roughnesses)
    for (double deg : view_degrees) {
      const double a = albedo(material({1, 1, 1}, 1.0f, r), deg * kPi / 180);
      CAPTURE(r);
      CAPTURE(deg);
      CHECK(a <= 1.0 + (r < 0.1f ? 5e-3 : 1e-3));
      CHECK(a >= 0.0);
      worst = std::max(worst, a);
      if (r == 1.0f && deg == 0) normal_r1 = a;
      if (r == 1.0f && deg == 85) grazing_r1 = a;
    }
  MESSAGE("white furnace, white metal: largest directional albedo " << worst << "; at roughness 1 it reflects "
                                                                    << normal_r1 << " head-on (loses "
                                                                    << 100 * (1 - normal_r1) << "%) and " << grazing_r1
                                                                    << " at 85 degrees (loses "
                                                                    << 100 * (1 - grazing_r1)
                                                                    << "%): single-scattering GGX drops the energy of "
                                                                       "multiple bounces between microfacets");
}

TEST_CASE("white furnace: a white dielectric stays <= 1 from roughness 0.5 and within 10% everywhere") {
  // kD = (1 − F(v·h))(1 − metallic) (the paper's model, as LearnOpenGL) weights the diffuse term by
  // the Fresnel of each light's half vector, not by what the specular lobe really took for
  // this view. At grazing views of a smooth surface the specular lobe reflects F(n·v) while
  // light from near the normal has v·h ≈ cos 40° and keeps nearly all its diffuse weight:
  // the sum exceeds 1, by up to 9.4% (roughness 0, view 80°). This pins that excess down
  // (it must not grow) and checks that rough dielectrics conserve energy.
  const double view_degrees[] = {0, 30, 60, 70, 75, 80, 85, 89, 89.9, 90};
  const float roughnesses[] = {0.0f, 0.05f, 0.1f, 0.25f, 0.5f, 0.75f, 1.0f};
  double worst = 0, worst_r = 0, worst_deg = 0;
  for (float r : roughnesses)
    for (double deg : view_degrees) {
      const double a = albedo(material({1, 1, 1}, 0.0f, r), deg * kPi / 180);
      CAPTURE(r);
      CAPTURE(deg);
      CHECK(a <= (r >= 0.5f ? 1.0 + 1e-3 : 1.10));
      CHECK(a > 0.9);  // the diffuse term alone keeps most of the light
      if (a > worst) worst = a, worst_r = r, worst_deg = deg;
    }
  MESSAGE("white furnace, white dielectric: largest directional albedo " << worst << " at roughness " << worst_r
                                                                         << ", view " << worst_deg
                                                                         << " degrees (kD = 1 - F(v.h) is not energy "
                                                                            "conserving at grazing views)");
}

TEST_CASE("shade() and brdf() stay finite and non-negative at grazing angles, roughness 0 and 1, "
          "normals facing away or zero, and a light at the surface point") {
  // Unit directions around +z (the geometric normal) from head-on to grazing and beyond.
  std::vector<glm::vec3> dirs;
  for (double deg : {0.0, 1e-3, 30.0, 60.0, 85.0, 89.0, 89.99, 90.0, 90.01, 95.0, 135.0, 180.0})
    for (double phi : {0.0, 1.3, 3.14159265358979})
      dirs.push_back(glm::vec3(polar(deg * kPi / 180, phi)));
  dirs.push_back({1, 0, 0});  // exactly in the tangent plane: n·x = 0 exactly
  std::vector<glm::vec3> normals = {{0, 0, 1}, {0, 0, -1}, {0, 0, 0}, {0, 0, 1e-30f}, {0, 0, 3}, {1, 0, 0}};
  normals.push_back(glm::vec3(std::numeric_limits<float>::quiet_NaN()));

  std::vector<pbr::PreparedLight> lights;
  const glm::vec3 p(0.25f, -0.5f, 1.0f);
  for (const glm::vec3 at : {p, p + glm::vec3(0, 0, 1e-6f), p + glm::vec3(1e-3f, 0, 0), p + glm::vec3(0, 2, 0.01f)}) {
    pbr::Light l;
    l.position = at;  // the first one exactly at the surface point
    l.intensity = 100.0f;
    lights.push_back(pbr::prepare_light(l));
  }
  pbr::Light sun;
  sun.type = pbr::LightType::Directional;
  sun.direction = {0, 0, -1};
  lights.push_back(pbr::prepare_light(sun));
  sun.direction = {-1, 0, 0};  // grazing: along the tangent plane
  lights.push_back(pbr::prepare_light(sun));
  pbr::Light spot;
  spot.type = pbr::LightType::Spot;
  spot.position = p;
  spot.inner_cone = 0.0f;
  spot.outer_cone = 1e-6f;
  lights.push_back(pbr::prepare_light(spot));

  // Failures are counted and the first of each kind reported, not one line per sample.
  int evaluated = 0, bad_shade = 0, bad_brdf = 0;
  std::ostringstream first_shade, first_brdf;
  auto show = [](std::ostream& os, const glm::vec3& x) { os << "(" << x.x << ", " << x.y << ", " << x.z << ")"; };
  for (float r : {0.0f, 1e-7f, pbr::kMinRoughness, 0.5f, 1.0f})
    for (float metallic : {0.0f, 0.5f, 0.8f, 1.0f})
      // A base colour above 1 is accepted by prepare_material; with metallic 0.8 it makes
      // F0 = 1.2 > 1, and the diffuse weight 1 − F must not turn negative.
      for (const glm::vec3 base : {glm::vec3(0.0f), glm::vec3(1.0f), glm::vec3(1.0f, 0.71f, 0.29f), glm::vec3(1.5f)}) {
        const pbr::ShadingMaterial m = material(base, metallic, r);
        CHECK(m.roughness == std::max(r, pbr::kMinRoughness));
        for (const glm::vec3& v : dirs)
          for (const glm::vec3& n_in : normals) {
            const glm::vec3 c = pbr::shade(m, lights, glm::vec3(0.03f), p, n_in, v);
            if (!finite_nonneg(c) && bad_shade++ == 0) {
              first_shade << "roughness " << r << ", metallic " << metallic << ", base ";
              show(first_shade, base);
              first_shade << ", v ";
              show(first_shade, v);
              first_shade << ", n ";
              show(first_shade, n_in);
              first_shade << " -> ";
              show(first_shade, c);
            }
            const glm::vec3 n = pbr::normalize_or(n_in, v);
            for (const glm::vec3& l : dirs) {
              const glm::vec3 f = pbr::brdf(m, n, l, v);
              ++evaluated;
              if (!finite_nonneg(f) && bad_brdf++ == 0) {
                first_brdf << "roughness " << r << ", metallic " << metallic << ", base ";
                show(first_brdf, base);
                first_brdf << ", n.l " << glm::dot(n, l) << ", n.v " << glm::dot(n, v) << " -> ";
                show(first_brdf, f);
              }
            }
          }
      }
  CHECK_MESSAGE(bad_shade == 0, bad_shade << " bad shade() results, the first: " << first_shade.str());
  CHECK_MESSAGE(bad_brdf == 0, bad_brdf << " bad brdf() results, the first: " << first_brdf.str());
  MESSAGE(evaluated << " brdf evaluations, all finite and non-negative");
}

TEST_CASE("prepare_material rejects out-of-range or non-finite fields, naming the field") {
  struct Bad {
    const char* field;
    void (*spoil)(pbr::Material&);
  };
  const Bad cases[] = {
      {"roughness", [](pbr::Material& m) { m.roughness = 2.0f; }},
      {"roughness", [](pbr::Material& m) { m.roughness = -0.1f; }},
      {"metallic", [](pbr::Material& m) { m.metallic = std::numeric_limits<float>::quiet_NaN(); }},
      {"metallic", [](pbr::Material& m) { m.metallic = 1.5f; }},
      {"base_color", [](pbr::Material& m) { m.base_color = {0.5f, -0.01f, 0.5f}; }},
      {"base_color", [](pbr::Material& m) { m.base_color.b = std::numeric_limits<float>::infinity(); }},
      {"emissive", [](pbr::Material& m) { m.emissive = {-1.0f, 0.0f, 0.0f}; }},
      {"ao", [](pbr::Material& m) { m.ao = std::numeric_limits<float>::quiet_NaN(); }},
  };
  for (const Bad& b : cases) {
    pbr::Material m;
    b.spoil(m);
    CAPTURE(b.field);
    CHECK_THROWS_WITH_AS(pbr::prepare_material(m), doctest::Contains(b.field), std::invalid_argument);
  }
  // The boundaries themselves are valid.
  for (float x : {0.0f, 1.0f}) {
    pbr::Material m;
    m.roughness = m.metallic = m.ao = x;
    CHECK_NOTHROW(pbr::prepare_material(m));
  }
}
