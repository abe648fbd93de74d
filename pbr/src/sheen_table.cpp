// The sheen layer's directional albedo table (environment_lookup.h, sheen_table).
#include <cmath>
#include <algorithm>
#include <cstddef>
#include <vector>

#include "softpbr/dmath/dmath.h"
#include "softpbr/pbr/brdf.h"
#include "softpbr/pbr/environment_lookup.h"

namespace softpbr::pbr {

namespace {

// E(n·v, roughness) = ∫ D_Charlie(h) V (n·l) dω_l over the hemisphere, n = z, v in the xz
// plane, with l = (sin θ cos φ, sin θ sin φ, cos θ): dω = d(cos θ) dφ. Midpoints of
// `samples` steps of cos θ in (0, 1] and of φ in [0, π] (the integrand is even in φ: twice
// the half circle). `cos_phi` and `sin_phi` hold the azimuths' cosines and sines.
double sheen_integrate(double NoV, double roughness, int samples, const std::vector<double>& cos_phi,
                       const std::vector<double>& sin_phi) {
  NoV = std::max(NoV, static_cast<double>(kMinNoV));
  const double r = std::max(roughness, static_cast<double>(kMinSheenRoughness));
  const double alpha = r * r;
  const double l_half = sheen_l(0.5, alpha);
  const double lambda_v = lambda_sheen(NoV, alpha, l_half);
  const glm::dvec3 v(std::sqrt(1.0 - NoV * NoV), 0.0, NoV);
  const double step = 1.0 / samples;
  double sum = 0.0;
  for (int i = 0; i < samples; ++i) {
    const double NoL = (i + 0.5) * step;
    const double sin_l = std::sqrt(1.0 - NoL * NoL);
    const double lambda_l = lambda_sheen(NoL, alpha, l_half);
    const double vis = V_Charlie_times_NoL(lambda_v, lambda_l, NoV, NoL);
    for (std::size_t j = 0; j < cos_phi.size(); ++j) {
      const glm::dvec3 u = glm::dvec3(sin_l * cos_phi[j], sin_l * sin_phi[j], NoL) + v;
      const double t = u.x * u.x + u.y * u.y + u.z * u.z;
      const double sin2h = (u.x * u.x + u.y * u.y) / t;
      sum += D_Charlie(sin2h, alpha) * vis;
    }
  }
  // dω = d(cos θ) dφ: each sample covers step × (π / samples), twice for the other half.
  return sum * step * (2.0 * dmath::kPi / static_cast<double>(cos_phi.size()));
}

void azimuths(int samples, std::vector<double>& cos_phi, std::vector<double>& sin_phi) {
  cos_phi.resize(static_cast<std::size_t>(samples));
  sin_phi.resize(static_cast<std::size_t>(samples));
  for (int j = 0; j < samples; ++j) {
    const double phi = (j + 0.5) * dmath::kPi / samples;
    cos_phi[static_cast<std::size_t>(j)] = dmath::cos(phi);
    sin_phi[static_cast<std::size_t>(j)] = dmath::sin(phi);
  }
}

}  // namespace

double sheen_albedo_reference(double NoV, double roughness, int samples) {
  std::vector<double> c, s;
  azimuths(samples, c, s);
  return sheen_integrate(NoV, roughness, samples, c, s);
}

const raster::Texture& sheen_table() {
  static const raster::Texture table = [] {
    std::vector<double> c, s;
    azimuths(kSheenSamples, c, s);
    std::vector<float> rgba(static_cast<std::size_t>(kSheenSize) * kSheenSize * 4);
    for (int y = 0; y < kSheenSize; ++y)
      for (int x = 0; x < kSheenSize; ++x) {
        // At most 1: the fitted Λ of the Charlie visibility lets smooth sheens seen at grazing
        // angles reflect more than arrives (E up to 3 at n·v = 0.01, roughness 0.05).
        const auto e = static_cast<float>(
            std::min(sheen_integrate((x + 0.5) / kSheenSize, (y + 0.5) / kSheenSize, kSheenSamples, c, s), 1.0));
        float* p = &rgba[(static_cast<std::size_t>(y) * kSheenSize + static_cast<std::size_t>(x)) * 4];
        p[0] = p[1] = p[2] = e;
        p[3] = 1.0f;
      }
    return raster::Texture(image::ImageViewF(kSheenSize, kSheenSize, rgba), raster::TextureOptions{.mipmaps = false});
  }();
  return table;
}

}  // namespace softpbr::pbr
