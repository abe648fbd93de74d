// softpbr.Scene, Mesh, Material, Light, Camera and Object (see python/softpbr/_softpbr.pyi
// for the Python signatures). Angles are in degrees, as in scene files; colours are linear.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <glm/geometric.hpp>

#include "bindings.h"
#include "softpbr/dmath/dmath.h"
#include "softpbr/job/render_job.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/obj.h"
#include "softpbr/pbr/environment.h"
#include "softpbr/pbr/mesh.h"
#include "softpbr/raster/renderer.h"

namespace softpbr::python {

namespace {

using Vec3 = std::array<float, 3>;
glm::vec3 to_glm(const Vec3& v) { return {v[0], v[1], v[2]}; }
Vec3 from_glm(const glm::vec3& v) { return {v.x, v.y, v.z}; }
float radians(double degrees) { return static_cast<float>(dmath::radians(degrees)); }
double degrees(float radians) { return static_cast<double>(radians) * (180.0 / dmath::kPi); }

// ---- Meshes from numpy arrays ---------------------------------------------------------------
// A (rows, columns) float32 array, rows checked finite. Errors name the argument and the row.
std::vector<float> float_rows(const py::array& a, const char* what, py::ssize_t columns, py::ssize_t rows = -1) {
  if (a.ndim() != 2 || a.shape(1) != columns)
    value_error(std::string("Mesh: ") + what + ": expected an array of shape (N, " + std::to_string(columns) + "), got " +
                shape_text(a));
  if (rows >= 0 && a.shape(0) != rows)
    value_error(std::string("Mesh: ") + what + ": expected " + std::to_string(rows) + " rows (one per position), got " +
                std::to_string(a.shape(0)));
  if (!a.dtype().is(py::dtype::of<float>()))
    type_error(std::string("Mesh: ") + what + ": expected dtype float32, got " + std::string(py::str(a.dtype())) +
               " (convert with .astype(numpy.float32))");
  const auto c = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
  std::vector<float> out(c.data(), c.data() + c.size());
  for (std::size_t i = 0; i < out.size(); ++i)
    if (!std::isfinite(out[i]))
      value_error(std::string("Mesh: ") + what + "[" + std::to_string(i / static_cast<std::size_t>(columns)) + "]: " +
                  "expected finite numbers, got " + (std::isnan(out[i]) ? "nan" : out[i] > 0 ? "inf" : "-inf"));
  return out;
}

// A numpy array as it is (its dtype is checked), or a nested list converted to float32 or
// int64 (a list has no dtype to be wrong).
template <class T>
py::array as_array(const py::object& o, const char* what) {
  if (py::isinstance<py::array>(o)) return py::reinterpret_borrow<py::array>(o);
  py::array a = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(o);
  if (!a) type_error(std::string("Mesh: ") + what + ": expected a numpy array, got " + std::string(py::str(o.get_type().attr("__name__"))));
  return a;
}

std::shared_ptr<pbr::Mesh> mesh_from_arrays(const py::object& positions_in, const py::object& indices_in,
                                             const py::object& normals, const py::object& uvs) {
  const std::vector<float> p = float_rows(as_array<float>(positions_in, "positions"), "positions", 3);
  const py::array indices = as_array<std::int64_t>(indices_in, "indices");
  const std::size_t n = p.size() / 3;
  if (n > std::size_t{0xFFFFFFFFu}) value_error("Mesh: positions: more than 2^32 - 1 vertices");
  if (indices.ndim() != 2 || indices.shape(1) != 3)
    value_error("Mesh: indices: expected an array of shape (M, 3), one row per triangle, got " + shape_text(indices));
  if (indices.dtype().kind() != 'i' && indices.dtype().kind() != 'u')
    type_error("Mesh: indices: expected an integer dtype (uint32), got " + std::string(py::str(indices.dtype())));
  const auto idx = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(indices);
  if (indices.dtype().kind() == 'u' && indices.dtype().itemsize() == 8) {
    // uint64 values above 2^63 would wrap to negatives in the int64 copy: check the originals.
    const auto u = py::array_t<std::uint64_t, py::array::c_style | py::array::forcecast>::ensure(indices);
    for (py::ssize_t i = 0; i < u.size(); ++i)
      if (u.data()[i] >= n)
        value_error("Mesh: indices[" + std::to_string(i / 3) + "]: index " + std::to_string(u.data()[i]) +
                    " is out of range (" + std::to_string(n) + " vertices)");
  }
  auto mesh = std::make_shared<pbr::Mesh>();
  mesh->indices.resize(static_cast<std::size_t>(idx.size()));
  for (py::ssize_t i = 0; i < idx.size(); ++i) {
    const std::int64_t v = idx.data()[i];
    if (v < 0 || static_cast<std::uint64_t>(v) >= n)
      value_error("Mesh: indices[" + std::to_string(i / 3) + "]: index " + std::to_string(v) + " is out of range (" +
                  std::to_string(n) + " vertices)");
    mesh->indices[static_cast<std::size_t>(i)] = static_cast<std::uint32_t>(v);
  }
  mesh->vertices.resize(n);
  for (std::size_t i = 0; i < n; ++i) mesh->vertices[i].position = {p[3 * i], p[3 * i + 1], p[3 * i + 2]};
  if (!uvs.is_none()) {
    const std::vector<float> t = float_rows(as_array<float>(uvs, "uvs"), "uvs", 2, static_cast<py::ssize_t>(n));
    for (std::size_t i = 0; i < n; ++i) mesh->vertices[i].uv = {t[2 * i], t[2 * i + 1]};
  }
  if (normals.is_none()) {
    pbr::compute_smooth_normals(*mesh);
  } else {
    const std::vector<float> v = float_rows(as_array<float>(normals, "normals"), "normals", 3, static_cast<py::ssize_t>(n));
    for (std::size_t i = 0; i < n; ++i) {
      // Normalised in double, as the OBJ loader normalises given normals.
      const glm::dvec3 d(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
      const double n2 = glm::dot(d, d);
      if (!(n2 > 0.0)) value_error("Mesh: normals[" + std::to_string(i) + "]: expected a non-zero vector, got (0, 0, 0)");
      mesh->vertices[i].normal = glm::vec3(d / std::sqrt(n2));
    }
  }
  return mesh;
}

template <class F>
py::array_t<float> columns(const pbr::Mesh& m, py::ssize_t k, F&& get) {
  py::array_t<float> out({static_cast<py::ssize_t>(m.vertices.size()), k});
  float* o = out.mutable_data();
  for (const pbr::MeshVertex& v : m.vertices) o = get(v, o);
  return out;
}

std::shared_ptr<pbr::Mesh> shared(pbr::Mesh&& m) { return std::make_shared<pbr::Mesh>(std::move(m)); }

// ---- Transforms: numpy (4, 4) row-major ↔ glm's column-major ---------------------------------
glm::mat4 matrix_from(const py::object& o) {
  if (o.is_none()) return glm::mat4(1.0f);
  const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(o);
  if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4)
    value_error("transform: expected a 4x4 matrix (numpy rows), got " + (a ? shape_text(a) : std::string("another type")));
  glm::mat4 m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      const float v = a.at(r, c);
      if (!std::isfinite(v)) value_error("transform: expected finite numbers, got " + std::to_string(v));
      m[c][r] = v;
    }
  return m;
}
py::array_t<float> matrix_to(const glm::mat4& m) {
  py::array_t<float> a({4, 4});
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) a.mutable_at(r, c) = m[c][r];
  return a;
}

pbr::Material preset_or_error(const std::string& name) {
  if (auto m = pbr::material_preset(name)) return *m;
  std::string names;
  for (const pbr::NamedMaterial& p : pbr::material_presets()) names += (names.empty() ? "" : ", ") + std::string(p.name);
  value_error("Material.preset: unknown preset \"" + name + "\" (expected one of " + names + ")");
}

const char* light_type_name(pbr::LightType t) {
  return t == pbr::LightType::Point ? "point" : t == pbr::LightType::Directional ? "directional" : "spot";
}

pbr::RenderSettings& settings(PyScene& s) { return s.file.render; }

// A glTF model as a scene, as `softpbr render model.glb` makes it: the render job's
// (job::load_model: pbr::gltf_scene_file, docs/scene-format.md "glTF models") with the same
// view and the job's messages.
std::shared_ptr<PyScene> gltf_scene(const std::filesystem::path& path, int width, int height, double yaw, double pitch,
                                    std::optional<int> camera, bool environment, const std::string& missing_images,
                                    std::optional<std::string> variant, std::optional<double> time,
                                    std::optional<std::variant<int, std::string>> animation,
                                    std::optional<std::variant<int, std::string>> scene) {
  require_readable(path);
  job::Settings view;
  view.time = time;
  if (scene) {
    if (std::holds_alternative<int>(*scene) && std::get<int>(*scene) < 0)
      value_error("Scene.load_gltf: scene: expected an index >= 0 or a name, got " + std::to_string(std::get<int>(*scene)));
    view.scene = std::holds_alternative<int>(*scene) ? std::to_string(std::get<int>(*scene)) : std::get<std::string>(*scene);
  }
  if (animation)
    view.animation = std::holds_alternative<int>(*animation) ? std::to_string(std::get<int>(*animation))
                                                             : std::get<std::string>(*animation);
  view.missing_images = missing_images;
  view.variant = std::move(variant);
  view.width = width;
  view.height = height;
  view.yaw = static_cast<float>(yaw);
  view.pitch = static_cast<float>(pitch);
  view.camera = camera;
  if (!environment) view.env = "none";
  auto s = std::make_shared<PyScene>();
  std::string error;
  bool out_of_memory = false;
  try {
    job::validate(view);
    py::gil_scoped_release unlocked;
    raster::ThreadPool pool(0);  // decodes images, builds the studio environment on first use (the same bits on any pool)
    s->file = job::load_model(path.string(), view, pool);
  } catch (const job::Error& e) {
    error = e.what();
    out_of_memory = e.kind() == job::Error::Kind::Memory;
  }
  if (out_of_memory) {
    PyErr_SetString(PyExc_MemoryError, ("Scene.load_gltf: " + error).c_str());
    throw py::error_already_set();
  }
  if (!error.empty()) value_error("Scene.load_gltf: " + error);
  return s;
}

// softpbr.load_gltf: a glTF model's objects, lights and cameras as the file places them, to
// add to a Scene (pbr::load_gltf).
struct PyGltfModel {
  pbr::GltfScene model;
};

std::shared_ptr<PyGltfModel> load_gltf_model(const std::filesystem::path& path, std::optional<int> scene,
                                             const std::string& missing_images, std::optional<std::string> variant) {
  require_readable(path);
  if (scene && *scene < 0) value_error("load_gltf: scene: expected an index >= 0, got " + std::to_string(*scene));
  if (missing_images != "error" && missing_images != "warn")
    value_error("load_gltf: missing_images: expected error or warn, got \"" + missing_images + "\"");
  if (variant && variant->empty()) value_error("load_gltf: variant: expected a material variant's name or index, got \"\"");
  auto out = std::make_shared<PyGltfModel>();
  py::gil_scoped_release unlocked;
  raster::ThreadPool pool(0);
  out->model = pbr::load_gltf(path, {.scene = scene.value_or(-1),
                                     .pool = &pool,
                                     .missing_images = missing_images == "warn" ? pbr::MissingImages::Warn
                                                                                : pbr::MissingImages::Error,
                                     .variant = variant.value_or("")});
  return out;
}

// ---- Environments (image-based lighting) ----------------------------------------------------
// softpbr.Environment: a prefiltered map, immutable and shared by the scenes that use it.
struct PyEnvironment {
  std::shared_ptr<const pbr::Environment> map;
};

std::shared_ptr<PyEnvironment> studio_environment() {
  auto e = std::make_shared<PyEnvironment>();
  py::gil_scoped_release unlocked;
  raster::ThreadPool pool(0);
  e->map = pbr::Environment::studio(&pool);  // built once per process; the same bits on any pool
  return e;
}

std::shared_ptr<PyEnvironment> load_environment_file(const std::filesystem::path& path, int size, int samples,
                                                const std::optional<std::filesystem::path>& cache_dir) {
  require_readable(path);
  pbr::EnvironmentOptions options;
  options.size = size;
  options.samples = samples;
  try {
    pbr::validate(options);
  } catch (const std::invalid_argument& e) {
    value_error(std::string("Environment.load: ") + e.what());
  }
  auto env = std::make_shared<PyEnvironment>();
  std::string error;
  std::vector<std::string> warnings;
  {
    py::gil_scoped_release unlocked;
    raster::ThreadPool pool(0);
    try {
      env->map = pbr::load_environment(path, options, &pool, cache_dir.value_or(std::filesystem::path{}), {}, &warnings);
    } catch (const std::invalid_argument& e) {
      error = e.what();
    } catch (const std::runtime_error& e) {
      error = e.what();
    }
  }
  if (!error.empty()) value_error(error);  // names the file, as the scene file's /environment/file
  for (const std::string& w : warnings)  // an unusable cache folder: a RuntimeWarning, the map is loaded
    if (PyErr_WarnEx(PyExc_RuntimeWarning, w.c_str(), 1) != 0) throw py::error_already_set();
  return env;
}

const char* background_mode_name(pbr::BackgroundMode m) {
  return m == pbr::BackgroundMode::Color ? "color" : m == pbr::BackgroundMode::Environment ? "environment" : "blur";
}

std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// The scene file's ranges (docs/scene-format.md, "Environment"), named as Python's arguments.
float env_number(const char* what, double v, double lo, double hi) {
  if (!(v >= lo && v <= hi))
    value_error(std::string(what) + ": expected a number in [" + number_text(lo) + ", " + number_text(hi) +
                "], got " + number_text(v));
  return static_cast<float>(v);
}

// The environment's map, its memory counted with the scene's (as the loaders count it).
void set_map(PyScene& s, std::shared_ptr<const pbr::Environment> map) {
  s.file.environment_bytes = map ? map->bytes() : 0;
  s.file.scene.environment.map = std::move(map);
}

void set_background_mode(PyScene& s, const std::string& mode) {
  pbr::Scene& sc = s.file.scene;
  if (mode == "color") sc.background_mode = pbr::BackgroundMode::Color;
  else if (mode == "environment" || mode == "blur") {
    if (!sc.environment.map) value_error("background_mode \"" + mode + "\": the scene has no environment (set_environment first)");
    sc.background_mode = mode == "blur" ? pbr::BackgroundMode::Blur : pbr::BackgroundMode::Environment;
  } else {
    value_error("background_mode: expected \"color\", \"environment\" or \"blur\", got \"" + mode + "\"");
  }
}

// Scene.set_environment: the scene file's /environment, or `softpbr render --env …` on a
// loaded scene: a value left None keeps the scene's (a scene without an environment shows
// it as its background, as a file's "environment" section does).
void set_environment(PyScene& s, const py::object& environment, std::optional<double> intensity,
                     std::optional<double> rotation, const py::object& background, std::optional<double> blur,
                     std::optional<bool> multiscatter, std::optional<bool> occlusion) {
  pbr::Scene& sc = s.file.scene;
  // Everything checked before the scene changes.
  const float i = intensity ? env_number("intensity", *intensity, 0, 1e6) : sc.environment.intensity;
  const float r = rotation ? env_number("rotation", *rotation, -1e6, 1e6) : sc.environment.rotation;
  const float b = blur ? env_number("blur", *blur, 0, 1) : sc.background_blur;
  std::optional<std::string> mode;
  std::optional<glm::vec4> colour;
  if (py::isinstance<py::str>(background)) {
    mode = background.cast<std::string>();
    if (*mode != "environment" && *mode != "blur" && *mode != "transparent")
      value_error("background: expected \"environment\", \"blur\", \"transparent\" or a colour (r, g, b), got \"" + *mode + "\"");
    if (mode == "transparent") colour = glm::vec4(0.0f);
  } else if (!background.is_none()) {
    Vec3 c{};
    try {
      c = background.cast<Vec3>();
    } catch (const py::cast_error&) {
      value_error("background: expected \"environment\", \"blur\", \"transparent\" or a colour (r, g, b), got " +
                  std::string(py::str(py::repr(background))));
    }
    for (float v : c) env_number("background", v, 0, 1e30);
    colour = glm::vec4(c[0], c[1], c[2], 1.0f);
  }
  std::shared_ptr<const pbr::Environment> map;
  if (environment.is_none()) {
    if (mode == "environment" || mode == "blur") value_error("background \"" + *mode + "\": the environment is None");
  } else if (py::isinstance<PyEnvironment>(environment)) {
    map = environment.cast<const PyEnvironment&>().map;
  } else if (py::isinstance<py::str>(environment) && environment.cast<std::string>() == "studio") {
    map = studio_environment()->map;
  } else {
    try {
      map = load_environment_file(environment.cast<std::filesystem::path>(), 0, 64, std::nullopt)->map;
    } catch (const py::cast_error&) {
      type_error("environment: expected an Environment, \"studio\", a path to an .hdr/.exr or None, got " +
                 std::string(py::str(environment.get_type().attr("__name__"))));
    }
  }
  const bool had_map = sc.environment.map != nullptr;
  set_map(s, std::move(map));
  if (!sc.environment.map) sc.background_mode = pbr::BackgroundMode::Color;
  else if (!had_map) sc.background_mode = pbr::BackgroundMode::Environment;
  if (mode == "environment") sc.background_mode = pbr::BackgroundMode::Environment;
  if (mode == "blur") sc.background_mode = pbr::BackgroundMode::Blur;
  if (colour) {
    sc.background_mode = pbr::BackgroundMode::Color;
    sc.background = *colour;
  }
  sc.environment.intensity = i;
  sc.environment.rotation = r;
  sc.background_blur = b;
  if (multiscatter) sc.environment.multiscatter = *multiscatter;
  if (occlusion) sc.environment.occlusion = *occlusion;
}

}  // namespace

void bind_scene(py::module_& m) {
  py::class_<pbr::Mesh, std::shared_ptr<pbr::Mesh>>(m, "Mesh", R"(A triangle mesh: positions, normals, texture coordinates and indices.

Mesh(positions, indices, *, normals=None, uvs=None) builds one from numpy arrays:
positions (N, 3) float32, indices (M, 3) of an integer dtype (uint32 usually), one row per
counter-clockwise triangle, normals (N, 3) float32 (normalised; smooth normals are computed
when omitted), uvs (N, 2) float32. Raises TypeError for a wrong dtype, ValueError for a wrong
shape, a NaN or infinite value, a zero normal or an index out of range (naming the row).)")
      .def(py::init(&mesh_from_arrays), py::arg("positions"), py::arg("indices"), py::kw_only(),
           py::arg("normals") = py::none(), py::arg("uvs") = py::none())
      .def_static("uv_sphere", [](float radius, int segments, int rings) { return shared(pbr::uv_sphere(radius, segments, rings)); },
                  py::arg("radius") = 1.0f, py::arg("segments") = 64, py::arg("rings") = 32, "A UV sphere centred at the origin.")
      .def_static("icosphere", [](float radius, int subdivisions) { return shared(pbr::icosphere(radius, subdivisions)); },
                  py::arg("radius") = 1.0f, py::arg("subdivisions") = 3, "A subdivided icosahedron.")
      .def_static("cube", [](float size) { return shared(pbr::cube(size)); }, py::arg("size") = 1.0f,
                  "An axis-aligned cube with flat faces.")
      .def_static("plane", [](float width, float depth, int subdivisions) { return shared(pbr::plane(width, depth, subdivisions)); },
                  py::arg("width") = 1.0f, py::arg("depth") = 1.0f, py::arg("subdivisions") = 1, "A plane in y = 0 facing +y.")
      .def_static("torus", [](float major, float minor, int segments, int sides) { return shared(pbr::torus(major, minor, segments, sides)); },
                  py::arg("major") = 1.0f, py::arg("minor") = 0.25f, py::arg("segments") = 48, py::arg("sides") = 24,
                  "A torus around the y axis.")
      .def_static(
          "load_obj",
          [](const std::filesystem::path& path) {
            require_readable(path);
            py::gil_scoped_release unlocked;
            return shared(pbr::merge_shapes(pbr::load_obj(path, {.textures = false})));
          },
          py::arg("path"),
          "All shapes of an OBJ file as one mesh (materials dropped). OSError if it cannot be read, ValueError "
          "naming the file and line if it is invalid.")
      .def_property_readonly("positions", [](const pbr::Mesh& me) {
        return columns(me, 3, [](const pbr::MeshVertex& v, float* o) { *o++ = v.position.x; *o++ = v.position.y; *o++ = v.position.z; return o; });
      }, "(N, 3) float32 copy of the positions.")
      .def_property_readonly("normals", [](const pbr::Mesh& me) {
        return columns(me, 3, [](const pbr::MeshVertex& v, float* o) { *o++ = v.normal.x; *o++ = v.normal.y; *o++ = v.normal.z; return o; });
      }, "(N, 3) float32 copy of the normals.")
      .def_property_readonly("uvs", [](const pbr::Mesh& me) {
        return columns(me, 2, [](const pbr::MeshVertex& v, float* o) { *o++ = v.uv.x; *o++ = v.uv.y; return o; });
      }, "(N, 2) float32 copy of the texture coordinates.")
      .def_property_readonly("indices", [](const pbr::Mesh& me) {
        py::array_t<std::uint32_t> a({static_cast<py::ssize_t>(me.triangle_count()), py::ssize_t{3}});
        std::copy(me.indices.begin(), me.indices.end(), a.mutable_data());
        return a;
      }, "(M, 3) uint32 copy of the triangles' indices.")
      .def_property_readonly("vertex_count", [](const pbr::Mesh& me) { return me.vertices.size(); })
      .def_property_readonly("triangle_count", &pbr::Mesh::triangle_count)
      .def("__repr__", [](const pbr::Mesh& me) {
        return "<softpbr.Mesh " + std::to_string(me.vertices.size()) + " vertices, " + std::to_string(me.triangle_count()) + " triangles>";
      });

  py::class_<pbr::Material>(m, "Material", R"(A metal/roughness material (glTF's model). Values are checked when rendered.)")
      .def(py::init([](Vec3 base_color, float metallic, float roughness, float ao, Vec3 emissive) {
             pbr::Material mat;
             mat.base_color = to_glm(base_color);
             mat.metallic = metallic;
             mat.roughness = roughness;
             mat.ao = ao;
             mat.emissive = to_glm(emissive);
             return mat;
           }),
           py::kw_only(), py::arg("base_color") = Vec3{0.8f, 0.8f, 0.8f}, py::arg("metallic") = 0.0f,
           py::arg("roughness") = 0.5f, py::arg("ao") = 1.0f, py::arg("emissive") = Vec3{0.0f, 0.0f, 0.0f})
      .def_static("preset", &preset_or_error, py::arg("name"),
                  "A named preset (gold, copper, …, see preset_names()); ValueError for an unknown name.")
      .def_static("preset_names", [] {
        std::vector<std::string> names;
        for (const pbr::NamedMaterial& p : pbr::material_presets()) names.emplace_back(p.name);
        return names;
      })
      .def_property("base_color", [](const pbr::Material& x) { return from_glm(x.base_color); },
                    [](pbr::Material& x, Vec3 v) { x.base_color = to_glm(v); }, "Linear RGB (a metal's F0).")
      .def_readwrite("metallic", &pbr::Material::metallic)
      .def_readwrite("roughness", &pbr::Material::roughness, "Perceptual roughness in [0, 1].")
      .def_readwrite("ao", &pbr::Material::ao)
      .def_property("emissive", [](const pbr::Material& x) { return from_glm(x.emissive); },
                    [](pbr::Material& x, Vec3 v) { x.emissive = to_glm(v); })
      .def_readwrite("alpha", &pbr::Material::alpha)
      .def_readwrite("double_sided", &pbr::Material::double_sided)
      .def_readwrite("unlit", &pbr::Material::unlit)
      .def_property_readonly("textured", &pbr::Material::textured)
      .def("__repr__", [](const pbr::Material& x) {
        return "<softpbr.Material base_color=(" + std::to_string(x.base_color.x) + ", " + std::to_string(x.base_color.y) + ", " +
               std::to_string(x.base_color.z) + ") metallic=" + std::to_string(x.metallic) +
               " roughness=" + std::to_string(x.roughness) + ">";
      });

  py::class_<pbr::Light>(m, "Light", R"(A punctual light (glTF KHR_lights_punctual falloff). Build one with
Light.point(), Light.directional() or Light.spot(); cone angles are in degrees.)")
      .def_static("point", [](Vec3 position, Vec3 color, float intensity, float range) {
        pbr::Light l;
        l.type = pbr::LightType::Point;
        l.position = to_glm(position);
        l.color = to_glm(color);
        l.intensity = intensity;
        l.range = range;
        return l;
      }, py::arg("position"), py::kw_only(), py::arg("color") = Vec3{1, 1, 1}, py::arg("intensity") = 1.0f, py::arg("range") = 0.0f)
      .def_static("directional", [](Vec3 direction, Vec3 color, float intensity) {
        pbr::Light l;
        l.type = pbr::LightType::Directional;
        l.direction = to_glm(direction);
        l.color = to_glm(color);
        l.intensity = intensity;
        return l;
      }, py::arg("direction"), py::kw_only(), py::arg("color") = Vec3{1, 1, 1}, py::arg("intensity") = 1.0f)
      .def_static("spot", [](Vec3 position, Vec3 direction, Vec3 color, float intensity, float range, double inner, double outer) {
        pbr::Light l;
        l.type = pbr::LightType::Spot;
        l.position = to_glm(position);
        l.direction = to_glm(direction);
        l.color = to_glm(color);
        l.intensity = intensity;
        l.range = range;
        l.inner_cone = radians(inner);
        l.outer_cone = radians(outer);
        return l;
      }, py::arg("position"), py::arg("direction"), py::kw_only(), py::arg("color") = Vec3{1, 1, 1}, py::arg("intensity") = 1.0f,
         py::arg("range") = 0.0f, py::arg("inner_cone") = 0.0, py::arg("outer_cone") = 45.0)
      .def_property_readonly("type", [](const pbr::Light& l) { return light_type_name(l.type); })
      .def_property("position", [](const pbr::Light& l) { return from_glm(l.position); }, [](pbr::Light& l, Vec3 v) { l.position = to_glm(v); })
      .def_property("direction", [](const pbr::Light& l) { return from_glm(l.direction); }, [](pbr::Light& l, Vec3 v) { l.direction = to_glm(v); })
      .def_property("color", [](const pbr::Light& l) { return from_glm(l.color); }, [](pbr::Light& l, Vec3 v) { l.color = to_glm(v); })
      .def_readwrite("intensity", &pbr::Light::intensity)
      .def_readwrite("range", &pbr::Light::range)
      .def_property_readonly("inner_cone", [](const pbr::Light& l) { return degrees(l.inner_cone); })
      .def_property_readonly("outer_cone", [](const pbr::Light& l) { return degrees(l.outer_cone); })
      .def("__repr__", [](const pbr::Light& l) { return std::string("<softpbr.Light ") + light_type_name(l.type) + ">"; });

  py::class_<pbr::Camera>(m, "Camera", R"(A look-at camera, perspective or orthographic (as a scene file's camera).

Perspective (the default): fov is the vertical field of view in degrees, the aspect ratio
the image's. Orthographic (orthographic=True): rays parallel to target - position, the view
2*xmag x 2*ymag world units (glTF's xmag, ymag); xmag 0 follows the image (ymag x width /
height); near may be 0 and fov is not used. Values are checked when rendered (ValueError).)")
      .def(py::init([](Vec3 position, Vec3 target, Vec3 up, double fov, float near, float far, bool orthographic, float ymag,
                       float xmag) {
             pbr::Camera c;
             c.position = to_glm(position);
             c.target = to_glm(target);
             c.up = to_glm(up);
             c.fovy = radians(fov);
             c.near = near;
             c.far = far;
             c.orthographic = orthographic;
             c.ymag = ymag;
             c.xmag = xmag;
             return c;
           }),
           py::kw_only(), py::arg("position") = Vec3{0, 0, 3}, py::arg("target") = Vec3{0, 0, 0}, py::arg("up") = Vec3{0, 1, 0},
           py::arg("fov") = 45.0, py::arg("near") = 0.1f, py::arg("far") = 100.0f, py::arg("orthographic") = false,
           py::arg("ymag") = 1.0f, py::arg("xmag") = 0.0f)
      .def_property("position", [](const pbr::Camera& c) { return from_glm(c.position); }, [](pbr::Camera& c, Vec3 v) { c.position = to_glm(v); })
      .def_property("target", [](const pbr::Camera& c) { return from_glm(c.target); }, [](pbr::Camera& c, Vec3 v) { c.target = to_glm(v); })
      .def_property("up", [](const pbr::Camera& c) { return from_glm(c.up); }, [](pbr::Camera& c, Vec3 v) { c.up = to_glm(v); })
      .def_property("fov", [](const pbr::Camera& c) { return degrees(c.fovy); }, [](pbr::Camera& c, double f) { c.fovy = radians(f); },
                    "Perspective: the vertical field of view, degrees.")
      .def_readwrite("near", &pbr::Camera::near)
      .def_readwrite("far", &pbr::Camera::far)
      .def_readwrite("orthographic", &pbr::Camera::orthographic, "True: an orthographic projection (ymag, xmag).")
      .def_readwrite("ymag", &pbr::Camera::ymag, "Orthographic: half the view's height in world units (> 0).")
      .def_readwrite("xmag", &pbr::Camera::xmag,
                     "Orthographic: half the view's width in world units; 0 follows the image (ymag x width / height).")
      .def("__repr__", [](const pbr::Camera& c) {
        return std::string("<softpbr.Camera ") + (c.orthographic ? "orthographic ymag=" + std::to_string(c.ymag) +
                                                                       " xmag=" + std::to_string(c.xmag)
                                                                 : "perspective fov=" + std::to_string(degrees(c.fovy))) +
               ">";
      });

  py::class_<pbr::Object>(m, "Object", "One object of a scene: a mesh drawn with a material and a model-to-world transform.")
      .def_property_readonly("mesh", [](const pbr::Object& o) { return std::const_pointer_cast<pbr::Mesh>(o.mesh); })
      .def_readonly("material", &pbr::Object::material)
      .def_property_readonly("transform", [](const pbr::Object& o) { return matrix_to(o.transform); },
                             "4x4 float32 matrix (numpy rows: a point p maps to transform @ [p, 1]).");

  py::class_<PyGltfModel, std::shared_ptr<PyGltfModel>>(m, "GltfModel", R"(A glTF 2.0 model as loaded by softpbr.load_gltf(path).

objects: one Object per mesh primitive per node, with the node's world transform and the
glTF material (textures included); lights: its KHR_lights_punctual lights placed by their
nodes; cameras: its cameras placed by their nodes (perspective or orthographic). Add them to
a Scene: scene.add(o.mesh, o.material, o.transform) for o in model.objects. Scene.load_gltf
is the whole model framed and lit as `softpbr render model.glb` shows it.)")
      .def_property_readonly("objects", [](const PyGltfModel& g) { return g.model.objects; })
      .def_property_readonly("lights", [](const PyGltfModel& g) { return g.model.lights; })
      .def_property_readonly("cameras", [](const PyGltfModel& g) {
        std::vector<pbr::Camera> c;
        for (const pbr::GltfCamera& k : g.model.cameras) c.push_back(k.camera);
        return c;
      }, "The file's cameras, in its order (Scene.load_gltf(path, camera=N) views through camera N).")
      .def_property_readonly("camera_names", [](const PyGltfModel& g) {
        std::vector<std::string> n;
        for (const pbr::GltfCamera& k : g.model.cameras) n.push_back(k.name);
        return n;
      })
      .def_property_readonly("warnings", [](const PyGltfModel& g) { return g.model.warnings; })
      .def_property_readonly("triangles", [](const PyGltfModel& g) { return g.model.triangles; })
      .def_property_readonly("files", [](const PyGltfModel& g) { return g.model.files; },
                             "The external buffers and images read (not the model's own file).")
      .def("__repr__", [](const PyGltfModel& g) {
        return "<softpbr.GltfModel " + std::to_string(g.model.objects.size()) + " objects, " +
               std::to_string(g.model.lights.size()) + " lights, " + std::to_string(g.model.cameras.size()) + " cameras>";
      });
  m.def("load_gltf", &load_gltf_model, py::arg("path"), py::kw_only(), py::arg("scene") = py::none(),
        py::arg("missing_images") = "error", py::arg("variant") = py::none(),
        "Loads a glTF 2.0 model (.gltf, .glb): its objects, lights and cameras (scene: the glTF scene to read, default "
        "the file's; missing_images=\"warn\": an image file that cannot be read leaves its textures out, with a "
        "warning, as --missing-images warn; variant: a KHR_materials_variants variant's name or index, as "
        "--variant). OSError if it cannot be read; ValueError with the file and the JSON "
        "pointer if it is invalid.");

  py::class_<PyEnvironment, std::shared_ptr<PyEnvironment>>(m, "Environment", R"(An HDR environment prefiltered for image-based lighting (docs/design.md, "Image-based lighting").

Environment.studio() is the built-in studio (what `softpbr render model.glb` lights a model
with); Environment.load(path) reads an equirectangular .hdr or .exr (linear radiance, every
value finite and >= 0). Immutable: one Environment may light many scenes, in many threads.
Give it to a scene with Scene.set_environment(env, intensity=…, rotation=…).)")
      .def_static("studio", &studio_environment, "The built-in studio: a grey dome, a darker floor and softboxes (no file).")
      .def_static("load", &load_environment_file, py::arg("path"), py::kw_only(), py::arg("size") = 0, py::arg("samples") = 64,
                  py::arg("cache_dir") = py::none(),
                  "Loads and prefilters an .hdr or .exr (the scene file's /environment/file, size and samples; "
                  "cache_dir as the command's --env-cache). Cached in memory by content: the same file gives the same "
                  "Environment. OSError if unreadable; ValueError naming the file if it is not a valid environment.")
      .def_property_readonly("name", [](const PyEnvironment& e) { return e.map->name(); })
      .def_property_readonly("size", [](const PyEnvironment& e) { return e.map->size(); },
                             "Side of the sharpest octahedral map, texels.")
      .def_property_readonly("bytes", [](const PyEnvironment& e) { return e.map->bytes(); }, "Memory held by its maps.")
      .def("__eq__", [](const PyEnvironment& a, const PyEnvironment& b) { return a.map == b.map; })
      .def("__hash__", [](const PyEnvironment& e) { return std::hash<const void*>()(e.map.get()); })
      .def("__repr__", [](const PyEnvironment& e) {
        return "<softpbr.Environment " + e.map->name() + " " + std::to_string(e.map->size()) + "x" + std::to_string(e.map->size()) + ">";
      });

  py::class_<PyScene, std::shared_ptr<PyScene>>(m, "Scene", R"(A scene: camera, objects, lights, and the render settings of a scene file.

Scene() is empty (default camera, no objects, 1280x720); Scene.load(path) reads a scene file
(docs/scene-format.md), Scene.from_dict(d) the same schema as a dict.)")
      .def(py::init([] { return std::make_shared<PyScene>(); }))
      .def_static(
          "load",
          [](const std::filesystem::path& path) {
            require_readable(path);
            auto s = std::make_shared<PyScene>();
            py::gil_scoped_release unlocked;
            s->file = pbr::load_scene_file(path);
            return s;
          },
          py::arg("path"),
          "Reads a scene file. OSError if it cannot be read; ValueError with the file and JSON pointer if it is invalid.")
      .def_static("load_gltf", &gltf_scene, py::arg("path"), py::kw_only(), py::arg("width") = 1280, py::arg("height") = 720,
                  py::arg("yaw") = 0.0, py::arg("pitch") = static_cast<double>(pbr::kDefaultPitch), py::arg("camera") = py::none(), py::arg("environment") = true,
                  py::arg("missing_images") = "error", py::arg("variant") = py::none(), py::arg("time") = py::none(),
                  py::arg("animation") = py::none(), py::arg("scene") = py::none(),
                  "A glTF 2.0 model (.gltf, .glb) as `softpbr render model.glb` shows it: framed for a width x height "
                  "image, turned by yaw and raised by pitch (degrees; 15 by default, 0 for a level view), or through camera N of the file; lit by the "
                  "built-in studio environment (blurred background) and the file's lights, or with environment=False "
                  "(`--env none`) by the file's lights or the default light rig when it has none; missing_images=\"warn\" "
                  "leaves out a texture whose image file cannot be read, with a warning (`--missing-images warn`); "
                  "variant: the KHR_materials_variants variant to show, by name or index (`--variant`). "
                  "time (seconds) applies the model's animations at that moment, every one or only animation (an "
                  "index or a name) (`--time`, `--animation`). scene: the file's scene to show, an index or a name "
                  "(`--scene`; default its \"scene\", else 0). "
                  "OSError if unreadable, "
                  "ValueError naming the JSON pointer if invalid.")
      .def_static(
          "from_json",
          [](const std::string& text, const std::string& name, const std::filesystem::path& base_dir) {
            auto s = std::make_shared<PyScene>();
            py::gil_scoped_release unlocked;
            s->file = pbr::parse_scene_file(text, name, base_dir);
            return s;
          },
          py::arg("text"), py::arg("name") = "<json>", py::arg("base_dir") = std::filesystem::path("."),
          "A scene from scene-file text; `name` starts error messages, `base_dir` resolves relative paths.")
      .def(
          "add",
          [](PyScene& s, const std::shared_ptr<pbr::Mesh>& mesh, const std::optional<pbr::Material>& material,
             const py::object& transform) {
            if (!mesh) value_error("Scene.add: mesh is None");
            if (s.file.scene.objects.size() >= pbr::kMaxObjects)
              value_error("Scene.add: a scene has at most " + std::to_string(pbr::kMaxObjects) + " objects");
            s.file.scene.objects.push_back({mesh, material.value_or(pbr::Material{}), matrix_from(transform)});
            s.file.triangles += mesh->triangle_count();
            // Its draw, its mesh and a glTF material's textures (softpbr.load_gltf), each mesh and image counted once.
            pbr::count_object_memory(s.file, s.file.scene.objects.back(), s.counted);
          },
          py::arg("mesh"), py::arg("material") = py::none(), py::arg("transform") = py::none(),
          "Adds an object: `mesh` with `material` (default: grey, roughness 0.5) placed by `transform` (4x4, default identity); "
          "its memory (and a glTF material's textures) counts toward the render's estimate.")
      .def("add_light", [](PyScene& s, const pbr::Light& l) {
        if (s.file.scene.lights.size() >= pbr::kMaxLights)
          value_error("Scene.add_light: a scene has at most " + std::to_string(pbr::kMaxLights) + " lights");
        s.file.scene.lights.push_back(l);
      }, py::arg("light"))
      .def_property_readonly("objects", [](const PyScene& s) { return s.file.scene.objects; })
      .def_property("lights", [](const PyScene& s) { return s.file.scene.lights; },
                    [](PyScene& s, const std::vector<pbr::Light>& l) {
                      if (l.size() > pbr::kMaxLights) value_error("Scene.lights: at most " + std::to_string(pbr::kMaxLights) + " lights");
                      s.file.scene.lights = l;
                    })
      .def_property("camera", [](const PyScene& s) { return s.file.scene.camera; },
                    [](PyScene& s, const pbr::Camera& c) { s.file.scene.camera = c; })
      .def_property("ambient", [](const PyScene& s) { return from_glm(s.file.scene.ambient); },
                    [](PyScene& s, Vec3 v) { s.file.scene.ambient = to_glm(v); })
      .def_property("background", [](const PyScene& s) {
        const glm::vec4& b = s.file.scene.background;
        return std::array<float, 4>{b.r, b.g, b.b, b.a};
      }, [](PyScene& s, std::array<float, 4> v) { s.file.scene.background = {v[0], v[1], v[2], v[3]}; }, "Linear RGBA clear colour.")
      .def_property("width", [](PyScene& s) { return settings(s).width; }, [](PyScene& s, int v) { settings(s).width = v; })
      .def_property("height", [](PyScene& s) { return settings(s).height; }, [](PyScene& s, int v) { settings(s).height = v; })
      .def_property("tonemap", [](PyScene& s) { return std::string(pbr::tone_map_name(settings(s).output.tone_map)); },
                    [](PyScene& s, const std::string& name) {
                      const auto op = pbr::tone_map_from_name(name);
                      if (!op) value_error("tonemap: expected one of none, reinhard, aces, neutral, got \"" + name + "\"");
                      settings(s).output.tone_map = *op;
                    })
      .def_property("exposure", [](PyScene& s) { return settings(s).output.exposure; },
                    [](PyScene& s, float v) { settings(s).output.exposure = v; })
      .def_property("gamma", [](PyScene& s) { return settings(s).output.gamma; }, [](PyScene& s, float v) { settings(s).output.gamma = v; },
                    "0: the exact sRGB curve; > 0: a power law.")
      .def_property("threads", [](PyScene& s) { return settings(s).threads; }, [](PyScene& s, unsigned v) { settings(s).threads = v; })
      .def_property("tile_size", [](PyScene& s) { return settings(s).tile_size; }, [](PyScene& s, int v) { settings(s).tile_size = v; })
      .def("set_environment", &set_environment, py::arg("environment"), py::kw_only(), py::arg("intensity") = py::none(),
           py::arg("rotation") = py::none(), py::arg("background") = py::none(), py::arg("blur") = py::none(),
           py::arg("multiscatter") = py::none(), py::arg("occlusion") = py::none(),
           R"(Lights the scene with an environment, as a scene file's "environment" section does.

environment: an Environment, "studio" (the built-in one), a path to an .hdr/.exr (loaded with
the default size and samples), or None (no image-based lighting; the background is the colour).
intensity (in [0, 1e6]) scales its radiance; rotation turns it about +Y, degrees;
background: "environment", "blur" (its radiance at roughness `blur`, in [0, 1]),
"transparent" (alpha 0) or a linear colour (r, g, b); multiscatter: energy compensation;
occlusion: screen-space ambient occlusion of the environment's light (on by default).
An argument left None keeps the scene's value, so on a scene that already has an environment
this is `softpbr render --env … --env-intensity … --env-rotation …`; a scene without one
shows the environment as its background (the file's default).)")
      .def_property_readonly("environment", [](const PyScene& s) -> std::shared_ptr<PyEnvironment> {
        if (!s.file.scene.environment.map) return nullptr;
        return std::make_shared<PyEnvironment>(PyEnvironment{s.file.scene.environment.map});
      }, "The Environment lighting the scene, or None (set it with set_environment).")
      .def_property("environment_intensity", [](const PyScene& s) { return s.file.scene.environment.intensity; },
                    [](PyScene& s, double v) { s.file.scene.environment.intensity = env_number("environment_intensity", v, 0, 1e6); },
                    "Scale of the environment's radiance, [0, 1e6].")
      .def_property("environment_rotation", [](const PyScene& s) { return s.file.scene.environment.rotation; },
                    [](PyScene& s, double v) { s.file.scene.environment.rotation = env_number("environment_rotation", v, -1e6, 1e6); },
                    "Degrees about +Y, counter-clockwise seen from above.")
      .def_property("multiscatter", [](const PyScene& s) { return s.file.scene.environment.multiscatter; },
                    [](PyScene& s, bool v) { s.file.scene.environment.multiscatter = v; },
                    "Multiple-scattering energy compensation of the environment lighting.")
      .def_property("occlusion", [](const PyScene& s) { return s.file.scene.environment.occlusion; },
                    [](PyScene& s, bool v) { s.file.scene.environment.occlusion = v; },
                    "Screen-space ambient occlusion of the environment's light on opaque and masked objects (on by default).")
      .def_property("background_mode", [](const PyScene& s) { return std::string(background_mode_name(s.file.scene.background_mode)); },
                    &set_background_mode,
                    "\"color\" (the background colour), \"environment\" or \"blur\" (both need an environment).")
      .def_property("background_blur", [](const PyScene& s) { return s.file.scene.background_blur; },
                    [](PyScene& s, double v) { s.file.scene.background_blur = env_number("background_blur", v, 0, 1); },
                    "Roughness of the \"blur\" background, [0, 1].")
      .def_property("msaa", [](PyScene& s) { return settings(s).msaa; },
                    [](PyScene& s, int v) {
                      if (!raster::valid_sample_count(v)) value_error("msaa: expected 1, 4 or 8, got " + std::to_string(v));
                      settings(s).msaa = v;
                    }, "Samples a pixel: 1, 4 or 8 (MSAA).")
      .def_property("resolve", [](PyScene& s) { return std::string(pbr::resolve_name(settings(s).output.resolve)); },
                    [](PyScene& s, const std::string& name) {
                      const auto r = pbr::resolve_from_name(name);
                      if (!r) value_error("resolve: expected \"tonemapped\" or \"linear\", got \"" + name + "\"");
                      settings(s).output.resolve = *r;
                    }, "How MSAA samples become a pixel of render(): \"tonemapped\" (the default) or \"linear\".")
      .def_property_readonly("warnings", [](const PyScene& s) { return s.file.warnings; })
      .def_property_readonly("triangles", [](const PyScene& s) { return s.file.triangles; })
      .def("__repr__", [](const PyScene& s) {
        return "<softpbr.Scene " + std::to_string(s.file.scene.objects.size()) + " objects, " +
               std::to_string(s.file.scene.lights.size()) + " lights, " + std::to_string(s.file.render.width) + "x" +
               std::to_string(s.file.render.height) + ">";
      });
}

}  // namespace softpbr::python
