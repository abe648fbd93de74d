// The softpbr._softpbr extension module: render, scenes, meshes, materials, lights and
// cameras, image comparison. The softpbr package (python/softpbr/__init__.py) re-exports it.
#include <cerrno>

#include "bindings.h"
#include "softpbr/image/read_file.h"
#include "softpbr/loaders/obj.h"

namespace softpbr::python {

void require_readable(const std::filesystem::path& path) {
  // Opened without blocking and closed again (read_file.h): a named pipe with no writer
  // raises at once instead of holding the GIL forever.
  const image::FileProblem p = image::file_problem(path);
  if (!p) return;
  if (p.error != 0 || p.folder) {
    errno = p.folder ? EISDIR : p.error;
    PyErr_SetFromErrnoWithFilename(PyExc_OSError, path.string().c_str());
  } else {
    PyErr_SetString(PyExc_OSError, (path.string() + ": " + p.reason).c_str());
  }
  throw py::error_already_set();
}

void value_error(const std::string& what) { throw py::value_error(what); }
void type_error(const std::string& what) { throw py::type_error(what); }

namespace {
template <class Image, class T>
py::array_t<T> owning_array(Image&& image) {
  auto* owner = new Image(std::move(image));
  py::capsule free_when_done(owner, [](void* p) { delete static_cast<Image*>(p); });
  const auto w = static_cast<py::ssize_t>(owner->width), h = static_cast<py::ssize_t>(owner->height);
  const auto s = static_cast<py::ssize_t>(sizeof(T));
  return py::array_t<T>({h, w, py::ssize_t{4}}, {w * 4 * s, 4 * s, s}, owner->rgba.data(), free_when_done);
}

template <class T>
void check_image_array(const py::array& a, const char* what) {
  if (a.ndim() != 3 || a.shape(2) != 4)
    value_error(std::string(what) + ": expected an array of shape (height, width, 4), got " + shape_text(a));
  if (!py::isinstance<py::array_t<T>>(a) || !a.dtype().is(py::dtype::of<T>()))
    type_error(std::string(what) + ": expected dtype " + std::string(py::str(py::dtype::of<T>())) + ", got " +
               std::string(py::str(a.dtype())));
}

template <class Image, class T>
Image copy_image(const py::array& a, const char* what) {
  check_image_array<T>(a, what);
  const auto c = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(a);
  Image image;
  image.height = static_cast<int>(a.shape(0));
  image.width = static_cast<int>(a.shape(1));
  image.rgba.assign(c.data(), c.data() + c.size());
  return image;
}
}  // namespace

py::array_t<std::uint8_t> to_numpy(image::Image8&& image) { return owning_array<image::Image8, std::uint8_t>(std::move(image)); }
py::array_t<float> to_numpy(image::ImageF&& image) { return owning_array<image::ImageF, float>(std::move(image)); }

bool is_float_image(const py::array& a) { return a.dtype().kind() == 'f'; }

image::Image8 image8_from_numpy(const py::array& a, const char* what) {
  return copy_image<image::Image8, std::uint8_t>(a, what);
}
image::ImageF imagef_from_numpy(const py::array& a, const char* what) {
  return copy_image<image::ImageF, float>(a, what);
}

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

}  // namespace softpbr::python

PYBIND11_MODULE(_softpbr, m) {
  namespace py = pybind11;
  m.doc() = "softpbr: bit-exact physically based rendering on the CPU (the compiled part of the softpbr package).";
  // The library's input errors are bad values: ValueError with the library's one-line message.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const softpbr::pbr::SceneFileError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const softpbr::pbr::LoadError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  softpbr::python::bind_scene(m);
  softpbr::python::bind_render(m);
  softpbr::python::bind_golden(m);
  softpbr::python::bind_model_views(m);
}
