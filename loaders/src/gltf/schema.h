// The glTF 2.0 JSON schema's structural rules, checked before tinygltf reads the file.
// Private to the glTF reader (docs/design.md, "glTF"); it checks document.h's DOM.
//
// tinygltf 2.7 reports a missing required property without saying where ("'count'
// property is missing in Accessor."), and skips a property of the wrong JSON type or an
// unknown enum value without a word (a texture's "source": "zero" drew the model
// untextured; a sampler's "magFilter": "x" fell back to the default). This pass walks the
// document (the reader's one DOM, document.h) once and reports the first such problem
// with its JSON pointer: every object that must be an object, every required property
// (glTF 2.0 §5, the schema's "required"), the JSON type of every property softpbr reads,
// and the enums (componentType, type, mode, filters, wrap modes, alphaMode, camera type).
// Then the specification's MUST rules across properties: asset.version and minVersion
// (a 2.x file, needing no more than 2.0), every integer as the exact value it is (within
// int where tinygltf holds an int — indices, and every integer inside "extensions" — and
// an accessor's count within the reader's 2^28), one parent a node, no cycle, scenes
// listing root nodes once, a node's matrix or TRS and an affine matrix, normalized only on
// integer types below UNSIGNED_INT, the component types of vertex attributes (integers
// only with KHR_mesh_quantization), and the references of skins, animations and the
// extensions softpbr reads (KHR_lights_punctual, Draco, EXT_meshopt_compression). Other
// numeric ranges stay with the loader, which checks the values it uses (with their
// pointers too).
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace softpbr::pbr::gltf {

// "pointer: message" for the first problem, or nothing. A document that is not a JSON
// object (or not JSON: discarded) is left to tinygltf, whose message says so.
std::optional<std::string> check_schema(const nlohmann::json& document);

}  // namespace softpbr::pbr::gltf
