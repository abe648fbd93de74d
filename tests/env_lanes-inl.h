// env_bilinear in lane form as a kernel compiled once per target (test_environment.cpp
// includes it through softpbr/simd/foreach_target.h; no include guard, no header included
// here), as the shaders inline it.

namespace env_test::SOFTPBR_TARGET_NS {

// out[c·N + i] = channel c of env_bilinear(t, u[i], v[i]) at N lanes.
template <int N>
SOFTPBR_KERNEL void bilinear_ops(const softpbr::raster::Texture& t, const float* u, const float* v, float* out) {
  using V = softpbr::simd::SOFTPBR_TARGET_NS::Vec<N>;
  const softpbr::pbr::EnvVec3<V> c = softpbr::pbr::env_bilinear(t, V::load(u), V::load(v));
  c.x.store(out);
  c.y.store(out + N);
  c.z.store(out + 2 * N);
}

}  // namespace env_test::SOFTPBR_TARGET_NS
