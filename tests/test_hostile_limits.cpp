// Limits: absurd sizes and counts are a clear error (or a bounded result), never an
// out-of-memory kill or a hang. Each case is decided before any large
// allocation or any read of the claimed data.
#include <doctest/doctest.h>

#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <climits>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>

#include "softpbr/loaders/obj.h"
#include "softpbr/pbr/gallery.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/raster/raster.h"

namespace raster = softpbr::raster;
namespace pbr = softpbr::pbr;

namespace {

// `bytes` of address space that may not be touched (PROT_NONE): a span over it that the
// renderer read from would crash the test, so a clean exception proves nothing was read.
class Untouchable {
 public:
  explicit Untouchable(std::size_t bytes) : bytes_(bytes) {
    void* p = ::mmap(nullptr, bytes, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    REQUIRE(p != MAP_FAILED);
    data_ = p;
  }
  ~Untouchable() { ::munmap(data_, bytes_); }
  Untouchable(const Untouchable&) = delete;
  Untouchable& operator=(const Untouchable&) = delete;
  template <class T>
  std::span<const T> as(std::size_t count) const {
    REQUIRE(count * sizeof(T) <= bytes_);
    return {static_cast<const T*>(data_), count};
  }

 private:
  std::size_t bytes_;
  void* data_;
};

struct PositionShader {
  using Vertex = glm::vec4;
  struct Varyings {};
  glm::vec4 vertex(const Vertex& in, Varyings&) const { return in; }
  glm::vec4 fragment(const raster::Fragment<Varyings>&) const { return {1, 1, 1, 1}; }
};

std::filesystem::path scratch_dir() {
  const auto dir = std::filesystem::path(SOFTPBR_BINARY_DIR) / "test_hostile_limits";
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace

TEST_CASE("targets outside 1x1 .. kMaxTargetSize are refused before allocating, naming the size") {
  struct Case {
    int width, height;
    const char* shown;
  };
  const Case cases[] = {{100000, 100000, "100000x100000"},
                        {raster::kMaxTargetSize + 1, 1, "16385x1"},
                        {1, raster::kMaxTargetSize + 1, "1x16385"},
                        {0, 1, "0x1"},
                        {-1, -1, "-1x-1"},
                        {INT_MAX, INT_MAX, "2147483647x2147483647"},
                        {INT_MIN, 16, "-2147483648x16"}};
  for (const Case& c : cases) {
    CAPTURE(c.shown);
    try {
      raster::Target target(c.width, c.height);
      FAIL("no exception");
    } catch (const std::invalid_argument& e) {
      CHECK(std::string(e.what()).find(c.shown) != std::string::npos);
    }
  }
}

TEST_CASE("tile sizes that are odd or outside [kMinTileSize, kMaxTileSize] are refused, and valid_tile_size says so") {
  for (const int tile : {0, -8, 7, 9, raster::kMinTileSize - 2, raster::kMaxTileSize + 2, INT_MAX, INT_MIN}) {
    CAPTURE(tile);
    CHECK_THROWS_AS(raster::Renderer({.threads = 1, .tile_size = tile}), std::invalid_argument);
    CHECK_FALSE(raster::valid_tile_size(tile));
  }
  // valid_tile_size (which the scene loader and the command line check with) accepts
  // exactly what the Renderer accepts.
  for (const int tile : {raster::kMinTileSize, raster::kMinTileSize + 2, 64, 66, raster::kMaxTileSize}) {
    CAPTURE(tile);
    CHECK(raster::valid_tile_size(tile));
    CHECK_NOTHROW(raster::Renderer({.threads = 1, .tile_size = tile}));
  }
  static_assert(raster::valid_tile_size(64) && !raster::valid_tile_size(65));
}

TEST_CASE("a draw claiming 2^31 or more indices is refused without reading them, and the frame goes on") {
  // 2^31 indices are 8 GiB; 3·2^30 + 3 are 12 GiB and one triangle past the 2^30 limit.
  const std::size_t counts[] = {std::size_t{1} << 31, 3 * ((std::size_t{1} << 30) + 1)};
  const Untouchable memory(counts[1] * sizeof(std::uint32_t));
  const std::vector<glm::vec4> vertices(3, glm::vec4(0, 0, 0, 1));
  raster::Renderer renderer({.threads = 2});
  raster::Target target(8, 8);
  renderer.begin_frame(target, raster::ClearValues{{0, 0, 0, 1}, 1.0f});
  for (const std::size_t count : counts) {
    CAPTURE(count);
    CHECK_THROWS_AS(renderer.draw(PositionShader{}, std::span<const glm::vec4>(vertices),
                                  memory.as<std::uint32_t>(count)),
                    std::logic_error);  // invalid_argument (not whole triangles) or length_error
  }
  renderer.end_frame();
  CHECK(target.color(3, 3) == glm::vec4(0, 0, 0, 1));
}

TEST_CASE("a non-indexed draw claiming 2^32 vertices is refused without reading them") {
  const std::size_t count = std::size_t{1} << 32;  // 64 GiB of vec4
  const Untouchable memory(count * sizeof(glm::vec4));
  raster::Renderer renderer({.threads = 1});
  raster::Target target(4, 4);
  renderer.begin_frame(target);
  CHECK_THROWS_AS(renderer.draw(PositionShader{}, memory.as<glm::vec4>(count)), std::length_error);
  renderer.end_frame();
}

TEST_CASE("OBJ indices beyond 2^31 are a located error, not a huge allocation") {
  const auto path = scratch_dir() / "huge_index.obj";
  // −2^63 too: its negation overflows (UBSan found it where the range check negated it).
  for (const char* index : {"2147483648", "4294967296", "-2147483649", "99999999999999999999999",
                            "-9223372036854775808", "9223372036854775807"}) {
    CAPTURE(index);
    std::ofstream(path) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 " << index << "\n";
    try {
      pbr::load_obj(path);
      FAIL("no exception");
    } catch (const pbr::LoadError& e) {
      CHECK(std::string(e.what()).rfind(path.string() + ":4: ", 0) == 0);
    }
  }
}

TEST_CASE("a million lights through the API is a bounded render with finite pixels") {
  // Cost is pixels × lights: a 2×2 target keeps it to 4·10⁶ light evaluations. (Scene
  // files cap the light count; the API leaves that to the caller.)
  pbr::GalleryOptions options;
  options.rows = {"gold"};
  options.columns = 1;
  options.segments = 8;
  pbr::Scene scene = pbr::make_gallery(options);
  scene.camera.position = {0.0f, 0.0f, 1.0f};  // the one sphere fills the view
  pbr::Light light;
  light.position = {0.0f, 0.0f, 5.0f};
  light.intensity = 1e-6f;
  scene.lights.assign(1'000'000, light);
  raster::Renderer renderer({.threads = 2});
  raster::Target target(2, 2);
  pbr::render(scene, renderer, target);
  for (const glm::vec4& c : target.colors()) {
    CHECK(std::isfinite(c.r));
    CHECK(c.r > scene.ambient.r * 0.5f);  // lit by the lights, not only ambient
  }
}

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define SOFTPBR_TEST_UNDER_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define SOFTPBR_TEST_UNDER_SANITIZER 1
#endif
#endif

namespace {
// In a child process whose address space leaves room for only a few thread stacks, a pool
// of `threads` is built and used: 0 when it started fewer threads than asked, ran every
// index exactly once and shut down; 1 when a check failed. A hang is killed by alarm().
int pool_under_address_limit(unsigned threads) {
  alarm(30);
  long pages = 0;
  {
    std::ifstream statm("/proc/self/statm");
    statm >> pages;
  }
  if (pages <= 0) return 1;
  // What the process maps now plus 48 MiB: a few 8 MiB thread stacks, then EAGAIN.
  const rlim_t limit = static_cast<rlim_t>(pages) * static_cast<rlim_t>(sysconf(_SC_PAGESIZE)) + (rlim_t{48} << 20);
  const rlimit r{limit, limit};
  if (setrlimit(RLIMIT_AS, &r) != 0) return 1;
  std::atomic<int> sum{0};
  {
    softpbr::raster::ThreadPool pool(threads);
    if (pool.requested() != threads || pool.size() >= threads || pool.size() < 1) return 1;
    pool.parallel_for(1000, [&](std::size_t i) { sum.fetch_add(static_cast<int>(i) + 1, std::memory_order_relaxed); });
  }
  return sum.load() == 1000 * 1001 / 2 ? 0 : 1;
}
}  // namespace

TEST_CASE("a thread pool the system refuses threads to runs with those it started: no hang, every index run once") {
#if defined(SOFTPBR_TEST_UNDER_SANITIZER)
  MESSAGE("skipped: sanitizers reserve address space beyond any useful limit");
#else
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) _exit(pool_under_address_limit(256));
  int status = 0;
  REQUIRE(waitpid(child, &status, 0) == child);
  CHECK(WIFEXITED(status));  // not killed by the 30 s alarm (a hang) or a crash
  CHECK(WEXITSTATUS(status) == 0);
#endif
}

TEST_CASE("an OBJ face of more than 4096 vertices is a located error, not minutes of ear clipping") {
  const auto path = scratch_dir() / "huge_face.obj";
  {
    std::ofstream out(path);
    for (int i = 0; i < 5000; ++i) out << "v " << i << " " << (i % 2) << " 0\n";
    out << "f";
    for (int i = 1; i <= 5000; ++i) out << " " << i;
    out << "\n";
  }
  CHECK_THROWS_WITH(pbr::load_obj(path), (path.string() + ":5001: a face of 5000 vertices (the limit is 4096: polygons are "
                                                           "triangulated by ear clipping, quadratic in their size)").c_str());
}

TEST_CASE("MTL values that are not finite numbers are located errors, not zeros read in silence") {
  const auto dir = scratch_dir();
  std::ofstream(dir / "hostile_mtl.obj") << "mtllib hostile.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n";
  const auto mtl = dir / "hostile.mtl";
  struct Case {
    const char* line;
    const char* error;
  };
  const Case cases[] = {
      {"Kd 0.5 banana 0.5", ":2: Kd value 'banana' is not a number"},
      {"Ns inf", ":2: Ns value 'inf' is not a finite number"},
      {"Ke nan 0 0", ":2: Ke value 'nan' is not a finite number"},
      {"Ke 1e40 0 0", ":2: Ke value '1e40' is beyond the float range"},
      {"Pr 0.5x", ":2: Pr value '0.5x' is not a number"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.line);
    std::ofstream(mtl) << "newmtl m\n" << c.line << "\n";
    CHECK_THROWS_WITH(pbr::load_obj(dir / "hostile_mtl.obj"), (mtl.string() + c.error).c_str());
  }
  // Valid forms still load: one or three values, a comment, d -halo.
  std::ofstream(mtl) << "newmtl m\nKd 0.5 # grey\nKs 1 1 1\nd -halo 0.5\nNs 10\nillum 2\n";
  CHECK(pbr::load_obj(dir / "hostile_mtl.obj").materials.size() == 1);
}

TEST_CASE("an OBJ whose parse would pass the memory limit is refused after the counting pass, before tinyobjloader") {
  const auto path = scratch_dir() / "bounded.obj";
  {
    std::ofstream out(path);
    for (int i = 0; i < 1000; ++i) out << "v " << i << " " << (i % 3) << " 0\n";
    for (int i = 1; i + 2 <= 1000; ++i) out << "f " << i << " " << i + 1 << " " << i + 2 << "\n";
  }
  pbr::ObjOptions options;
  options.memory_limit = 100000;  // the estimate: the text, 12 bytes a position, 100 a corner (~310 KB)
  try {
    pbr::load_obj(path, options);
    FAIL("no exception");
  } catch (const pbr::LoadError& e) {
    const std::string what = e.what();
    CHECK(what.rfind(path.string() + ": parsing it needs an estimated ", 0) == 0);
    CHECK(what.ends_with(", over the memory limit of 97.7 KiB"));
  }
  options.memory_limit = 1 << 20;
  CHECK(pbr::load_obj(path, options).shapes.size() == 1);
}
