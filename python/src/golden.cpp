// softpbr.compare, diff_image, side_by_side, content_hash, match_golden and image files:
// the golden library (softpbr/golden/) on numpy images. uint8 arrays are 8-bit images
// (differences in code values, PSNR peak 255), float32 arrays float images (peak 1).
#include <optional>
#include <stdexcept>
#include <string>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "bindings.h"
#include "softpbr/golden/compare.h"
#include "softpbr/golden/golden.h"
#include "softpbr/golden/image.h"

namespace softpbr::python {

namespace {

namespace golden = softpbr::golden;

// Calls f(Image8, Image8) or f(ImageF, ImageF) for two arrays of one dtype.
template <class F>
auto with_pair(const py::array& a, const py::array& b, F&& f) {
  if (is_float_image(a) != is_float_image(b))
    type_error("expected two images of one dtype (uint8 or float32), got " + std::string(py::str(a.dtype())) + " and " +
               std::string(py::str(b.dtype())));
  if (is_float_image(a)) {
    const golden::ImageF x = imagef_from_numpy(a, "a"), y = imagef_from_numpy(b, "b");
    py::gil_scoped_release unlocked;
    return f(x, y);
  }
  const golden::Image8 x = image8_from_numpy(a, "a"), y = image8_from_numpy(b, "b");
  py::gil_scoped_release unlocked;
  return f(x, y);
}

// Image decoding errors (std::runtime_error starting with the path) are bad values.
template <class F>
auto image_errors(F&& f) {
  try {
    return f();
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::runtime_error& e) {
    value_error(e.what());
  }
}

bool is_float_path(const std::filesystem::path& p) {
  std::string ext = p.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".hdr" || ext == ".exr";
}

}  // namespace

void bind_golden(py::module_& m) {
  py::class_<golden::Comparison>(m, "Comparison", R"(Difference statistics of two images (softpbr/golden/compare.h), in the
images' units: 8-bit codes for uint8 images, float values for float32 images.)")
      .def_readonly("identical", &golden::Comparison::identical, "Same size and every sample equal.")
      .def_property_readonly("same_size", &golden::Comparison::same_size)
      .def_property_readonly("max", &golden::Comparison::max_diff, "Largest |a - b| of any sample.")
      .def_readonly("max_per_channel", &golden::Comparison::max_abs_diff, "Largest |a - b| per channel R, G, B, A.")
      .def_readonly("mean", &golden::Comparison::mean_abs_diff_all, "Mean |a - b| over every sample.")
      .def_readonly("mean_per_channel", &golden::Comparison::mean_abs_diff)
      .def_readonly("rmse", &golden::Comparison::rmse)
      .def_readonly("psnr", &golden::Comparison::psnr, "dB; inf when identical.")
      .def_readonly("peak", &golden::Comparison::peak, "255 (uint8) or 1 (float32).")
      .def_readonly("threshold", &golden::Comparison::threshold)
      .def_readonly("pixels", &golden::Comparison::pixels)
      .def_readonly("pixels_above", &golden::Comparison::pixels_above, "Pixels whose largest channel difference is over the threshold.")
      .def_readonly("fraction_above", &golden::Comparison::fraction_above)
      .def_property_readonly("expected_size", [](const golden::Comparison& c) { return std::pair(c.expected_width, c.expected_height); })
      .def_property_readonly("actual_size", [](const golden::Comparison& c) { return std::pair(c.actual_width, c.actual_height); })
      .def("describe", &golden::Comparison::describe, "One paragraph with every statistic.")
      .def("__str__", &golden::Comparison::describe)
      .def("__repr__", [](const golden::Comparison& c) { return "<softpbr.Comparison " + c.describe() + ">"; });

  m.def("compare",
        [](const py::array& a, const py::array& b, double max_diff) {
          return with_pair(a, b, [&](const auto& x, const auto& y) { return golden::compare(x, y, max_diff); });
        },
        py::arg("a"), py::arg("b"), py::arg("max_diff") = 0.0,
        "Statistics of b (actual) against a (expected): max, mean, RMSE, PSNR, pixels over max_diff.");
  m.def("diff_image",
        [](const py::array& a, const py::array& b, double scale) {
          return to_numpy(with_pair(a, b, [&](const auto& x, const auto& y) { return golden::diff_image(x, y, scale); }));
        },
        py::arg("a"), py::arg("b"), py::arg("scale") = 0.0,
        "A heat map of |a - b| (black equal, red → yellow → white); scale 0: the largest difference shows white.");
  m.def("side_by_side",
        [](const py::array& a, const py::array& b, double scale) {
          return to_numpy(with_pair(a, b, [&](const auto& x, const auto& y) { return golden::side_by_side(x, y, scale); }));
        },
        py::arg("a"), py::arg("b"), py::arg("scale") = 0.0, "a | b | diff_image(a, b), left to right, as uint8.");
  m.def("content_hash",
        [](const py::array& a) {
          return is_float_image(a) ? golden::content_hash(imagef_from_numpy(a, "image"))
                                   : golden::content_hash(image8_from_numpy(a, "image"));
        },
        py::arg("image"), "The documented 64-bit FNV-1a hash of the image's size and samples (softpbr/golden/compare.h).");

  m.def("load_image",
        [](const std::filesystem::path& path) -> py::array {
          require_readable(path);
          if (is_float_path(path)) {
            golden::ImageF image = image_errors([&] {
              py::gil_scoped_release unlocked;
              return image::load_imagef(path);
            });
            return to_numpy(std::move(image));
          }
          golden::Image8 image = image_errors([&] {
            py::gil_scoped_release unlocked;
            return image::load_image8(path);
          });
          return to_numpy(std::move(image));
        },
        py::arg("path"), "PNG or JPEG → uint8 (H, W, 4); .hdr or .exr → float32. OSError if unreadable, ValueError if invalid.");
  m.def("write_png",
        [](const std::filesystem::path& path, const py::array& a) {
          const golden::Image8 image = image8_from_numpy(a, "image");
          image_errors([&] {
            py::gil_scoped_release unlocked;
            image::write_png(path, image);
            return 0;
          });
        },
        py::arg("path"), py::arg("image"), "Writes a uint8 (H, W, 4) image as PNG, atomically.");
  m.def("write_hdr",
        [](const std::filesystem::path& path, const py::array& a, bool exr) {
          const golden::ImageF image = imagef_from_numpy(a, "image");
          image_errors([&] {
            py::gil_scoped_release unlocked;
            exr ? image::write_exr(path, image) : image::write_hdr(path, image);
            return 0;
          });
        },
        py::arg("path"), py::arg("image"), py::arg("exr") = false,
        "Writes a float32 (H, W, 4) image as Radiance .hdr (or OpenEXR with exr=True), atomically.");

  py::class_<golden::MatchResult>(m, "MatchResult", "The outcome of match_golden.")
      .def_readonly("passed", &golden::MatchResult::passed)
      .def_readonly("updated", &golden::MatchResult::updated, "Update mode rewrote the golden.")
      .def_readonly("golden", &golden::MatchResult::golden)
      .def_readonly("comparison", &golden::MatchResult::comparison)
      .def_readonly("written", &golden::MatchResult::written, "Failure images written: actual, diff, side by side.")
      .def_readonly("message", &golden::MatchResult::message);
  m.def("match_golden",
        [](const py::array& a, const std::filesystem::path& golden_path, double max_diff, std::uint64_t max_pixels,
           const std::filesystem::path& output_dir, bool update, const std::string& update_command) {
          golden::Options options;
          options.output_dir = output_dir;
          options.update = update;
          options.update_command = update_command;
          const golden::Tolerance tolerance{max_diff, max_pixels};
          if (is_float_image(a)) {
            const golden::ImageF image = imagef_from_numpy(a, "image");
            py::gil_scoped_release unlocked;
            return golden::match_golden(image, golden_path, tolerance, options);
          }
          const golden::Image8 image = image8_from_numpy(a, "image");
          py::gil_scoped_release unlocked;
          return golden::match_golden(image, golden_path, tolerance, options);
        },
        py::arg("image"), py::arg("golden"), py::kw_only(), py::arg("max_diff") = 0.0, py::arg("max_pixels") = 0,
        py::arg("output_dir") = std::filesystem::path(), py::arg("update") = false,
        py::arg("update_command") = std::string("pytest --softpbr-update-goldens"),
        "golden::match_golden: checks an image against a .png (uint8) or .hdr (float32) golden; see softpbr.testing.");
}

}  // namespace softpbr::python
