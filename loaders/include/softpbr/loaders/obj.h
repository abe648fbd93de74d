// softpbr/loaders/obj.h — Wavefront OBJ + MTL loading (through tinyobjloader) into meshes and
// metal/roughness materials.
//
// OBJ files are untrusted input (docs/design.md, "Errors"): every number and index is checked, and any
// problem is a LoadError whose message starts with the file and, when known, the line
// ("models/cow.obj:12: face index 9 is out of range (8 vertices so far)"). Loading never
// reads out of bounds and never aborts.
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "softpbr/loaders/load_error.h"
#include "softpbr/loaders/missing_images.h"
#include "softpbr/pbr/material.h"
#include "softpbr/pbr/mesh.h"

namespace softpbr::pbr {

// The faces of one OBJ object/group (`o`/`g`) that use one material. An object whose faces
// use several materials becomes several ObjShapes with the same name, in the order the
// materials first appear.
struct ObjShape {
  std::string name;
  Mesh mesh;
  int material = -1;  // index into ObjModel::materials, −1 = none (use a default material)
};

struct ObjModel {
  std::vector<ObjShape> shapes;                               // in file order
  std::vector<std::pair<std::string, Material>> materials;    // every material of every mtllib
  std::vector<std::string> warnings;                          // tinyobjloader's and ours, one per line
  std::uint64_t texture_bytes = 0;  // texels of the materials' textures, mip levels included, each once
  std::vector<std::string> files;   // the OBJ and MTL files read (not the texture images)
};

struct ObjOptions {
  // Load the MTL files' texture maps (false: the materials keep their factors only, e.g.
  // for a model drawn with merge_shapes and a material of its own).
  bool textures = true;
  // The texels of all the model's textures (mip levels included) may take at most this;
  // a map that would pass it is refused from its image header, before it is decoded.
  std::uint64_t texture_memory_limit = std::uint64_t{4} << 30;
  // When not empty, the OBJ file, its MTL files and their maps must lie inside one of these
  // folders (symbolic links and ".." resolved), as SceneLoadOptions::roots.
  std::vector<std::filesystem::path> roots{};
  // The parse's estimated peak memory (the text, tinyobjloader's arrays, the meshes built:
  // about 100 bytes a face corner) may take at most this: checked after the validation
  // pass has counted the elements, before anything is parsed into memory.
  std::uint64_t memory_limit = std::numeric_limits<std::uint64_t>::max();
  // A texture map whose file cannot be read: the model refused (Error) or the map left out
  // with a warning (Warn); missing_images.h.
  MissingImages missing_images = MissingImages::Error;
};

// Loads an OBJ file and the MTL libraries it names (looked up next to the OBJ file).
// - Polygons are triangulated by tinyobjloader (quads split along the shorter diagonal,
//   larger polygons by ear clipping); faces with fewer than 3 vertices are dropped with a
//   warning; `l` and `p` elements are ignored with a warning.
// - Vertices are shared within a shape where position, texture and normal indices agree.
// - Vertices without a normal get the angle-weighted smooth normal of the shape's faces
//   around their position (smoothing groups are ignored); given normals are normalised.
// - Texture coordinates are optional ((0, 0) when missing) and flipped to (u, 1 − v): OBJ's
//   v grows up the image, softpbr's (and glTF's, raster/texture.h) down from its first row.
// - MTL → Material: base_color ← Kd (clamped to [0, 1]); metallic ← Pm; roughness ← Pr
//   (both PBR-extension keys, clamped to [0, 1]), or when Pr is absent
//   roughness_from_phong_exponent(Ns), or Material's default when both are absent;
//   emissive ← Ke (negatives raised to 0). Clamping is reported in warnings. Other keys
//   (Ka, Ks, d/Tr, Ni, illum) are ignored. A material stays in force across `o`/`g`.
// - MTL texture maps → texture slots (paths relative to the MTL file; PNG or JPEG, and
//   .hdr/.exr for the single-image maps; each file loaded once per colour space):
//     map_Kd → base_color_texture (sRGB); map_Ke → emissive_texture (sRGB);
//     map_Pr, map_Pm → one metallic_roughness_texture (linear, glTF's layout: roughness in
//       G, metallic in B) made from the two grey images' red channels, at the larger
//       width and height of the two, nearest-resampled; the missing one is 1 (255);
//     map_Ns → that texture's roughness when neither Pr nor map_Pr is given: per texel
//       roughness_from_phong_exponent(Ns × code/255), Ns 1000 when absent;
//     norm → normal_texture (linear); map_Bump/bump → normal_texture only when the image
//       is a normal map (not grey, mean colour within (0.5 ± 0.1, 0.5 ± 0.1, ≥ 0.75)):
//       a height map is skipped with a warning (bump mapping is not supported); norm wins
//       over bump; -bm → normal_scale;
//     map_d → the base colour texture's alpha (the image's alpha channel when it has one
//       below 255, else its red channel; combined with map_Kd's RGB, or white, as
//       map_Pr/map_Pm are) and alpha_mode Mask at cutoff 0.5 (cut-outs, as glTF's MASK;
//       the constant d/Tr stays ignored: exporters disagree on Tr's sense).
//   A map given without its constant (map_Kd without Kd, map_Ke without Ke, map_Pr
//   without Pr, map_Pm without Pm) makes that factor 1, so the map is used as it is.
//   Options: -o u v w → uv_transform offset, -s u v w → scale (both in OBJ's v-up space,
//   converted for the flip), -clamp on → clamp_to_edge; the others are ignored.
//   ObjOptions::textures = false loads none.
// Throws LoadError for: a missing or unreadable file, a file over 1 GiB, binary data,
// a coordinate that is not a finite float, a position or texture index that is 0 or out of
// range, a `t` tag declaring more values than it has (tinyobjloader would allocate them),
// and any error tinyobjloader reports. A normal index out of range only drops that
// normal (with a warning) and a smooth normal is computed instead. A texture map that
// cannot be used — a missing, truncated or oversized image, a float image where a grey
// one is combined, an option that swallowed the file name — is a LoadError naming the MTL
// file, the line and the keyword: "models/x.mtl:7: map_Kd: models/wood.png: no such file".
ObjModel load_obj(const std::filesystem::path& path, const ObjOptions& options = {});

// Perceptual roughness for a Blinn-Phong specular exponent Ns (the MTL fallback when Pr is
// absent): α = √(2 / (Ns + 2)), inverting the Phong ↔ Beckmann correspondence
// αp = 2/αb² − 2 of Walter et al. 2007, "Microfacet Models for Refraction through Rough
// Surfaces", §5.2 (also in Karis's "Specular BRDF Reference", 2013), with the Beckmann width
// taken as GGX's α; then roughness = √α since α = roughness² here (brdf.h).
// Ns ≤ 0 or NaN gives 1; +∞ gives 0; otherwise the result is in (0, 1).
float roughness_from_phong_exponent(float ns);

// All shapes of a model in one mesh (materials dropped), e.g. to draw it with one material.
// An optional stream (tangents, uv1, colors; mesh.h) is kept if every shape with vertices
// has it and dropped otherwise. Throws std::invalid_argument if a shape's stream has the
// wrong length (validate_streams).
Mesh merge_shapes(const ObjModel& model);

}  // namespace softpbr::pbr
