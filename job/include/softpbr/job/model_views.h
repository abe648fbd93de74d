// softpbr/job/model_views.h — a model seen from a set of views that share one framing, as
// `softpbr diff a.glb b.glb` compares two models and Python's assert_model_matches checks
// one against another: any input (a glTF model, an OBJ model, a scene file) loaded with the
// render job's settings, a summary of what its file holds (`softpbr info`'s data, one row a
// property), and the camera of each view around given bounds (the union of both models'
// bounds, so a part that moved shows). Angles go through dmath, as the automatic camera's.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "softpbr/job/render_job.h"
#include "softpbr/pbr/camera.h"
#include "softpbr/pbr/mesh.h"

namespace softpbr::job {

// A view of the automatic camera (pbr::framing_camera): turned `yaw` degrees about the
// vertical axis (0: from +z, the front) and raised `pitch` degrees (in [−89, 89]).
struct View {
  float yaw = 0.0f;
  float pitch = 15.0f;  // pbr::kDefaultPitch
};

// At most this many views a comparison: a contact sheet of 64 rows stays readable.
inline constexpr int kMaxViews = 64;

// The default views (`softpbr diff`'s --views N, docs/cli.md): the automatic camera's front
// (yaw 0, pitch 15), then the rest of a ring at pitch 15 (yaw 360·k/(N−1) for k = 1 … N−2),
// and last one from above (pitch 89). N = 1: the front alone; N = 2: the front and the top.
// N in [1, kMaxViews] (Error, Kind::Setting, "views", otherwise).
std::vector<View> default_views(int count);

// Views from lists of angles (--yaw 0,90 --pitch 15): as many as the longer list, a list of
// one angle (or none: yaw 0, pitch 15) given to every view. Error (Kind::Setting) for lists
// of other lengths, a pitch outside [−89, 89], an angle that is not finite, or more than
// kMaxViews views.
std::vector<View> views_from_angles(const std::vector<float>& yaws, const std::vector<float>& pitches);

// A model ready to be seen from views: the scene (lit by the settings' environment, the
// studio by default; its camera is replaced by each view's), its bounds, and what the file
// holds, as rows of (property, value) in a fixed order (a glTF file's nodes, meshes,
// triangles, materials with their factors, textures with their sizes, extensions, bounds;
// an OBJ file's shapes and materials; a scene file's objects and lights).
struct ViewedModel {
  pbr::LoadedScene scene;
  pbr::Bounds bounds{};
  // The lights are the automatic light rig (no environment, a model without lights): they
  // follow each view's camera (pbr::default_light_rig) as they follow the render's.
  bool light_rig = false;
  std::vector<std::pair<std::string, std::string>> summary;
};

// Loads `input` by its extension: .gltf/.glb (pbr::load_and_inspect_gltf: one parse for the
// scene and its listing), .obj (pbr::load_obj; its MTL materials), else a scene file. The
// settings' memory limit, roots, missing images, environment and background apply; their
// width and height are the views' image. Throws as job::load (pbr::LoadError,
// pbr::SceneFileError naming the file; Error).
ViewedModel load_viewed(const std::string& input, const Settings& settings, raster::ThreadPool& pool);

// The camera of `view` framing `bounds` in a width × height image (pbr::framing_camera).
// Throws Error (Kind::Input) naming `what` when float cannot frame them.
pbr::Camera view_camera(const pbr::Bounds& bounds, int width, int height, View view, const std::string& what);

// `model`'s scene seen through `camera` (its light rig turned with it).
pbr::Scene scene_for_view(const ViewedModel& model, const pbr::Camera& camera);

}  // namespace softpbr::job
