// libFuzzer target: OBJ + MTL loading (pbr::load_obj).
//
// An input is an OBJ text, optionally followed by kMtlSeparator and an MTL text. Both are
// written to a private temporary folder as fuzz.obj and fuzz.mtl (load_obj takes a path
// and finds MTL libraries next to the OBJ; seeds say "mtllib fuzz.mtl"), then loaded.
// A LoadError is a fine outcome; anything else thrown, a crash or a sanitizer report is a
// finding. A model that loads must be usable: every index names a vertex, every position,
// normal and UV is finite, every normal has unit length, every material index is valid.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "fuzz_support.h"

#include "softpbr/loaders/obj.h"

namespace fs = std::filesystem;
namespace pbr = softpbr::pbr;

namespace {

constexpr std::string_view kMtlSeparator = "\n%%MTL%%\n";

[[noreturn]] void finding(const char* what) { softpbr::fuzz::finding("fuzz_obj", what); }

const fs::path& folder() { return softpbr::fuzz::private_folder("obj"); }

void write(const fs::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) finding("cannot write the temporary input file");
}

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void check(const pbr::ObjModel& model) {
  for (const pbr::ObjShape& shape : model.shapes) {
    if (shape.material < -1 || shape.material >= static_cast<int>(model.materials.size()))
      finding("material index out of range");
    if (shape.mesh.indices.size() % 3 != 0) finding("index count is not a multiple of 3");
    for (const std::uint32_t i : shape.mesh.indices)
      if (i >= shape.mesh.vertices.size()) finding("index past the vertices");
    for (const pbr::MeshVertex& v : shape.mesh.vertices) {
      if (!finite(v.position) || !finite(v.normal) || !std::isfinite(v.uv.x) || !std::isfinite(v.uv.y))
        finding("non-finite vertex attribute");
      const double n2 = double(v.normal.x) * v.normal.x + double(v.normal.y) * v.normal.y +
                        double(v.normal.z) * v.normal.z;
      if (std::fabs(n2 - 1.0) > 1e-3) finding("normal is not unit length");
    }
  }
  for (const auto& [name, m] : model.materials) {
    if (!finite(m.base_color) || !finite(m.emissive) || !(m.metallic >= 0.0f && m.metallic <= 1.0f) ||
        !(m.roughness >= 0.0f && m.roughness <= 1.0f))
      finding("material value out of range");
  }
  const pbr::Mesh merged = pbr::merge_shapes(model);
  for (const std::uint32_t i : merged.indices)
    if (i >= merged.vertices.size()) finding("merged index past the vertices");
  (void)pbr::bounds(merged);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const std::size_t split = input.find(kMtlSeparator);
  const fs::path obj = folder() / "fuzz.obj", mtl = folder() / "fuzz.mtl";
  write(obj, input.substr(0, split));
  std::error_code ec;
  if (split != std::string_view::npos) write(mtl, input.substr(split + kMtlSeparator.size()));
  else fs::remove(mtl, ec);
  try {
    check(pbr::load_obj(obj));
  } catch (const pbr::LoadError& e) {
    if (std::string_view(e.what()).substr(0, obj.string().size()) != obj.string() &&
        std::string_view(e.what()).substr(0, mtl.string().size()) != mtl.string())
      finding("a LoadError that does not start with the file name");
  }
  return 0;
}
