// softpbr/pbr/environment.h — image-based lighting: an HDR environment prefiltered for the
// split-sum approximation (Karis 2013), and its lookups in lane form.
//
// The shaders' side — the environment prepared for a frame and its lookups in lane form —
// is environment_lookup.h (included here), which needs no more of this class than its
// name: the tile kernels include that header alone, so a change here recompiles what loads
// and prefilters environments, not every kernel.
//
// An Environment is built once from an equirectangular linear image (an .hdr or .exr)
// and is then immutable, shared between frames, renders and threads:
//   - diffuse: the irradiance map, an octahedral map (kIrradianceSize a side) of the map's
//     exact convolution with the clamped cosine, divided by π, so irradiance(n) is the
//     radiance a white Lambertian surface with normal n reflects;
//   - specular: kLevels octahedral maps of the radiance prefiltered with the GGX lobe of
//     α = kEnvironmentLevelAlpha[i] (level 0 is the map itself), each sized to its lobe,
//     importance-sampled with a fixed Hammersley set and filtered importance sampling
//     (Křivánek & Colbert 2008), so a sun of radiance in the thousands gives a smooth
//     highlight;
//   - dfg_table(): the BRDF integration table (A, B) of the split sum, computed by the
//     library, with Smith–Schlick-GGX visibility at k = α/2 (α = roughness²).
// docs/design.md, "Image-based lighting", has the maths, the conventions and the
// measured errors.
//
// Conventions: +Y is up. Direction d = (x, y, z) reads the equirectangular image at
//   u = 1/2 + atan2(x, −z) / 2π,   v = atan2(√(x² + z²), y) / π   (v = 0 the top row),
// so the image's centre column is seen looking down −Z (the default camera's view) and
// +X is to its right. A rotation θ turns the environment about +Y, counter-clockwise
// seen from above: what was at −Z appears toward −X after 90°.
//
// Everything is computed with IEEE basic operations and dmath in a fixed order, the work
// split by rows over the pool: the same bits for any thread count and on every platform.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "softpbr/image/image.h"
#include "softpbr/pbr/environment_lookup.h"
#include "softpbr/raster/pool.h"
#include "softpbr/raster/texture.h"
#include "softpbr/simd/simd.h"

namespace softpbr::pbr {

struct EnvironmentOptions {
  // Side of the octahedral map the equirectangular image is resampled to (level 0, the
  // mirror reflection and the background): a power of two in [8, 2048]; 0 chooses from
  // the image, the largest power of two ≤ √(width × height), at most 1024.
  int size = 0;
  // GGX samples per texel of the prefiltered level of α = 0.05 (roughness 0.22); the
  // narrower levels take a half and a quarter of it (at least 8), each wider level twice
  // the last, up to 8×: [8, 4096].
  int samples = 64;

  bool operator==(const EnvironmentOptions&) const = default;
};

// Throws std::invalid_argument naming the field.
void validate(const EnvironmentOptions& options);

class Environment {
 public:
  static constexpr int kLevels = kEnvironmentLevels;  // prefiltered levels, kEnvironmentLevelAlpha

  // Prefilters an equirectangular linear RGB image (alpha is ignored) of any size from
  // 1×1. Throws std::invalid_argument naming `name` for non-finite or negative values or
  // a bad size; the work runs on `pool` when given (the same bits either way).
  Environment(const image::ImageViewF& equirect, std::string name, const EnvironmentOptions& options = {},
              raster::ThreadPool* pool = nullptr);

  // A studio: a soft grey dome, a darker floor and three softboxes (key, fill, rim),
  // built procedurally (no file, the same bits everywhere), prefiltered at size 128. What `softpbr render
  // model.glb` lights a model with when no environment is given. Built once per process,
  // on the first caller's `pool` when it gives one (the same bits either way).
  static std::shared_ptr<const Environment> studio(raster::ThreadPool* pool = nullptr);

  // The equirectangular image studio() prefilters (width × height, linear).
  static image::ImageF studio_image(int width = 512, int height = 256);

  const std::string& name() const { return name_; }
  const EnvironmentOptions& options() const { return options_; }
  int size() const { return size_; }

  // The irradiance map / π: kIrradianceSize a side and a one-texel border (looked up as
  // the levels are, env_irradiance).
  const raster::Texture& irradiance() const { return *irradiance_; }
  // Level i: the octahedral map prefiltered at α = kEnvironmentLevelAlpha[i], stored with a
  // one-texel border (size + 2 texels a side) so that bilinear lookups wrap as the sphere
  // does; lookups go through env_bilinear (the same filter as raster::sample_lod with
  // level_sampler(): bilinear, clamp to edge).
  const raster::Texture& level(int i) const { return *levels_[static_cast<std::size_t>(i)]; }
  int level_size(int i) const { return level(i).width() - 2; }
  static const raster::Sampler& level_sampler();

  // The side of level i for a map of side `size`: the map's for level 0, else the largest
  // power of two ≤ 8 / α (about 4 texels across the lobe), in [32, size].
  static int level_side(int size, int i);

  // Bytes held (the levels' and the irradiance map's texels).
  std::size_t bytes() const;

  // The serialized form for a disk cache, and back: a versioned binary blob (header, the
  // key of what it was made from, options, the irradiance map, the levels) ending with a
  // checksum of everything before it. `key` is the caller's (load_environment: the source
  // file's hash and length). from_bytes throws std::invalid_argument naming `name` when
  // the blob is truncated, of another version, made from another key, damaged (the
  // checksum), or holds sizes that disagree or values that are not finite and ≥ 0.
  std::vector<std::uint8_t> to_bytes(std::uint64_t key = 0) const;
  static std::shared_ptr<const Environment> from_bytes(std::span<const std::uint8_t> bytes, std::string name,
                                                       std::uint64_t key = 0);

 private:
  Environment() = default;
  std::string name_;
  EnvironmentOptions options_;
  int size_ = 0;
  std::shared_ptr<const raster::Texture> irradiance_;
  std::vector<std::shared_ptr<const raster::Texture>> levels_;
};

// Loads an .hdr or .exr (by content) and prefilters it. Cached in memory by the file's
// content hash and the options: the same file gives the same shared Environment across
// renders. With a non-empty `cache_dir`, the prefiltered result is also stored there (and
// read back) as <hash>-<options>.spenv, written atomically. A cache entry is used only when
// it verifies (Environment::from_bytes: its version, the key of this file's bytes and the
// options, its checksum, finite values); one that does not — damaged, stale, another map's,
// not a regular file — is ignored, the map prefiltered again and the entry replaced where
// the folder allows. A cache folder that cannot be made or written is one line in
// `warnings` (when given) and the load goes on. Throws std::runtime_error /
// std::invalid_argument naming the file for the map itself.
std::shared_ptr<const Environment> load_environment(const std::filesystem::path& path,
                                                    const EnvironmentOptions& options = {},
                                                    raster::ThreadPool* pool = nullptr,
                                                    const std::filesystem::path& cache_dir = {},
                                                    const image::Limits& limits = {},
                                                    std::vector<std::string>* warnings = nullptr);

// Direction ↔ octahedral coordinates in [0, 1]² (+Y at the centre, −Y at the corners).
glm::dvec2 octahedral_encode(const glm::dvec3& d);
glm::dvec3 octahedral_decode(const glm::dvec2& uv);  // unit length
// The equirectangular coordinates of a direction (see the header comment).
glm::dvec2 equirect_uv(const glm::dvec3& d);

}  // namespace softpbr::pbr
