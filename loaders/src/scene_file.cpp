// JSON scene files (see scene_file.h; the format is docs/scene-format.md): the top level
// here, each kind of value in scene_file/ (see scene_file/loader.h).
#include "softpbr/loaders/scene_file.h"

#include <algorithm>
#include <cstdio>
#include <system_error>

#include "json_reader.h"
#include "scene_file/loader.h"
#include "softpbr/image/read_file.h"
#include "softpbr/loaders/format_bytes.h"

namespace softpbr::pbr {

namespace scene_file {

void MemoryBudget::charge(const Node& where, std::uint64_t bytes, const char* what) {
  bytes_ += bytes;
  if (bytes_ > limit_)
    r_.fail(where, std::string(what) + " brings the scene's estimated memory to " + format_bytes(bytes_) +
                       ", over the limit of " + format_bytes(limit_));
}

}  // namespace scene_file

namespace {

using scene_file::Json;
using scene_file::Node;
using scene_file::Reader;

SceneFile load(const Reader& r, const Node& root, const std::filesystem::path& base_dir,
               const SceneLoadOptions& options) {
  r.object(root, {"camera", "lights", "ambient", "environment", "ground", "meshes", "objects", "render", "animation"});
  SceneFile out;
  scene_file::MemoryBudget budget(r, options.memory_limit);
  scene_file::TextureLibrary textures(r, base_dir, budget);
  textures.cache().set_roots(options.roots);
  scene_file::MeshLibrary meshes(r, base_dir, budget, textures);
  meshes.set_missing_images(options.missing_images);
  if (auto c = r.member(root, "camera")) out.scene.camera = scene_file::read_camera(r, *c);
  if (auto a = r.member(root, "ambient")) out.scene.ambient = r.vec3(*a, 0, 1e30);
  if (auto s = r.member(root, "render")) scene_file::read_render(r, *s, out);
  // After /render: the environment's background replaces render.background.
  if (auto e = r.member(root, "environment")) scene_file::read_environment(r, *e, base_dir, budget, options, out);
  if (auto a = r.member(root, "animation")) scene_file::read_animation(r, *a, out.animation);
  if (auto g = r.member(root, "ground")) {
    r.object(*g, {"shadow", "darkness", "softness"});
    if (auto v = r.member(*g, "shadow")) out.scene.ground.shadow = r.boolean(*v);
    if (auto v = r.member(*g, "darkness")) out.scene.ground.darkness = static_cast<float>(r.number(*v, 0, 1));
    if (auto v = r.member(*g, "softness")) out.scene.ground.softness = static_cast<float>(r.number(*v, 0, 1));
  }
  if (auto l = r.member(root, "lights")) {
    const std::size_t n = r.array(*l, kMaxLights, "every light is evaluated at every pixel");
    for (std::size_t i = 0; i < n; ++i) out.scene.lights.push_back(scene_file::read_light(r, l->at(i)));
  }
  if (auto m = r.member(root, "meshes")) meshes.define(*m);
  const Node objects = r.required(root, "objects");
  const std::size_t n = r.array(objects, kMaxObjects, "each object is a draw call");
  for (std::size_t i = 0; i < n; ++i) scene_file::read_object(r, objects.at(i), meshes, textures, budget, out);
  out.texture_bytes = textures.bytes();
  out.mesh_bytes = budget.bytes() - out.texture_bytes - out.environment_bytes;
  out.warnings = std::move(meshes.warnings());
  for (std::string& f : meshes.files()) out.inputs.push_back(std::move(f));  // after the environment's file
  for (std::string& f : textures.cache().files()) out.inputs.push_back(std::move(f));
  return out;
}

SceneFile parse(std::string_view text, const std::string& name, const std::filesystem::path& base_dir,
                const SceneLoadOptions& options) {
  const Reader reader(name);
  // nlohmann's parser stops at a NUL byte, accepting whatever follows: none is allowed.
  if (const std::size_t nul = text.find('\0'); nul != std::string_view::npos)
    throw SceneFileError(name + ": a NUL byte at byte " + std::to_string(nul) + " (a scene file is UTF-8 JSON text)");
  json_reader::Counts counts;
  if (const auto problem = json_reader::find_structure_problem(text, &counts)) reader.fail(problem->pointer, problem->message);
  // The DOM built next: nlohmann's 16-byte values (32 with the arrays' spare capacity), a
  // node and a map or vector per container (about 64 bytes), and the strings (at most the
  // text again). 7.7 million numbers in arrays of 10: estimated 291 MiB, measured peak 252.
  const std::uint64_t dom = 32 * std::uint64_t{counts.values} + 64 * std::uint64_t{counts.containers} + text.size();
  if (dom > options.memory_limit)
    throw SceneFileError(name + ": parsing it needs an estimated " + format_bytes(dom) + ", over the memory limit of " +
                         format_bytes(options.memory_limit));
  Json root;
  try {
    // Comments (// and /* */) are accepted as an extension; see docs/scene-format.md.
    root = Json::parse(text.begin(), text.end(), nullptr, true, true);  // depth checked above
  } catch (const Json::exception& e) {
    // "[json.exception.parse_error.101] parse error at line 3, column 5: …" → drop the tag.
    std::string what = e.what();
    if (const auto close = what.find("] "); what.rfind("[json.exception", 0) == 0 && close != std::string::npos)
      what = what.substr(close + 2);
    // nlohmann quotes the text it read ("last read: '…'"): at most 40 bytes of it.
    if (const auto at = what.find("; last read: '"); at != std::string::npos) {
      const std::size_t start = at + 14;
      std::size_t end = what.find("'; ", start);
      if (end == std::string::npos) end = what.size();
      if (end - start > 40) what.replace(start + 40, end - start - 40, "...");
    }
    for (char& c : what)
      if (static_cast<unsigned char>(c) < 0x20) c = '?';  // one line
    throw SceneFileError(name + ": invalid JSON: " + what);
  }
  return load(reader, Node{root, ""}, base_dir, options);
}

}  // namespace

SceneFile parse_scene_file(std::string_view text, const std::string& name, const std::filesystem::path& base_dir,
                           const SceneLoadOptions& options) {
  try {
    return parse(text, name, base_dir, options);
  } catch (const json_reader::Error& e) {
    throw SceneFileError(e.what());  // the reader's line as is: "FILE: /pointer: what"
  }
}

SceneFile load_scene_file(const std::filesystem::path& path, const SceneLoadOptions& options) {
  const std::string name = path.string();
  // A pipe is read (`softpbr render <(generate-scene)`); opening one never waits for a
  // writer, and one without a writer reads as empty (read_file.h).
  std::string text;
  if (const image::FileProblem p = image::read_whole_file(path, kMaxSceneFileBytes, text, image::Pipes::Read); p) {
    if (p.folder) throw SceneFileError(name + ": is a folder, not a scene file");
    if (p.too_large)
      throw SceneFileError(name + ": the scene file is " +
                           (p.size > kMaxSceneFileBytes + 1 ? format_bytes(p.size) + ", " : std::string()) +
                           "over the limit of " + format_bytes(kMaxSceneFileBytes) + " (meshes belong in OBJ files)");
    if (p.error != 0) throw SceneFileError(name + ": cannot open the scene file: " + std::generic_category().message(p.error));
    throw SceneFileError(name + ": " + p.reason);
  } else if (p.pipe && text.empty()) {
    throw SceneFileError(name + ": is a pipe that gave nothing (a named pipe with no writer reads as empty)");
  }
  SceneFile file = parse_scene_file(text, name, path.parent_path(), options);
  file.inputs.insert(file.inputs.begin(), name);
  return file;
}

std::uint64_t image_memory(int width, int height, int samples) {
  // Target colour (16) + depth (4), then the largest output's buffers, one output at a
  // time: PNG 8 (Image8 + encoding), .hdr 16 (float RGB + RGBE), .exr up to 52 (four float
  // planes and tinyexr's compression buffers). Measured peak resident memory of a 2048²
  // render of lights.json: 30 bytes a pixel with .png, 34 with .hdr, 50 with .exr.
  // MSAA adds the multisampled target (colour and depth per sample); the 1-sample target
  // above then holds the resolved image.
  constexpr std::uint64_t kBytesPerPixel = 72;
  const std::uint64_t pixels =
      static_cast<std::uint64_t>(std::max(width, 0)) * static_cast<std::uint64_t>(std::max(height, 0));
  const std::uint64_t multisampled = samples > 1 ? pixels * static_cast<std::uint64_t>(samples) * 20 : 0;
  return pixels * kBytesPerPixel + multisampled;
}

}  // namespace softpbr::pbr
