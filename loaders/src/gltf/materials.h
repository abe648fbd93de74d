// The glTF reader's materials: glTF's materials (with KHR_materials_emissive_strength,
// KHR_materials_unlit, and the layers of KHR_materials_ior, _specular, _clearcoat, _sheen;
// the archived KHR_materials_pbrSpecularGlossiness converted to them), their textures (KHR_texture_transform) and samplers, each material
// read once; the textures are made at the end, all images decoding in parallel. Private to
// the glTF reader (docs/design.md, "glTF").
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "gltf/reader.h"
#include "gltf/resources.h"
#include "softpbr/pbr/material.h"
#include "softpbr/raster/texture.h"

namespace softpbr::pbr::gltf {

inline constexpr const char* kSpecularGlossiness = "KHR_materials_pbrSpecularGlossiness";

class Materials : public Context {
 public:
  explicit Materials(const Context& context) : Context(context) {}

  // Reads material `index` once (-1: the default material) and returns it; its texture
  // slots are filled by make_textures().
  const Material& material(int index, const std::string& referrer);
  // A material read before (with its textures after make_textures()).
  const Material& at(int index) const { return *materials_.at(index); }

  // Decodes every image a slot needs, once per image and colour space (Resources::textures),
  // and fills the slots of the materials read.
  void make_textures(Resources& resources);

 private:
  raster::Sampler sampler(int index, const std::string& referrer);
  // The material extensions' layers of `g` into `m` (material_extensions.cpp):
  // KHR_materials_ior, _specular, _clearcoat and _sheen, or KHR_materials_pbrSpecularGlossiness
  // converted to the metal/roughness model (docs/design.md, "glTF").
  void layers(Material& m, const tg::Material& g, const std::string& pointer);
  // A textureInfo object inside an extension (`info`, at `pointer`) into `slot`.
  void extension_texture(TextureSlot& slot, const tg::Value& info, raster::ColorSpace space, const std::string& pointer,
                         float* scale = nullptr);
  void texture_slot(TextureSlot& slot, int texture, int tex_coord, const tg::ExtensionMap& extensions,
                    raster::ColorSpace space, const std::string& pointer);

  static constexpr int kAnisotropy = 8;

  struct Pending {
    TextureSlot* slot;
    int image;
    raster::ColorSpace space;
    // ≥ 0: the slot takes, instead of the image, a roughness texture made from its linear
    // decode: G = 255 − round(glossiness · A) (KHR_materials_pbrSpecularGlossiness).
    float glossiness = -1.0f;
  };
  // The roughness texture of a specular-glossiness image (see Pending::glossiness).
  static std::shared_ptr<const raster::Texture> roughness_from_glossiness(const raster::Texture& image,
                                                                          float glossiness);

  std::map<int, std::unique_ptr<Material>> materials_;
  std::vector<Pending> pending_;
};

}  // namespace softpbr::pbr::gltf
