// Inputs that are not regular files — a named pipe (FIFO) with no writer, a character
// device, a folder, a symbolic-link loop — named wherever softpbr reads a file: every
// reader opens through image::read_whole_file (read_file.h), which never waits on one and
// names the true reason. A reader that blocked would hang here: the alarm below ends the
// test binary with a message instead.
#include <doctest/doctest.h>

#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "softpbr/image/load.h"
#include "softpbr/image/read_file.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/gltf_info.h"
#include "softpbr/loaders/obj.h"
#include "softpbr/loaders/scene_file.h"
#include "softpbr/pbr/environment.h"

namespace image = softpbr::image;
namespace pbr = softpbr::pbr;
namespace fs = std::filesystem;

namespace {

// Ends the process if a test blocks for 60 s (a reader waiting on a pipe forever): the
// suite fails at once instead of hanging until ctest's timeout.
struct Deadline {
  Deadline() {
    ::signal(SIGALRM, [](int) {
      constexpr char kMessage[] = "test_hostile_files: a reader blocked for 60 s on a pipe or a device\n";
      [[maybe_unused]] const ssize_t n = ::write(2, kMessage, sizeof kMessage - 1);
      ::_exit(3);
    });
    ::alarm(60);
  }
  ~Deadline() { ::alarm(0); }
};

// Each test case works in an empty folder of its own, named after the case: ctest runs
// the cases as separate processes in parallel, and a folder shared between them was
// emptied by one case while another wrote into it ("cannot remove: Directory not empty").
fs::path g_case_folder;

struct CaseFolder {
  explicit CaseFolder(const std::string& name) {
    g_case_folder = fs::path(SOFTPBR_BINARY_DIR) / "test_hostile_files" / name;
    fs::remove_all(g_case_folder);
    fs::create_directories(g_case_folder);
  }
  ~CaseFolder() { g_case_folder.clear(); }
};

fs::path folder() {
  REQUIRE_MESSAGE(!g_case_folder.empty(), "a test case of test_hostile_files made no CaseFolder");
  return g_case_folder;
}

fs::path fifo(const std::string& name) {
  const fs::path p = folder() / name;
  fs::remove(p);
  REQUIRE(::mkfifo(p.c_str(), 0644) == 0);
  return p;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no error";
}

// A triangle glTF whose buffer is `buffer_uri`, with a base colour texture of image
// `image_uri` when not empty.
std::string triangle_gltf(const std::string& buffer_uri, const std::string& image_uri = "") {
  std::string j = R"({"asset": {"version": "2.0"}, "buffers": [{"uri": ")" + buffer_uri + R"(", "byteLength": 36}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0})";
  if (!image_uri.empty()) j += R"(, "material": 0)";
  j += R"(}]}], "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0)";
  if (!image_uri.empty())
    j += R"(, "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}], "textures": [{"source": 0}],
      "images": [{"uri": ")" + image_uri + R"("}])";
  return j + "}";
}

void write(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

void write_triangle_bin(const fs::path& path) {
  const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(xyz), sizeof xyz);
}

const std::string kFifo = ": is a named pipe (FIFO), not a regular file";

}  // namespace

TEST_CASE("read_whole_file names what a path is when it is not a regular file, without waiting on a pipe") {
  const CaseFolder here("read_whole_file_kinds");
  const Deadline deadline;
  std::vector<std::uint8_t> bytes;
  const fs::path pipe = fifo("pipe.bin");
  CHECK(image::read_whole_file(pipe, 1 << 20, bytes).reason == "is a named pipe (FIFO), not a regular file");
  CHECK(image::read_whole_file("/dev/null", 1 << 20, bytes).reason == "is a character device, not a regular file");
  const image::FileProblem dir = image::read_whole_file(folder(), 1 << 20, bytes);
  CHECK(dir.folder);
  CHECK(dir.reason == "is a folder");
  const fs::path loop = folder() / "loop";
  fs::remove(loop);
  fs::create_symlink("loop", loop);
  const image::FileProblem looped = image::read_whole_file(loop, 1 << 20, bytes);
  CHECK(looped.error == ELOOP);
  CHECK(looped.reason == "too many levels of symbolic links (a link loop)");
  CHECK(image::read_whole_file(folder() / "missing", 1 << 20, bytes).reason == "no such file");
  // The size limit before a byte is read; a regular file within it is read whole.
  write(folder() / "ten.bin", "0123456789");
  const image::FileProblem big = image::read_whole_file(folder() / "ten.bin", 9, bytes);
  CHECK(big.too_large);
  CHECK(big.reason == "10 bytes, over the limit of 9");
  CHECK(!image::read_whole_file(folder() / "ten.bin", 10, bytes));
  CHECK(bytes.size() == 10);
  // A pipe, where a caller allows one (the command's scene file): a FIFO with no writer
  // reads as empty at once.
  std::string text = "x";
  const image::FileProblem piped = image::read_whole_file(pipe, 1 << 20, text, image::Pipes::Read);
  CHECK(!piped);
  CHECK(piped.pipe);
  CHECK(text.empty());
  // file_problem: the same answers, nothing read.
  CHECK(image::file_problem(pipe).reason == "is a named pipe (FIFO), not a regular file");
  CHECK(!image::file_problem(folder() / "ten.bin"));
}

TEST_CASE("every reader refuses a named pipe with no writer at once, naming it and the reason") {
  const CaseFolder here("readers_refuse_fifo");
  const Deadline deadline;
  const fs::path png = fifo("pipe.png"), hdr = fifo("pipe.hdr"), obj = fifo("pipe.obj"), glb = fifo("pipe.glb");
  const fs::path json = fifo("pipe.json"), bin = fifo("pipe.bin");
  CHECK(error_of([&] { image::load_png(png); }) == png.string() + kFifo);
  CHECK(error_of([&] { image::load_image8(png); }) == png.string() + kFifo);
  CHECK(error_of([&] { image::load_hdr(hdr); }) == hdr.string() + kFifo);
  CHECK(error_of([&] { pbr::load_environment(hdr); }).find(hdr.string() + kFifo) != std::string::npos);
  CHECK(error_of([&] { pbr::load_obj(obj); }) == obj.string() + ": cannot open" + kFifo);
  CHECK(error_of([&] { pbr::load_gltf(glb); }) == glb.string() + kFifo);
  CHECK(error_of([&] { pbr::inspect_gltf(glb); }) == glb.string() + kFifo);
  // A scene file may be a pipe (`softpbr render <(generate-scene)`); one with no writer
  // gives nothing, said so at once.
  CHECK(error_of([&] { pbr::load_scene_file(json); }) ==
        json.string() + ": is a pipe that gave nothing (a named pipe with no writer reads as empty)");
  // A glTF buffer that is a pipe: tinygltf's own FileExists opened it (fopen) and waited.
  const fs::path gltf = folder() / "pipe_buffer.gltf";
  write(gltf, triangle_gltf("pipe.bin"));
  const std::string buffer = gltf.string() + ": /buffers/0/uri: " + bin.string() + kFifo;
  CHECK(error_of([&] { pbr::load_gltf(gltf); }) == buffer);
  CHECK(error_of([&] { pbr::inspect_gltf(gltf); }) == buffer);
  CHECK(error_of([&] { pbr::load_and_inspect_gltf(gltf); }) == buffer);
  // A glTF image that is a pipe.
  write_triangle_bin(folder() / "triangle.bin");
  const fs::path textured = folder() / "pipe_image.gltf";
  write(textured, triangle_gltf("triangle.bin", "pipe.png"));
  CHECK(error_of([&] { pbr::load_gltf(textured); }) == textured.string() + ": /images/0/uri: " + png.string() + kFifo);
  // An OBJ's MTL and an MTL's texture that are pipes.
  write(folder() / "mtl.obj", "mtllib pipe.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const fs::path mtl = fifo("pipe.mtl");
  // (an MTL file that cannot be read is a warning, as a missing one)
  const pbr::ObjModel model = pbr::load_obj(folder() / "mtl.obj");
  CHECK(std::count(model.warnings.begin(), model.warnings.end(), mtl.string() + ": cannot open" + kFifo) == 1);
  write(folder() / "tex.mtl", "newmtl m\nmap_Kd pipe.png\n");
  write(folder() / "tex.obj", "mtllib tex.mtl\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n");
  const std::string texture = error_of([&] { pbr::load_obj(folder() / "tex.obj"); });
  CAPTURE(texture);
  CHECK(texture.find(png.string() + kFifo) != std::string::npos);
}

TEST_CASE("a glTF buffer that cannot be read is one line with its pointer, not tinygltf's \"File read error\"") {
  const CaseFolder here("unreadable_buffer");
  const Deadline deadline;
  const fs::path gltf = folder() / "folder_buffer.gltf";
  fs::create_directories(folder() / "a_folder.bin");
  write(gltf, triangle_gltf("a_folder.bin"));
  const std::string expected = gltf.string() + ": /buffers/0/uri: " + (folder() / "a_folder.bin").string() + ": is a folder";
  CHECK(error_of([&] { pbr::load_gltf(gltf); }) == expected);
  CHECK(error_of([&] { pbr::inspect_gltf(gltf); }) == expected);
  const fs::path loop = folder() / "loop.bin";
  fs::remove(loop);
  fs::create_symlink("loop.bin", loop);
  write(gltf, triangle_gltf("loop.bin"));
  CHECK(error_of([&] { pbr::load_gltf(gltf); }) ==
        gltf.string() + ": /buffers/0/uri: " + loop.string() + ": too many levels of symbolic links (a link loop)");
  // A .glb or .gltf that is a link loop: the loop, not "no such file".
  const fs::path glb = folder() / "loop.glb";
  fs::remove(glb);
  fs::create_symlink("loop.glb", glb);
  CHECK(error_of([&] { pbr::load_gltf(glb); }) == glb.string() + ": too many levels of symbolic links (a link loop)");
  CHECK(error_of([&] { pbr::inspect_gltf(glb); }) == glb.string() + ": too many levels of symbolic links (a link loop)");
}

TEST_CASE("a long data URI tinygltf cannot use is quoted to 40 bytes with its pointer") {
  const CaseFolder here("long_data_uri");
  const fs::path gltf = folder() / "data_uri.gltf";
  // Valid base64 of 1500 bytes for a buffer of 36: tinygltf quoted all 2 kB.
  const std::string uri = "data:application/octet-stream;base64," + std::string(2000, 'A');
  write(gltf, triangle_gltf(uri));
  CHECK(error_of([&] { pbr::load_gltf(gltf); }) ==
        gltf.string() + ": /buffers/0/uri: the data URI \"" + uri.substr(0, 40) + "…\" (" + std::to_string(uri.size()) +
            " bytes) does not decode to the buffer's byteLength bytes");
  // A 2 kB file name that is not there.
  const std::string name = std::string(2000, 'x') + ".bin";
  write(gltf, triangle_gltf(name));
  CHECK(error_of([&] { pbr::load_gltf(gltf); }) == gltf.string() + ": /buffers/0/uri: " + name.substr(0, 40) + "…: no such file");
  // A percent-encoded name: tinygltf names the decoded file, still found with its pointer.
  write(gltf, triangle_gltf("a%20" + std::string(100, 'z') + ".bin"));
  CHECK(error_of([&] { pbr::load_gltf(gltf); }) ==
        gltf.string() + ": /buffers/0/uri: " + ("a " + std::string(100, 'z')).substr(0, 40) + "…: no such file");
  // An image file of a 200-byte name that is not an image: the URI quoted to 40 bytes.
  const std::string image_name = std::string(200, 'y') + ".png";
  write(folder() / image_name, "not an image");
  write_triangle_bin(folder() / "triangle.bin");
  write(gltf, triangle_gltf("triangle.bin", image_name));
  const std::string bad = error_of([&] { pbr::load_gltf(gltf); });
  CAPTURE(bad);
  CHECK(bad.rfind(gltf.string() + ": /images/0 (" + image_name.substr(0, 40) + "…): ", 0) == 0);
  CHECK(bad.size() < gltf.string().size() + 200);
}

TEST_CASE("MissingImages::Warn leaves out a texture whose file cannot be read, with a warning, and Error refuses the model") {
  const CaseFolder here("missing_images");
  const Deadline deadline;
  write_triangle_bin(folder() / "triangle.bin");
  const fs::path gltf = folder() / "gone_image.gltf";
  write(gltf, triangle_gltf("triangle.bin", "gone.png"));
  const std::string gone = (folder() / "gone.png").string();
  CHECK(error_of([&] { pbr::load_gltf(gltf); }) == gltf.string() + ": /images/0/uri: " + gone + ": no such file");
  const pbr::GltfScene g = pbr::load_gltf(gltf, {.missing_images = pbr::MissingImages::Warn});
  REQUIRE(g.objects.size() == 1);
  CHECK(g.objects[0].material.base_color_texture.texture == nullptr);
  CHECK(std::count(g.warnings.begin(), g.warnings.end(),
                   gltf.string() + ": /images/0/uri: " + gone + ": no such file (a missing image: its textures are left out)") == 1);
  // A named pipe is such a file too; a file outside the roots stays an error.
  fifo("pipe.png");
  write(gltf, triangle_gltf("triangle.bin", "pipe.png"));
  CHECK_NOTHROW(pbr::load_gltf(gltf, {.missing_images = pbr::MissingImages::Warn}));
  write(gltf, triangle_gltf("triangle.bin", "../outside.png"));
  CHECK(error_of([&] { pbr::load_gltf(gltf, {.roots = {folder()}, .missing_images = pbr::MissingImages::Warn}); })
            .find("outside the folders") != std::string::npos);
  // An OBJ whose MTL names a missing map.
  write(folder() / "gone.mtl", "newmtl m\nKd 0.5 0.2 0.1\nmap_Kd gone.png\n");
  write(folder() / "gone.obj", "mtllib gone.mtl\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n");
  const std::string mtl = (folder() / "gone.mtl").string();
  CHECK(error_of([&] { pbr::load_obj(folder() / "gone.obj"); }) == mtl + ":3: map_Kd: " + gone + ": no such file");
  const pbr::ObjModel o = pbr::load_obj(folder() / "gone.obj", {.missing_images = pbr::MissingImages::Warn});
  REQUIRE(o.materials.size() == 1);
  CHECK(o.materials[0].second.base_color_texture.texture == nullptr);
  CHECK(o.materials[0].second.base_color.r == doctest::Approx(0.5f));
  CHECK(std::count(o.warnings.begin(), o.warnings.end(),
                   mtl + ":3: map_Kd: " + gone + ": no such file (a missing image: the map is left out)") == 1);
}
