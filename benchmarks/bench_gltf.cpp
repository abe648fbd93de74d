// bench_gltf — what `softpbr render model.glb -o out.png --width 1920 --height 1080` spends
// its time on, stage by stage (issue 14, "Speed").
//
//   bench_gltf [--benchmark_filter=WaterBottle] [--benchmark_min_time=1]
//
// The models: WaterBottle, MetalRoughSpheresNoTextures and DamagedHelmet from
// ../shared/gltf (SOFTPBR_SHARED_GLTF points elsewhere), each skipped with a note when
// absent. Every stage runs on 2 threads (a raster::ThreadPool of 2, or a Renderer of 2),
// as the command does on the 2-core machine; one iteration is:
//   load/M        pbr::load_gltf(file, {.pool}): everything the command's load does (read,
//                 parse, validate, geometry, tangents, image decode, mip chains)
//   parse/M       tinygltf alone, configured as the loader configures it (the file and its
//                 buffers read, the JSON parsed, images in buffers kept encoded, image
//                 files left unread: since 2026-12-04 the loader reads those itself, on
//                 the pool): the part of load/M before softpbr's own work
//   decode/M      image::load_image8 of every image the model's materials use, on the pool
//                 (one job per image, as the loader)
//   mips/M        raster::Texture of every decoded image in the colour space its slot
//                 gives it (the mip chain), on the pool (one job per texture, as the loader)
//   prefilter     the studio environment the command lights a model with
//                 (Environment::studio(): studio_image() prefiltered), /threads:1 as
//                 studio() builds it (no pool), /threads:2 on a pool
//   frame/M/msaa  pbr::render of gltf_scene_file()'s scene (framing camera, studio
//                 environment, blurred background) into a 1920×1080 Target of 1 or 4
//                 samples, the Target made once
//   output/M      what the command does after the frame: tone_map_to_rgba8 and encode_png
//                 of the 1× frame
// The whole command (process start to PNG) is timed by benchmarks/time_render.sh.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "gltf/tinygltf.h"
#include "softpbr/image/load.h"
#include "softpbr/image/write.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/pbr/environment.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/raster.h"

namespace fs = std::filesystem;
namespace image = softpbr::image;
namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;

namespace {

constexpr unsigned kThreads = 2;
constexpr int kWidth = 1920, kHeight = 1080;

fs::path shared_gltf() {
  if (const char* env = std::getenv("SOFTPBR_SHARED_GLTF")) return env;
  return fs::path(SOFTPBR_SOURCE_DIR) / ".." / "shared" / "gltf";
}

// The model file of a sample folder: its glTF-Binary .glb, else its glTF .gltf.
fs::path model_file(const fs::path& folder) {
  for (const char* sub : {"glTF-Binary", "glTF"}) {
    const fs::path dir = folder / sub;
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) continue;
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().extension() == ".glb" || e.path().extension() == ".gltf") return e.path();
  }
  return {};
}

// A model's images as the loader sees them: encoded bytes, decoded pixels, the colour
// space of the slots that use them (an image used as sRGB and linear appears twice).
struct Model {
  std::string name;
  fs::path file;
  std::vector<std::vector<std::uint8_t>> encoded;  // every image a material uses
  std::vector<image::Image8> decoded;              // the same, decoded
  std::vector<std::pair<std::size_t, raster::ColorSpace>> textures;  // (decoded index, space)
  pbr::SceneFile scene;                                             // as the command renders it
};

bool keep_encoded(tinygltf::Image* im, const int, std::string*, std::string*, int, int, const unsigned char* bytes,
                  int size, void*) {
  im->image.assign(bytes, bytes + size);
  return true;
}

bool parse(const fs::path& file, tinygltf::Model& model) {
  tinygltf::TinyGLTF parser;
  parser.SetImageLoader(&keep_encoded, nullptr);
  std::string err, warn;
  return file.extension() == ".glb" ? parser.LoadBinaryFromFile(&model, &err, &warn, file.string())
                                    : parser.LoadASCIIFromFile(&model, &err, &warn, file.string());
}

Model prepare(const std::string& name, const fs::path& file, raster::ThreadPool& pool) {
  Model m;
  m.name = name;
  m.file = file;
  tinygltf::Model g;
  if (!parse(file, g)) throw std::runtime_error(file.string() + ": tinygltf cannot parse it");
  // The images the materials use, with their slots' colour spaces (glTF: base colour and
  // emissive are sRGB, the rest linear).
  std::set<std::pair<int, raster::ColorSpace>> uses;
  auto use = [&](int texture, raster::ColorSpace space) {
    if (texture < 0 || static_cast<std::size_t>(texture) >= g.textures.size()) return;
    const int source = g.textures[static_cast<std::size_t>(texture)].source;
    if (source >= 0) uses.insert({source, space});
  };
  using CS = raster::ColorSpace;
  for (const tinygltf::Material& mat : g.materials) {
    use(mat.pbrMetallicRoughness.baseColorTexture.index, CS::Srgb);
    use(mat.pbrMetallicRoughness.metallicRoughnessTexture.index, CS::Linear);
    use(mat.normalTexture.index, CS::Linear);
    use(mat.occlusionTexture.index, CS::Linear);
    use(mat.emissiveTexture.index, CS::Srgb);
  }
  std::map<int, std::size_t> image_of;
  for (const auto& u : uses) {
    auto it = image_of.find(u.first);
    if (it == image_of.end()) {
      it = image_of.emplace(u.first, m.encoded.size()).first;
      const tinygltf::Image& im = g.images[static_cast<std::size_t>(u.first)];
      // An image in its own file: softpbr's tinygltf leaves it unread (the loader reads it;
      // the sample models' URIs need no percent-decoding).
      m.encoded.push_back(im.image.empty() ? image::read_file(file.parent_path() / im.uri) : im.image);
    }
    m.textures.push_back({it->second, u.second});
  }
  for (const auto& bytes : m.encoded) m.decoded.push_back(image::load_image8(bytes, name));
  pbr::GltfView view;
  view.width = kWidth;
  view.height = kHeight;
  m.scene = pbr::gltf_scene_file(pbr::load_gltf(file, {.pool = &pool}), view, file.string());
  return m;
}

void load(benchmark::State& state, const Model* m) {
  raster::ThreadPool pool(kThreads);
  for (auto _ : state) {
    pbr::GltfScene g = pbr::load_gltf(m->file, {.pool = &pool});
    benchmark::DoNotOptimize(g.objects.data());
  }
}

void parse_only(benchmark::State& state, const Model* m) {
  for (auto _ : state) {
    tinygltf::Model g;
    if (!parse(m->file, g)) state.SkipWithError("tinygltf cannot parse it");
    benchmark::DoNotOptimize(g.buffers.data());
  }
}

void decode(benchmark::State& state, const Model* m) {
  raster::ThreadPool pool(kThreads);
  std::vector<image::Image8> out(m->encoded.size());
  for (auto _ : state) {
    pool.parallel_for(m->encoded.size(), [&](std::size_t i) { out[i] = image::load_image8(m->encoded[i], m->name); });
    benchmark::DoNotOptimize(out.data());
  }
  double texels = 0;
  for (const image::Image8& im : m->decoded) texels += static_cast<double>(im.width) * im.height;
  state.counters["images"] = static_cast<double>(m->encoded.size());
  state.counters["Mtexels"] = texels / 1e6;
}

void mips(benchmark::State& state, const Model* m) {
  raster::ThreadPool pool(kThreads);
  std::vector<std::shared_ptr<const raster::Texture>> out(m->textures.size());
  for (auto _ : state) {
    pool.parallel_for(m->textures.size(), [&](std::size_t i) {
      out[i] = std::make_shared<const raster::Texture>(m->decoded[m->textures[i].first], m->textures[i].second);
    });
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["textures"] = static_cast<double>(m->textures.size());
}

void prefilter(benchmark::State& state) {
  const unsigned threads = static_cast<unsigned>(state.range(0));
  std::unique_ptr<raster::ThreadPool> pool;
  if (threads > 1) pool = std::make_unique<raster::ThreadPool>(threads);
  for (auto _ : state) {
    const image::ImageF im = pbr::Environment::studio_image();
    pbr::Environment env(image::ImageViewF(im), "studio", {}, pool.get());
    benchmark::DoNotOptimize(env.irradiance());
  }
}

void frame(benchmark::State& state, const Model* m) {
  const int samples = static_cast<int>(state.range(0));
  raster::Renderer renderer(raster::RendererOptions{.threads = kThreads});
  raster::Target target(kWidth, kHeight, samples);
  for (auto _ : state) {
    pbr::render(m->scene.scene, renderer, target);
    benchmark::DoNotOptimize(target.colors().data());
  }
  state.counters["triangles"] = static_cast<double>(m->scene.triangles);
}

void output(benchmark::State& state, const Model* m) {
  raster::Renderer renderer(raster::RendererOptions{.threads = kThreads});
  raster::Target target(kWidth, kHeight);
  pbr::render(m->scene.scene, renderer, target);
  for (auto _ : state) {
    const std::vector<std::uint8_t> png =
        image::encode_png(pbr::tone_map_to_rgba8(target, m->scene.render.output), "out.png");
    benchmark::DoNotOptimize(png.data());
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  static std::vector<std::unique_ptr<Model>> models;
  {
    raster::ThreadPool pool(kThreads);
    for (const char* name : {"WaterBottle", "MetalRoughSpheresNoTextures", "DamagedHelmet"}) {
      const fs::path file = model_file(shared_gltf() / name);
      if (file.empty()) {
        std::fprintf(stderr, "note: %s not found in %s: its benchmarks are skipped\n", name, shared_gltf().string().c_str());
        continue;
      }
      models.push_back(std::make_unique<Model>(prepare(name, file, pool)));
    }
  }
  auto ms = [](benchmark::internal::Benchmark* b) {
    return b->UseRealTime()->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);
  };
  for (const auto& m : models) {
    const Model* p = m.get();
    ms(benchmark::RegisterBenchmark(("load/" + m->name).c_str(), load, p));
    ms(benchmark::RegisterBenchmark(("parse/" + m->name).c_str(), parse_only, p));
    if (!m->encoded.empty()) {
      ms(benchmark::RegisterBenchmark(("decode/" + m->name).c_str(), decode, p));
      ms(benchmark::RegisterBenchmark(("mips/" + m->name).c_str(), mips, p));
    }
  }
  ms(benchmark::RegisterBenchmark("prefilter/studio", prefilter)->ArgName("threads")->Arg(1)->Arg(2));
  for (const auto& m : models) {
    const Model* p = m.get();
    ms(benchmark::RegisterBenchmark(("frame/" + m->name).c_str(), frame, p)->ArgName("msaa")->Arg(1)->Arg(4));
    ms(benchmark::RegisterBenchmark(("output/" + m->name).c_str(), output, p));
  }
  if (models.empty()) std::fprintf(stderr, "note: no model of %s found: only the prefilter runs\n", shared_gltf().string().c_str());
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
