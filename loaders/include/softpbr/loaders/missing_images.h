// softpbr/loaders/missing_images.h — what a model's texture image that cannot be read does
// to the model (ObjOptions, GltfOptions, SceneLoadOptions; the command's --missing-images).
#pragma once

namespace softpbr::pbr {

// An image file a model's material names (an MTL map, a glTF image's URI) that cannot be
// read: no such file, a folder, a named pipe or device, no permission, a link loop.
// - Error (the default): the model is refused with one line naming the file and the reason,
//   right for golden tests, where a lost texture must not pass silently.
// - Warn: that texture slot is left empty (the material's factors alone) and the model gets
//   a warning naming the file and the reason: a thumbnail of a downloaded model whose
//   textures were not downloaded with it.
// A file that is read but is not a valid image, is over a limit or lies outside the roots
// is an error either way.
enum class MissingImages { Error, Warn };

}  // namespace softpbr::pbr
