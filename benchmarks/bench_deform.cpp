// bench_deform — a glTF skin and morph target applied on the CPU (issue 50).
//
//   bench_deform [--benchmark_filter=normals] [--benchmark_min_time=1]
//
// One iteration is gltf::deform of a synthetic mesh of 1,048,576 vertices
// (tests/synthetic_rig.h): one morph target moving positions and normals, then four
// influences per vertex (every fourth vertex three) over 64 joints, written into a mesh
// allocated once (what posing a loaded model again does: positions, normals and tangents
// written, nothing else copied). On a raster::ThreadPool of `threads` threads (1: no
// pool). `deform_1M/normals/...` has positions and normals; `deform_1M/tangents/...`
// tangents too, and a vertex → accessor map (as a primitive with split tangents has).
// The counter `vertices` is vertices per second of wall time; "CPU" is the whole
// process's CPU time. Issue 50's target: ≤ 20 ms at 2 threads. `deform_1M_double_baseline`
// is the first form of the deformation (double, per-vertex inverse transpose, two whole
// copies of the mesh), for comparison in the same run.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include <glm/mat3x3.hpp>

#include "softpbr/raster/pool.h"
#include "synthetic_rig.h"

namespace gltf = softpbr::pbr::gltf;
namespace raster = softpbr::raster;

namespace {

constexpr std::size_t kVertices = std::size_t{1} << 20;

void deform_1M(benchmark::State& state, bool tangents) {
  const unsigned threads = static_cast<unsigned>(state.range(0));
  std::optional<raster::ThreadPool> pool;
  if (threads > 1) pool.emplace(threads);
  const std::unique_ptr<softpbr::testing::SyntheticRig> rig = softpbr::testing::synthetic_rig(kVertices, 64, tangents, tangents);
  softpbr::pbr::Mesh out = rig->base;
  for (auto _ : state) {
    gltf::deform(rig->base, rig->deformation, out, pool ? &*pool : nullptr);
    benchmark::DoNotOptimize(out.vertices.data());
    benchmark::ClobberMemory();
  }
  state.counters["vertices"] = benchmark::Counter(static_cast<double>(state.iterations()) * kVertices,
                                                  benchmark::Counter::kIsRate);
}

// The baseline: deformation as it was first written (issue 50, part 1), kept here to
// measure against — a copy of the whole mesh, the morph in double into it, a second copy,
// then per vertex the 4×4 skin matrix Σ wⱼ·Jⱼ in double and its inverse transpose (the
// loader's normal_matrix: nine cofactors and a division) for the normal.
softpbr::pbr::Mesh deform_double(const softpbr::testing::SyntheticRig& rig, raster::ThreadPool* pool) {
  const softpbr::pbr::Mesh& base = rig.base;
  const gltf::Deformation& d = rig.deformation;
  const gltf::SkinInfluences& k = rig.skin;
  softpbr::pbr::Mesh out = base;
  const std::size_t n = base.vertices.size(), block = 4096, tasks = (n + block - 1) / block;
  const bool tangents = !base.tangents.empty(), has_sources = !rig.sources.empty();
  auto for_tasks = [&](auto&& fn) {
    if (pool != nullptr) pool->parallel_for(tasks, [&](std::size_t t) { fn(t); });
    else
      for (std::size_t t = 0; t < tasks; ++t) fn(t);
  };
  for_tasks([&](std::size_t task) {
    for (std::size_t i = task * block; i < std::min(n, task * block + block); ++i) {
      const std::size_t s = has_sources ? rig.sources[i] : i;
      glm::dvec3 p(base.vertices[i].position), nn(base.vertices[i].normal);
      glm::dvec3 t = tangents ? glm::dvec3(base.tangents[i]) : glm::dvec3(0.0);
      for (const gltf::MorphTarget& m : d.targets) {
        if (m.position) p += m.weight * glm::dvec3(m.position[3 * s], m.position[3 * s + 1], m.position[3 * s + 2]);
        if (m.normal) nn += m.weight * glm::dvec3(m.normal[3 * s], m.normal[3 * s + 1], m.normal[3 * s + 2]);
        if (m.tangent && tangents) t += m.weight * glm::dvec3(m.tangent[3 * s], m.tangent[3 * s + 1], m.tangent[3 * s + 2]);
      }
      out.vertices[i].position = glm::vec3(p);
      out.vertices[i].normal = glm::vec3(nn);
      if (tangents) out.tangents[i] = glm::vec4(glm::vec3(t), base.tangents[i].w);
    }
  });
  const softpbr::pbr::Mesh morphed = out;
  for_tasks([&](std::size_t task) {
    for (std::size_t i = task * block; i < std::min(n, task * block + block); ++i) {
      const std::size_t s = has_sources ? rig.sources[i] : i;
      glm::dmat4 M(0.0);
      for (std::size_t j = 0; j < k.influences; ++j) {
        const double w = k.weights[s * k.influences + j];
        if (w == 0.0) continue;
        const glm::dmat4& J = rig.joint_matrices[k.joints[s * k.influences + j]];
        for (int c = 0; c < 4; ++c) M[c] += w * J[c];
      }
      const softpbr::pbr::MeshVertex& v = morphed.vertices[i];
      out.vertices[i].position = glm::vec3(glm::dvec3(M * glm::dvec4(glm::dvec3(v.position), 1.0)));
      out.vertices[i].normal = glm::vec3(gltf::normal_matrix(M) * glm::dvec3(v.normal));
      if (tangents) {
        const glm::vec4& t = morphed.tangents[i];
        out.tangents[i] = glm::vec4(glm::vec3(glm::dmat3(M) * glm::dvec3(t.x, t.y, t.z)), t.w);
      }
    }
  });
  return out;
}

void deform_1M_double_baseline(benchmark::State& state, bool tangents) {
  const unsigned threads = static_cast<unsigned>(state.range(0));
  std::optional<raster::ThreadPool> pool;
  if (threads > 1) pool.emplace(threads);
  const std::unique_ptr<softpbr::testing::SyntheticRig> rig = softpbr::testing::synthetic_rig(kVertices, 64, tangents, tangents);
  for (auto _ : state) {
    softpbr::pbr::Mesh out = deform_double(*rig, pool ? &*pool : nullptr);
    benchmark::DoNotOptimize(out.vertices.data());
  }
  state.counters["vertices"] = benchmark::Counter(static_cast<double>(state.iterations()) * kVertices,
                                                  benchmark::Counter::kIsRate);
}

}  // namespace

BENCHMARK_CAPTURE(deform_1M_double_baseline, normals, false)->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(deform_1M, normals, false)->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(deform_1M, tangents, true)->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
