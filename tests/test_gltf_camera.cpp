// Orthographic cameras: pbr::orthographic is glTF's matrix, pbr::Camera's orthographic mode
// (validation, parallel view rays), glTF orthographic cameras, scene-file orthographic
// cameras, and a glTF camera rendering bit for bit as the same camera in a scene file.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/scene_file.h"
#include "softpbr/pbr/camera.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/raster/raster.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
namespace fs = std::filesystem;

namespace {

fs::path write_file(const std::string& name, const std::string& text) {
  const fs::path dir = fs::path(SOFTPBR_BINARY_DIR) / "gltf-camera";
  fs::create_directories(dir);
  const fs::path p = dir / name;
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

// One triangle (0,0,0), (1,0,0), (0,1,0) with a red dielectric material, seen by camera 0
// of node 1 (`camera` is the camera object, `node` the camera node's transform keys).
std::string camera_gltf(const std::string& camera, const std::string& node = R"("translation": [0.25, 0.25, 5])") {
  return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
    "nodes": [{"mesh": 0}, {"camera": 0, )" + node + R"(}],
    "cameras": [)" + camera + R"(],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.1, 1], "metallicFactor": 0, "roughnessFactor": 0.4}}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
    "buffers": [{"byteLength": 44, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                  {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]})";
}

const char* kOrtho = R"({"type": "orthographic", "name": "front", "orthographic": {"xmag": 1.0, "ymag": 0.75, "znear": 0.5, "zfar": 20}})";

std::string load_error(const fs::path& p) {
  try {
    pbr::load_gltf(p);
  } catch (const pbr::LoadError& e) {
    return e.what();
  }
  return "(no error)";
}

std::string scene_error(const std::string& text) {
  try {
    pbr::parse_scene_file(text, "t.json", fs::path(SOFTPBR_BINARY_DIR));
  } catch (const pbr::SceneFileError& e) {
    return e.what();
  }
  return "(no error)";
}

std::string validate_error(const pbr::Camera& c) {
  try {
    pbr::validate(c);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

raster::Target render(const pbr::Scene& s, int w, int h, const raster::RendererOptions& options = {.threads = 2}) {
  raster::Renderer renderer(options);
  raster::Target target(w, h);
  pbr::render(s, renderer, target);
  return target;
}

}  // namespace

TEST_CASE("orthographic(): glTF 2.0's orthographic projection matrix, element by element") {
  const float xmag = 2.5f, ymag = 1.25f, n = 0.5f, f = 40.0f;
  const glm::mat4 m = pbr::orthographic(xmag, ymag, n, f);
  // glTF 2.0, "Projection matrices": rows [1/r 0 0 0], [0 1/t 0 0],
  // [0 0 2/(n−f) (f+n)/(n−f)], [0 0 0 1] with r = xmag, t = ymag (glm is column-major).
  glm::mat4 want(0.0f);
  want[0][0] = 1.0f / xmag;
  want[1][1] = 1.0f / ymag;
  want[2][2] = 2.0f / (n - f);
  want[3][2] = (f + n) / (n - f);
  want[3][3] = 1.0f;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) {
      CAPTURE(c);
      CAPTURE(r);
      CHECK(m[c][r] == want[c][r]);
    }
  // The same as glm::ortho over [−xmag, xmag] × [−ymag, ymag], and it maps the near and far
  // planes to clip z −1 and +1 with w = 1.
  CHECK(m == glm::ortho(-xmag, xmag, -ymag, ymag, n, f));
  const glm::vec4 near_point = m * glm::vec4(xmag, -ymag, -n, 1.0f);
  const glm::vec4 far_point = m * glm::vec4(0.0f, 0.0f, -f, 1.0f);
  CHECK(near_point == glm::vec4(1.0f, -1.0f, -1.0f, 1.0f));
  CHECK(far_point.z == doctest::Approx(1.0f).epsilon(1e-6));
  CHECK(far_point.w == 1.0f);

  // Camera: orthographic with both magnifications, or xmag from the aspect ratio; the
  // perspective projection is what it always was.
  pbr::Camera c;
  c.orthographic = true;
  c.ymag = ymag;
  c.near = n;
  c.far = f;
  CHECK(c.projection(2.0f) == pbr::orthographic(ymag * 2.0f, ymag, n, f));
  c.xmag = xmag;
  CHECK(c.projection(0.3f) == m);
  const pbr::Camera p;
  CHECK(p.projection(1.5f) == pbr::perspective(p.fovy, 1.5f, p.near, p.far));
}

TEST_CASE("validate(): an orthographic camera's ymag, xmag, near and far") {
  pbr::Camera c;
  c.orthographic = true;
  c.near = 0.0f;  // allowed: the depth is linear
  CHECK(validate_error(c) == "(no error)");
  struct Case {
    float pbr::Camera::*field;
    float value;
    const char* message;
  };
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Case> cases = {
      {&pbr::Camera::ymag, 0.0f, "camera ymag: must be finite and > 0"},
      {&pbr::Camera::ymag, nan, "camera ymag: must be finite and > 0"},
      {&pbr::Camera::ymag, 1e-35f, "camera ymag: must be at least 1e-30"},
      {&pbr::Camera::xmag, -1.0f, "camera xmag: must be finite and > 0 (0: ymag times the aspect ratio)"},
      {&pbr::Camera::xmag, 1e-35f, "camera xmag: must be at least 1e-30"},
      {&pbr::Camera::near, -0.5f, "camera near: must be >= 0"},
      {&pbr::Camera::far, 0.0f, "camera far: must be finite and > near"},
      {&pbr::Camera::far, 1e-35f, "camera far: must be at least 1e-30 beyond near"},
  };
  for (const Case& k : cases) {
    pbr::Camera bad = c;
    bad.*(k.field) = k.value;
    CAPTURE(k.message);
    CHECK(validate_error(bad) == k.message);
  }
  pbr::Camera huge = c;
  huge.near = 2e38f;
  huge.far = 3e38f;
  CHECK(validate_error(huge) == "camera far: plus near must stay below 3.4e38 (float's range)");
  huge.near = 1e37f;
  CHECK(validate_error(huge) == "(no error)");
  // The fov is not an orthographic camera's: any value passes.
  pbr::Camera wide = c;
  wide.fovy = 7.0f;
  CHECK(validate_error(wide) == "(no error)");
  wide.orthographic = false;
  CHECK(validate_error(wide) == "camera fovy: must be in (0, pi) radians");
}

TEST_CASE("orthographic camera: parallel rays — the image does not change with the camera's distance") {
  const pbr::GltfScene g = pbr::load_gltf(write_file("ortho_distance.gltf", camera_gltf(kOrtho)));
  pbr::Scene s;
  s.objects = g.objects;
  s.camera.orthographic = true;
  s.camera.ymag = 0.75f;
  s.camera.xmag = 1.0f;
  s.camera.near = 0.5f;
  s.camera.far = 200.0f;
  s.camera.target = {0.25f, 0.25f, 0.0f};
  s.lights = pbr::default_light_rig(pbr::Camera{});
  s.ambient = glm::vec3(0.1f);
  s.background = {0.0f, 0.0f, 0.0f, 1.0f};
  s.camera.position = {0.25f, 0.25f, 2.0f};
  const raster::Target close = render(s, 64, 48);
  s.camera.position = {0.25f, 0.25f, 100.0f};
  const raster::Target far = render(s, 64, 48);
  // Every colour (not the depths) is the same: the rays and the view direction shading
  // sees do not depend on where the camera stands.
  CHECK(raster::hash_colors(close) == raster::hash_colors(far));
  // The triangle (legs of 1 in a view 2 × 1.5 units) covers 1/6 of the image: 512 pixels.
  int covered = 0;
  for (float d : close.depths()) covered += d < 1.0f;
  CHECK(covered == doctest::Approx(64 * 48 / 6).epsilon(0.05));
  // A perspective camera sees the triangle smaller from farther away, and shades it
  // differently: the test above can fail.
  s.camera.orthographic = false;
  const raster::Target persp_far = render(s, 64, 48);
  s.camera.position = {0.25f, 0.25f, 2.0f};
  CHECK(raster::hash_colors(render(s, 64, 48)) != raster::hash_colors(persp_far));
  // The same bits at every lane width, thread count and with dispatch off.
  s.camera.orthographic = true;
  for (int lanes : {1, 4, 8, 16}) {
    CAPTURE(lanes);
    const raster::Target o = render(s, 64, 48, {.threads = 3, .tile_size = 16, .lanes = lanes, .dispatch = lanes != 8});
    CHECK(raster::hash_colors(o) == raster::hash_colors(close));
  }
}

TEST_CASE("glTF orthographic cameras load with the specification's xmag, ymag, znear and zfar") {
  const pbr::GltfScene g = pbr::load_gltf(write_file("ortho.gltf", camera_gltf(kOrtho)));
  REQUIRE(g.cameras.size() == 1);
  const pbr::Camera& c = g.cameras[0].camera;
  CHECK(g.cameras[0].name == "front");
  CHECK(c.orthographic);
  CHECK(c.xmag == 1.0f);
  CHECK(c.ymag == 0.75f);
  CHECK(c.near == 0.5f);
  CHECK(c.far == 20.0f);
  CHECK(c.position == glm::vec3(0.25f, 0.25f, 5.0f));
  CHECK(c.target == glm::vec3(0.25f, 0.25f, 4.0f));
  CHECK(c.up == glm::vec3(0.0f, 1.0f, 0.0f));
  CHECK(c.projection(16.0f / 9.0f) == pbr::orthographic(1.0f, 0.75f, 0.5f, 20.0f));
  for (const std::string& w : g.warnings) CHECK(w.find("camera") == std::string::npos);

  // A camera turned by its node (a quarter turn about +y: from +x, looking down −x).
  const pbr::GltfScene turned = pbr::load_gltf(write_file(
      "ortho_turned.gltf", camera_gltf(kOrtho, R"("translation": [5, 0, 0], "rotation": [0, 0.7071067811865476, 0, 0.7071067811865476])")));
  REQUIRE(turned.cameras.size() == 1);
  const glm::vec3 forward = turned.cameras[0].camera.target - turned.cameras[0].camera.position;
  CHECK(forward.x == doctest::Approx(-1.0f));
  CHECK(std::abs(forward.z) < 1e-6f);

  struct Case {
    std::string name;
    std::string camera;
    std::string message;
  };
  const std::vector<Case> cases = {
      {"xmag0.gltf", R"({"type": "orthographic", "orthographic": {"xmag": 0, "ymag": 1, "znear": 0, "zfar": 10}})",
       "xmag0.gltf: /cameras/0/orthographic/xmag: must be a number in (0, 1e30], got 0"},
      {"ymag_negative.gltf", R"({"type": "orthographic", "orthographic": {"xmag": 1, "ymag": -2, "znear": 0, "zfar": 10}})",
       "ymag_negative.gltf: /cameras/0/orthographic/ymag: must be a number in (0, 1e30], got -2"},
      {"ymag_tiny.gltf", R"({"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1e-40, "znear": 0, "zfar": 10}})",
       "ymag_tiny.gltf: /cameras/0/orthographic/ymag: must be at least 1e-30, got 1e-40"},
      {"xmag_huge.gltf", R"({"type": "orthographic", "orthographic": {"xmag": 1e31, "ymag": 1, "znear": 0, "zfar": 10}})",
       "xmag_huge.gltf: /cameras/0/orthographic/xmag: must be a number in (0, 1e30], got 1e+31"},
      {"znear.gltf", R"({"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": -1, "zfar": 10}})",
       "znear.gltf: /cameras/0/orthographic/znear: must be a number in [0, 1e30], got -1"},
      {"zfar.gltf", R"({"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": 10, "zfar": 10}})",
       "zfar.gltf: /cameras/0/orthographic/zfar: must be above znear and at most 1e30, got 10"},
      {"zfar_close.gltf", R"({"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": 1, "zfar": 1.00000001}})",
       "zfar_close.gltf: /cameras/0/orthographic/zfar: must be at least 1e-30 beyond znear in float precision, got 1.00000001"},
  };
  for (const Case& k : cases) {
    CAPTURE(k.name);
    const std::string message = load_error(write_file(k.name, camera_gltf(k.camera)));
    CHECK(message == (fs::path(SOFTPBR_BINARY_DIR) / "gltf-camera").string() + "/" + k.message);
  }
}

TEST_CASE("scene files: an orthographic camera, and each invalid value with its JSON pointer") {
  const pbr::SceneFile f = pbr::parse_scene_file(
      R"({"camera": {"position": [0, 1, 5], "target": [0, 1, 0], "orthographic": {"ymag": 2, "xmag": 3}, "near": 0, "far": 50},
          "objects": [{"mesh": {"type": "cube"}}]})",
      "t.json", fs::path(SOFTPBR_BINARY_DIR));
  CHECK(f.scene.camera.orthographic);
  CHECK(f.scene.camera.ymag == 2.0f);
  CHECK(f.scene.camera.xmag == 3.0f);
  CHECK(f.scene.camera.near == 0.0f);
  CHECK(f.scene.camera.far == 50.0f);
  // An orbit camera may be orthographic too; xmag defaults to 0 (the image's aspect).
  const pbr::SceneFile orbit = pbr::parse_scene_file(
      R"({"camera": {"distance": 10, "yaw": 30, "orthographic": {"ymag": 1.5}, "far": 1e6}, "objects": [{"mesh": {"type": "cube"}}]})",
      "t.json", fs::path(SOFTPBR_BINARY_DIR));
  CHECK(orbit.scene.camera.orthographic);
  CHECK(orbit.scene.camera.xmag == 0.0f);
  CHECK(orbit.scene.camera.ymag == 1.5f);  // far/near 1e7 is no limit for a linear depth

  struct Case {
    std::string camera;
    std::string message;
  };
  const std::vector<Case> cases = {
      {R"({"orthographic": {"ymag": 1}, "fov": 30})",
       "t.json: /camera/fov: an orthographic camera has no field of view (its view is 2·ymag high)"},
      {R"({"orthographic": {"xmag": 1}})", "t.json: /camera/orthographic: missing key \"ymag\""},
      {R"({"orthographic": {"ymag": 0}})", "t.json: /camera/orthographic/ymag: expected a number > 0, got 0"},
      {R"({"orthographic": {"ymag": 1, "xmag": -1}})", "t.json: /camera/orthographic/xmag: expected a number > 0, got -1"},
      {R"({"orthographic": {"ymag": 1e-40}})", "t.json: /camera: camera ymag: must be at least 1e-30"},
      {R"({"orthographic": {"ymag": 1, "zmag": 1}})", "t.json: /camera/orthographic/zmag: unknown key \"zmag\" (did you mean \"ymag\"?)"},
      {R"({"orthographic": 2})", "t.json: /camera/orthographic: expected an object, got 2"},
      {R"({"orthographic": {"ymag": 1}, "near": -1})", "t.json: /camera/near: expected a number >= 0, got -1"},
      {R"({"orthographic": {"ymag": 1}, "near": 5, "far": 5})", "t.json: /camera: camera far: must be finite and > near"},
  };
  for (const Case& k : cases) {
    CAPTURE(k.camera);
    CHECK(scene_error(R"({"camera": )" + k.camera + R"(, "objects": [{"mesh": {"type": "cube"}}]})") == k.message);
  }
}

TEST_CASE("a glTF orthographic camera renders bit for bit as the same camera in a scene file") {
  const fs::path model = write_file("ortho_scene.gltf", camera_gltf(kOrtho));
  // `softpbr render ortho_scene.gltf --camera 0 --env none`: the file's camera.
  pbr::GltfView view;
  view.width = 96;
  view.height = 72;
  view.camera = 0;
  view.environment = false;
  const pbr::SceneFile a = pbr::gltf_scene_file(pbr::load_gltf(model), view, model.string());
  // The same camera and model written in a scene file (with the command's light rig).
  const std::string json = R"({"camera": {"position": [0.25, 0.25, 5], "target": [0.25, 0.25, 4],
      "orthographic": {"xmag": 1, "ymag": 0.75}, "near": 0.5, "far": 20},
      "objects": [{"mesh": {"file": ")" + model.string() + R"("}}]})";
  pbr::SceneFile b = pbr::parse_scene_file(json, "t.json", model.parent_path());
  const pbr::Camera& ca = a.scene.camera;
  const pbr::Camera& cb = b.scene.camera;
  CHECK(ca.orthographic == cb.orthographic);
  CHECK(ca.position == cb.position);
  CHECK(ca.target == cb.target);
  CHECK(ca.up == cb.up);
  CHECK(ca.xmag == cb.xmag);
  CHECK(ca.ymag == cb.ymag);
  CHECK(ca.near == cb.near);
  CHECK(ca.far == cb.far);
  b.scene.lights = a.scene.lights;
  b.scene.ambient = a.scene.ambient;
  b.scene.background = a.scene.background;
  REQUIRE(a.scene.objects.size() == b.scene.objects.size());
  const raster::Target ta = render(a.scene, view.width, view.height);
  const raster::Target tb = render(b.scene, view.width, view.height);
  CHECK(raster::hash_colors(ta) == raster::hash_colors(tb));
  int covered = 0;
  for (float d : ta.depths()) covered += d < 1.0f;
  CHECK(covered > 96 * 72 / 10);  // the triangle is in view
  // Lit by the studio environment, the background is the one direction the camera looks in.
  view.environment = true;
  const pbr::SceneFile lit = pbr::gltf_scene_file(pbr::load_gltf(model), view, model.string());
  const raster::Target tl = render(lit.scene, view.width, view.height);
  const glm::vec4 corner = tl.color(0, 0), other = tl.color(95, 71);
  CHECK(corner.r == doctest::Approx(other.r).epsilon(1e-4));
  CHECK(corner.g == doctest::Approx(other.g).epsilon(1e-4));
}

TEST_CASE("the automatic camera looks from the front, 15 degrees above: a model lying flat is seen, not edge-on") {
  // The triangle of camera_gltf turned to lie flat in the ground plane (−90° about x: its
  // (0, 1, 0) corner goes to (0, 0, −1)), as TwoSidedPlane lies.
  std::string text = camera_gltf(kOrtho);
  const std::string node = R"({"mesh": 0})";
  text.replace(text.find(node), node.size(), R"({"mesh": 0, "rotation": [-0.70710678, 0, 0, 0.70710678]})");
  const fs::path model = write_file("flat.gltf", text);
  pbr::GltfView view;
  CHECK(view.pitch == pbr::kDefaultPitch);
  CHECK(pbr::kDefaultPitch == 15.0f);
  view.width = 96;
  view.height = 72;
  view.environment = false;
  auto covered_pixels = [&](const pbr::GltfView& v, pbr::Camera* camera) {
    const pbr::SceneFile f = pbr::gltf_scene_file(pbr::load_gltf(model), v, model.string());
    *camera = f.scene.camera;
    const raster::Target t = render(f.scene, v.width, v.height);
    int covered = 0;
    for (float d : t.depths()) covered += d < 1.0f;
    return covered;
  };
  pbr::Camera raised, level;
  const int seen = covered_pixels(view, &raised);
  view.pitch = 0.0f;
  const int edge_on = covered_pixels(view, &level);
  // From 15° above: the eye above the bounds' centre by sin 15° of its distance, in front (+z).
  const glm::vec3 d = raised.position - raised.target;
  CHECK(d.y / glm::length(d) == doctest::Approx(std::sin(15.0 * 3.14159265358979 / 180.0)).epsilon(1e-5));
  CHECK(d.z > 0.0f);
  CHECK(d.x == doctest::Approx(0.0f).scale(1.0f));
  CHECK(level.position.y == level.target.y);
  // Seen from above it covers a few hundred pixels of 96 × 72; level, almost none.
  CHECK(seen > 150);
  CHECK(edge_on < 20);
}

TEST_CASE("the automatic camera: bounds float cannot frame are one line naming the file, yaw is reduced modulo 360 exactly") {
  // The triangle (0..1) placed by its node: scaled to 1e38 (the view distance squared
  // overflows float), to 1e-40 (denormal: eye and target coincide in float), moved to 3e38
  // and scaled to 1e37 (the same), and spanning -7e38 … 3e38 (beyond float). Each was "softpbr: internal error: camera …" (exit 5), no file named.
  struct Case {
    const char* name;
    std::string node;
    std::string message;
  };
  const std::vector<Case> cases = {
      {"huge.gltf", R"("matrix": [1e38, 0, 0, 0, 0, 1e38, 0, 0, 0, 0, 1e38, 0, 0, 0, 0, 1])",
       "the automatic camera cannot frame the model's bounds (0, 0, 0) to (1e+38, 1e+38, 0) in float precision"},
      {"tiny.gltf", R"("scale": [1e-40, 1e-40, 1e-40])", "the automatic camera cannot frame the model's bounds"},
      {"far.gltf", R"("translation": [3e38, 3e38, 3e38], "scale": [1e37, 1e37, 1e37])",
       "the automatic camera cannot frame the model's bounds"},
      {"overflow.gltf", R"("translation": [3e38, 0, 0], "scale": [-1e39, 1, 1])", "reach beyond float's range"},
  };
  pbr::GltfView view;
  view.width = 32;
  view.height = 24;
  view.environment = false;
  for (const Case& c : cases) {
    const std::string name = c.name;
    CAPTURE(name);
    std::string text = camera_gltf(kOrtho);
    const std::string node = R"({"mesh": 0})";
    text.replace(text.find(node), node.size(), "{\"mesh\": 0, " + c.node + "}");
    const fs::path model = write_file(c.name, text);
    std::string message = "(no error)";
    try {
      pbr::gltf_scene_file(pbr::load_gltf(model), view, model.string());
    } catch (const pbr::LoadError& e) {
      message = e.what();
    }
    CAPTURE(message);
    CHECK(message.rfind(model.string() + ": ", 0) == 0);
    CHECK(message.find(c.message) != std::string::npos);
    CHECK(message.find('\n') == std::string::npos);
  }

  // Yaw: 1e25° frames as its remainder modulo 360 (computed here in 128-bit integers: the
  // float 1e25 is an integer), −1e25 as its negation; 540° as 180°, −190° as 170°.
  const fs::path model = write_file("yaw.gltf", camera_gltf(kOrtho));
  auto camera_at = [&](float yaw) {
    pbr::GltfView v = view;
    v.yaw = yaw;
    return pbr::gltf_scene_file(pbr::load_gltf(model), v, model.string()).scene.camera;
  };
  const float big = 1e25f;
  const auto exact = static_cast<unsigned __int128>(static_cast<long double>(big));
  const auto remainder = static_cast<int>(exact % 360);  // in [0, 360)
  const float reduced = static_cast<float>(remainder > 180 ? remainder - 360 : remainder);
  const std::vector<std::pair<float, float>> same = {{big, reduced}, {-big, -reduced}, {540.0f, 180.0f}, {-190.0f, 170.0f},
                                                     {720.25f, 0.25f}};
  for (const auto& [yaw, equivalent] : same) {
    CAPTURE(yaw);
    const pbr::Camera a = camera_at(yaw), b = camera_at(equivalent);
    CHECK(a.position == b.position);
    CHECK(a.target == b.target);
    CHECK(a.up == b.up);
  }
}
