// python/src/bindings.h — what the parts of the Python module (softpbr._softpbr) share:
// the Scene wrapper, numpy conversions and the errors they raise (docs/python.md, "Errors":
// ValueError for bad values, TypeError for a wrong dtype, OSError for a file that cannot be
// read).
#pragma once

#include <cstdint>
#include <filesystem>
#include <set>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "softpbr/image/image.h"
#include "softpbr/loaders/scene_file.h"

namespace softpbr::python {

namespace py = pybind11;

// softpbr.Scene: a scene with its render settings and animation, as a scene file gives them.
struct PyScene {
  pbr::SceneFile file;
  std::set<const void*> counted;  // meshes and textures of Scene.add's objects already in the estimate (count_object_memory)
};

void bind_scene(py::module_& m);
void bind_render(py::module_& m);
void bind_golden(py::module_& m);
void bind_model_views(py::module_& m);

// Raises the Python OSError (a FileNotFoundError, PermissionError, IsADirectoryError…)
// for `path` unless it is a regular file that can be opened for reading.
void require_readable(const std::filesystem::path& path);

// Throws a Python ValueError / TypeError with this text.
[[noreturn]] void value_error(const std::string& what);
[[noreturn]] void type_error(const std::string& what);

// An 8-bit image as a numpy uint8 array (height, width, 4) that owns its pixels: moved, not copied.
py::array_t<std::uint8_t> to_numpy(image::Image8&& image);
py::array_t<float> to_numpy(image::ImageF&& image);

// A numpy (height, width, 4) array, uint8 or float32, copied into an image. `what` names
// the argument in errors: "a: expected an array of shape (height, width, 4), got (3, 3)".
bool is_float_image(const py::array& a);
image::Image8 image8_from_numpy(const py::array& a, const char* what);
image::ImageF imagef_from_numpy(const py::array& a, const char* what);

// "(3, 4)" for error messages.
std::string shape_text(const py::array& a);

}  // namespace softpbr::python
