// model_diff.h — `softpbr diff A.glb B.glb`: two models (glTF, OBJ or scene files) rendered
// from the same views, framed on the union of their bounds, compared view by view, with
// what changed in the files; exit 0 within the tolerance, 1 outside, 2 on any error (as
// the image diff, diff.h).
#pragma once

#include <string>

#include "diff.h"

namespace softpbr::cli {

// Whether `path` names a model or scene (.gltf, .glb, .obj, .json) rather than an image.
bool is_model_path(const std::string& path);

int run_model_diff(const DiffArgs& args);

}  // namespace softpbr::cli
