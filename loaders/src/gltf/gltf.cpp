// glTF 2.0 loading (see gltf.h): the file read, its document checked and prepared
// (gltf/document.h), tinygltf's parse of the JSON and the buffers, then the scene graph
// (gltf/scene_graph.h: nodes, meshes, materials, cameras, lights, with the resources of
// gltf/resources.h), which validates everything the renderer reads against the
// specification before it is used.
#include "softpbr/loaders/gltf.h"

#include <algorithm>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "gltf/document.h"
#include "gltf/files.h"
#include "gltf/info.h"
#include "gltf/reader.h"
#include "gltf/scene_graph.h"
#include "gltf/schema.h"
#include "gltf/tinygltf.h"
#include "gltf/variants.h"
#include "softpbr/image/load.h"
#include "softpbr/image/read_file.h"
#include "softpbr/loaders/gltf_info.h"

namespace softpbr::pbr {

// What a poseable GltfScene keeps: the scene graph with everything it refers to.
class GltfPoser {
 public:
  std::string file;
  tinygltf::Model model;
  GltfOptions options;
  GltfScene scene;  // what the scene graph fills
  std::unique_ptr<gltf::SceneGraph> graph;
  std::mutex mutex;
};

namespace {

namespace tg = tinygltf;

std::vector<unsigned char> read_file(const std::filesystem::path& path, std::uint64_t limit, const std::string& what) {
  std::vector<unsigned char> bytes;
  if (const image::FileProblem p = image::read_whole_file(path, limit, bytes)) {
    if (p.too_large) throw LoadError(what + ": " + std::to_string(p.size) + " bytes is over the limit of " + std::to_string(limit));
    throw LoadError(what + ": " + p.reason);
  }
  return bytes;
}

struct FsContext {
  std::uint64_t limit;
  const std::vector<std::filesystem::path>* roots;
  std::vector<std::string> files;  // every external file read (GltfScene::files)
  std::string problem;             // the first file that could not be read: "path: reason"
  std::string problem_path;
};

// tinygltf's file reader (external buffers: images it leaves to gltf::Resources, resources.h).
bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  auto* ctx = static_cast<FsContext*>(user);
  ctx->files.push_back(path);
  if (const std::string problem = gltf::read_external(path, ctx->limit, *ctx->roots, *out); !problem.empty()) {
    if (ctx->problem.empty()) {
      ctx->problem = problem;
      ctx->problem_path = path;
    }
    if (err) *err += problem + "\n";
    return false;
  }
  return true;
}

// tinygltf's image loader callback: keeps an image's encoded bytes (softpbr::image decodes
// them later, with its checks). An image in a buffer view comes with a pointer tinygltf 2.7
// computed without checking that the view lies inside its buffer (fuzz_gltf read past a
// buffer's end): checked here, against the model tinygltf is filling (`user` is an
// ImageContext; the model's buffers and views are parsed first).
struct ImageContext {
  const tg::Model* model;
  std::vector<int> kept;  // the images whose bytes were kept, by index (for describe(), gltf/info.h)
};

bool keep_encoded(tg::Image* image, const int index, std::string* err, std::string*, int, int,
                  const unsigned char* bytes, int size, void* user) {
  auto* context = static_cast<ImageContext*>(user);
  const tg::Model* model = context->model;
  if (model != nullptr && image->bufferView >= 0) {
    const auto v = static_cast<std::size_t>(image->bufferView);
    const tg::BufferView* view = v < model->bufferViews.size() ? &model->bufferViews[v] : nullptr;
    const tg::Buffer* buffer = view != nullptr && view->buffer >= 0 &&
                                       static_cast<std::size_t>(view->buffer) < model->buffers.size()
                                   ? &model->buffers[static_cast<std::size_t>(view->buffer)]
                                   : nullptr;
    const std::size_t have = buffer != nullptr ? buffer->data.size() : 0;
    if (view == nullptr || buffer == nullptr || size < 0 || view->byteOffset > have ||
        view->byteLength > have - view->byteOffset || static_cast<std::size_t>(size) != view->byteLength) {
      if (err != nullptr) {
        *err += "/images/" + std::to_string(index) + "/bufferView: bufferView " + std::to_string(image->bufferView);
        if (view != nullptr && buffer != nullptr)
          *err += " (bytes " + std::to_string(view->byteOffset) + " to " +
                  std::to_string(static_cast<std::uint64_t>(view->byteOffset) + view->byteLength) + ")";
        *err += " does not lie inside its buffer" +
                (buffer != nullptr ? " of " + std::to_string(have) + " bytes" : std::string()) + "\n";
      }
      return false;
    }
  }
  image->image.assign(bytes, bytes + size);
  image->as_is = true;
  context->kept.push_back(index);
  return true;
}

std::string first_line(const std::string& s) {
  std::string line = s.substr(0, s.find('\n'));
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
  return line;
}

// load_gltf; with `info`, also what inspect_gltf lists of the model tinygltf parsed (with
// what the pre-pass changed put back: restore_prepass).
GltfScene load(std::span<const std::uint8_t> bytes, const std::string& file, const std::filesystem::path& base,
               const GltfOptions& options, std::optional<GltfInfo>* info) {
  if (bytes.size() > options.max_file_bytes || bytes.size() > std::numeric_limits<unsigned>::max())
    throw LoadError(file + ": " + std::to_string(bytes.size()) + " bytes is over the limit of " +
                    std::to_string(options.max_file_bytes));
  // The document: the .glb container, the JSON's limits (a streaming pass), its one DOM,
  // the schema check and the pre-pass on that DOM (gltf/document.h), which rewrites
  // EXT_meshopt_compression's placeholder buffers and Draco primitives' indices for tinygltf.
  gltf::Document doc = gltf::read_document(bytes, file, options.memory_limit, /*schema=*/true);
  const gltf::Container& container = doc.container;
  bytes = doc.bytes;
  if (bytes.size() > std::numeric_limits<unsigned>::max())
    throw LoadError(file + ": " + std::to_string(bytes.size()) + " bytes is over the limit of " +
                    std::to_string(std::numeric_limits<unsigned>::max()));
  tg::TinyGLTF parser;
  FsContext fs_context{options.max_file_bytes, &options.roots, {}, {}, {}};
  parser.SetFsCallbacks({&gltf::file_exists, &tg::ExpandFilePath, &read_whole_file, &tg::WriteWholeFile, &fs_context});
  tg::Model model;
  ImageContext images{&model, {}};
  parser.SetImageLoader(&keep_encoded, &images);
  std::string err, warn;
  const std::string base_dir = base.string();
  bool ok = false;
  try {
    if (container.binary)
      ok = parser.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), static_cast<unsigned>(bytes.size()), base_dir);
    else
      ok = parser.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                      static_cast<unsigned>(bytes.size()), base_dir);
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    throw LoadError(file + ": " + first_line(e.what()));
  }
  if (!ok) {
    // A buffer's file that could not be read: its pointer and the reason (tinygltf wraps it
    // as "File read error : path : path: reason").
    if (!fs_context.problem.empty())
      throw LoadError(file + ": " + gltf::buffer_pointer(doc.hints, base_dir, fs_context.problem_path) + fs_context.problem);
    // A few references tinygltf checks itself: said with their JSON pointer when found.
    const std::string pointed = gltf::tinygltf_error_with_pointer(doc.hints, err);
    if (!pointed.empty()) throw LoadError(file + ": " + pointed);
    throw LoadError(file + ": " + (err.empty() ? std::string("not a glTF file") : first_line(err)));
  }
  GltfScene out;
  out.files = std::move(fs_context.files);
  for (std::size_t start = 0; start < warn.size();) {
    const std::size_t end = warn.find('\n', start);
    const std::string line = warn.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (!line.empty()) out.warnings.push_back(file + ": " + line);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  gltf::use_texture_extension_sources(model);
  out.variants = gltf::variant_names(model);
  if (!options.variant.empty()) gltf::select_variant(model, options.variant, file);
  if (options.poseable) {
    // The scene graph, its model and options kept for GltfScene::pose (it fills the
    // poser's scene, which `out` copies).
    auto poser = std::make_shared<GltfPoser>();
    poser->file = file;
    poser->model = std::move(model);
    poser->options = options;
    poser->scene = std::move(out);
    poser->graph = std::make_unique<gltf::SceneGraph>(gltf::Context(poser->file, poser->model, poser->options, poser->scene),
                                                      base_dir, doc.placeholders, doc.draco_indices);
    poser->graph->load();
    poser->options.pool = nullptr;  // the caller's pool may not outlive the scene
    out = poser->scene;
    out.poser = poser;
    if (info != nullptr) model = poser->model;  // (a copy: describe() reads it below)
  } else {
    gltf::SceneGraph(gltf::Context(file, model, options, out), base_dir, doc.placeholders, doc.draco_indices).load();
  }
  if (info != nullptr) {
    std::map<int, image::ImageHeader> headers;
    std::map<int, std::size_t> sizes;
    for (const int i : images.kept) {
      const std::vector<unsigned char>& encoded = model.images[static_cast<std::size_t>(i)].image;
      headers[i] = image::read_image_header(encoded);
      sizes[i] = encoded.size();
    }
    *info = gltf::describe(model, file, base_dir, warn, std::move(headers), std::move(sizes), options);
    if (doc.rewritten()) gltf::restore_prepass(**info, model, doc.draco_indices, doc.placeholders);
  }
  return out;
}

}  // namespace

void GltfScene::pose(std::optional<double> time, const std::string& animation, raster::ThreadPool* pool) {
  if (poser == nullptr) throw std::logic_error("GltfScene::pose: the model was not loaded with GltfOptions::poseable");
  const std::lock_guard<std::mutex> lock(poser->mutex);
  GltfOptions& o = poser->options;
  o.time = time;
  o.animation = animation;
  o.pool = pool;
  poser->scene.warnings.clear();
  try {
    poser->graph->pose();
  } catch (...) {
    o.pool = nullptr;
    throw;
  }
  o.pool = nullptr;
  objects = poser->scene.objects;
  lights = poser->scene.lights;
  cameras = poser->scene.cameras;
  for (const std::string& w : poser->scene.warnings)
    if (std::find(warnings.begin(), warnings.end(), w) == warnings.end()) warnings.push_back(w);
}

GltfScene load_gltf(const std::filesystem::path& path, const GltfOptions& options) {
  const std::vector<unsigned char> bytes = read_file(path, options.max_file_bytes, path.string());
  return load(bytes, path.string(), path.parent_path(), options, nullptr);
}

GltfScene load_gltf(std::span<const std::uint8_t> bytes, const std::string& file, const std::filesystem::path& base,
                    const GltfOptions& options) {
  return load(bytes, file, base, options, nullptr);
}

GltfModelInfo load_and_inspect_gltf(const std::filesystem::path& path, const GltfOptions& options) {
  const std::vector<unsigned char> bytes = read_file(path, options.max_file_bytes, path.string());
  std::optional<GltfInfo> info;
  GltfModelInfo out;
  out.scene = load(bytes, path.string(), path.parent_path(), options, &info);
  out.info = std::move(*info);
  return out;
}

}  // namespace softpbr::pbr
