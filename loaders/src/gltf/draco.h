// KHR_draco_mesh_compression: a primitive's Draco-compressed geometry, decoded with
// Debian's libdraco. Private to the glTF reader (resources.cpp; docs/design.md, "glTF").
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace softpbr::pbr::gltf {

inline constexpr const char* kDraco = "KHR_draco_mesh_compression";

struct DracoAttribute {
  std::vector<float> values;  // points × components; integers as their values (not normalized)
  int components = 0;
  bool dequantized = false;  // float values (quantized, octahedral or stored as floats)
};

struct DracoMesh {
  std::size_t points = 0;
  std::vector<std::uint32_t> indices;             // triangles, 3 per face
  std::map<std::string, DracoAttribute> attributes;  // by glTF attribute name
};

// Decodes `bytes` and the attributes `ids` names (glTF attribute name → Draco unique id).
// Dequantization and octahedral normals are computed here, in softpbr's floating-point
// rules (libdraco's own inverse transforms are compiled with whatever contraction its build
// allowed), with the same formulas as libdraco. `fail(sub_pointer, message)` throws.
DracoMesh decode_draco(std::span<const std::uint8_t> bytes, const std::map<std::string, int>& ids, std::size_t max_points,
                       const std::function<void(const std::string&, const std::string&)>& fail);

}  // namespace softpbr::pbr::gltf
